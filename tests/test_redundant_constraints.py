"""Dependent constraint rows are dropped with a warning (lagcli/model/redundancy.py).

Two wheels on one axle, each a `rolling:` element: both forbid the axle's sideways
slip, so one of the two sideways rows repeats the other. Kept, `check` said DOF 1
(the true count is 2: the speeds of the two wheels) and `simulate` failed at t = 0
with a singular matrix. The warning itself is a case of the warning corpus
(tests/data/warn/two_wheels_one_axle_rolling.yaml)."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

import lagcli

AXLE = Path(__file__).parent / "data" / "warn" / "two_wheels_one_axle_rolling.yaml"


def _load():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return lagcli.load(AXLE)


def test_two_wheels_on_one_axle_have_two_degrees_of_freedom():
    d = _load().derivation
    assert d.n - d.n_holonomic - d.n_nonholonomic == 2
    assert [row.label for row in d.constraints].count("rolling_W2_y") == 0


def test_two_wheels_on_one_axle_roll_straight_at_constant_speed():
    # equal wheel rates, gravity normal to the ground: the axle runs straight at its
    # initial speed (x = v t, y = phi = 0) and each wheel turns at -v / r
    system = _load()
    run = system.simulate(t_end=0.5, dt=0.1, backend="python")
    assert run.failure is None
    v = run["x_dot"][0]
    assert abs(v) > 0.1
    np.testing.assert_allclose(run["x"], v * run["t"], atol=1e-9)
    np.testing.assert_allclose(run["y"], 0.0, atol=1e-9)
    np.testing.assert_allclose(run["phi"], 0.0, atol=1e-9)
    np.testing.assert_allclose(run["a1_dot"], run["a2_dot"], atol=1e-9)


def test_independent_rows_are_all_kept():
    d = lagcli.load(Path(__file__).parent.parent / "specs" / "rolling_disc_frames.yaml").derivation
    assert d.n_nonholonomic == 2
