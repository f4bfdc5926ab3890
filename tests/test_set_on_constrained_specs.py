"""`simulate --set` on every bundled constrained spec: the spec's initial state is
moved onto the constraints of the new parameters, on both backends.

Each case checks the first row against the constraint written out by hand for the
new parameter value (not against what the solver returned), the residual column
on every row, and that the two backends agree to 1e-7 (docs/simulate.md). Specs
whose constraints do not involve the changed parameter keep their initial state
(no note). `test_every_constrained_spec_has_a_case` keeps the list complete.
"""
from __future__ import annotations

import io
import math
import shutil

import numpy as np
import pytest
from click.testing import CliRunner

from lagcli.cli import cli

from conftest import SPECS

BACKENDS = ["python", pytest.param("c", marks=pytest.mark.skipif(
    shutil.which("cc") is None, reason="no C compiler (cc)"))]


def _roll_x(s):
    """rolling_disc's roll_x with r = 0.5 (specs/rolling_disc.yaml)."""
    r = 0.5
    return s["x_dot"] - r * (s["psi_dot"] * math.cos(s["psi"]) * math.sin(s["theta"])
                             + s["theta_dot"] * math.sin(s["psi"]) * math.cos(s["theta"])
                             + s["phi_dot"] * math.cos(s["psi"]))


def _knife(s):
    """The knife edge of chaplygin_sled and the axle of ex6_9 (no parameter in it)."""
    return s["x_dot"] * math.sin(s["phi"]) - s["y_dot"] * math.cos(s["phi"])


def _bicycle_rear_x(s):
    """benchmark_bicycle's rear_x with rR = 0.35."""
    return s["x_dot"] + 0.35 * (s["theta_dot"] + s["theta_R_dot"]) * math.cos(s["psi"])


CASES = {
    "cartesian_pendulum": ("l=2", lambda s: s["x"] ** 2 + s["y"] ** 2 - 4,
                           "solved for dependent coordinates: x = 1.2, y = -1.6"),
    "atwood": ("L=12", lambda s: s["y1"] + s["y2"] - 12,
               "solved for dependent coordinates: y1 = 6, y2 = 6"),
    "rolling_disc": ("r=0.5", _roll_x, "solved for dependent velocities"),
    "chaplygin_sled": ("b=0.3", _knife, None),
    "ex6_9_two_wheels_axle": ("l=0.8", _knife, None),
    "ex6_9_two_wheels_axle_frames": ("l=0.8", _knife, None),
    "rolling_disc_frames": ("r=0.5", _roll_x, "solved for dependent velocities"),
    "disc_on_incline": ("r=0.2", lambda s: s["s"] - 0.2 * s["theta"], None),
    "benchmark_bicycle": ("rR=0.35", _bicycle_rear_x, "solved for dependent velocities"),   # slow
    "gantry_crane": ("l=2", lambda s: (s["xl"] - s["x"]) ** 2 + s["yl"] ** 2 - 4,
                     "solved for dependent coordinates"),
}

# Rolling-element specs whose --set runs are covered elsewhere: sphere_on_turntable by
# tests/test_frames_specs.py (simulated against 2 Omega / 7), benchmark_bicycle_frames by
# its equality with benchmark_bicycle (slow), which is in CASES.
RUN_ELSEWHERE = {"sphere_on_turntable", "benchmark_bicycle_frames"}


def test_every_constrained_spec_has_a_case():
    constrained = {path.stem for path in SPECS.glob("*.yaml")
                   if "\nconstraints:" in path.read_text() or "\nrolling:" in path.read_text()}
    assert constrained == set(CASES) | RUN_ELSEWHERE


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def run(spec: str, assignment: str, backend: str):
    try:
        runner = CliRunner(mix_stderr=False)
    except TypeError:
        runner = CliRunner()
    result = runner.invoke(cli, ["simulate", str(SPECS / f"{spec}.yaml"), "--set", assignment,
                                 "--t-end", "1", "--backend", backend])
    assert result.exit_code == 0, result.stderr
    header = result.stdout.splitlines()[0].split(",")
    return header, np.loadtxt(io.StringIO(result.stdout), delimiter=",", skiprows=1), result.stderr


@pytest.mark.core_specs
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("spec", sorted(CASES))
def test_set_moves_the_initial_state_onto_the_new_constraints(spec, backend):
    assignment, constraint, note = CASES[spec]
    header, rows, stderr = run(spec, assignment, backend)
    first = dict(zip(header, rows[0]))
    assert abs(constraint(first)) < 1e-10
    assert np.max(rows[:, header.index("constraint_residual")]) < 1e-8
    if note is None:
        assert "solved for" not in stderr
        return
    assert note in stderr
    name, _, value = assignment.partition("=")
    assert f"with {name} = {value} (--set)" in stderr


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
@pytest.mark.parametrize("spec", sorted(CASES))
def test_backends_agree_after_set(spec):
    assignment = CASES[spec][0]
    (hp, p, notes_p), (hc, c, notes_c) = (run(spec, assignment, b) for b in ("python", "c"))
    assert hp == hc and notes_p == notes_c
    assert p.shape == c.shape
    assert np.max(np.abs(p - c)) < 1e-7


def test_unrepairable_state_names_what_the_user_gave():
    try:
        runner = CliRunner(mix_stderr=False)
    except TypeError:
        runner = CliRunner()
    result = runner.invoke(cli, ["simulate", str(SPECS / "cartesian_pendulum.yaml"), "--set", "l=2",
                                 "--init", "x=0.5", "--init", "y=0.5", "--backend", "python"])
    assert result.exit_code == 2
    assert "hint: --init gave x, y; --set gave l;" in result.stderr
