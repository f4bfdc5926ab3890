"""Equilibria (lagcli/analysis/equilibria.py): bead on a spinning hoop, closed forms."""
from __future__ import annotations

import math

import pytest

from lagcli.analysis.equilibria import default_guesses, equilibria


def find(d, **overrides):
    params = {p.symbol.name: float(p.value) for p in d.model.parameters} | overrides
    return equilibria(d, params, default_guesses(d, []))


def test_bead_off_axis_equilibrium_and_its_small_oscillations(derived):
    d = derived("bead_on_spinning_hoop")
    R, g, Omega = 0.5, 9.81, 6.0
    found = find(d)
    off_axis = [e for e in found if 0 < e.coordinates["theta"] < math.pi]
    (e,) = off_axis
    theta = math.acos(g / (R * Omega**2))            # cos(theta*) = g / (R Omega^2)
    assert e.coordinates["theta"] == pytest.approx(theta, rel=1e-12)
    omega = Omega * math.sin(theta)                  # omega^2 = Omega^2 sin^2(theta*)
    assert [abs(s) for s in e.stability.eigenvalues] == pytest.approx([omega, omega], rel=1e-10)
    assert all(s.real == 0 for s in e.stability.eigenvalues)
    bottom = next(e for e in found if e.coordinates["theta"] == 0)
    assert bottom.stability.verdict == "unstable"


@pytest.mark.parametrize("Omega, off_axis_exists", [(math.sqrt(9.81 / 0.5) * 0.99, False),
                                                     (math.sqrt(9.81 / 0.5) * 1.01, True)])
def test_bead_bifurcation_at_omega_squared_g_over_R(derived, Omega, off_axis_exists):
    found = find(derived("bead_on_spinning_hoop"), Omega=Omega)
    thetas = [e.coordinates["theta"] for e in found]
    assert any(0 < t < math.pi for t in thetas) == off_axis_exists
    bottom = next(e for e in found if e.coordinates["theta"] == 0)
    assert bottom.stability.verdict == ("unstable" if off_axis_exists else "stable")


def test_double_pendulum_hanging_frequencies(derived):
    # two equal masses m on rods of equal length l: omega^2 = (2 -+ sqrt 2) g / l
    d = derived("double_pendulum")
    values = {p.symbol.name: p.value for p in d.model.parameters}
    (down,) = [e for e in find(d) if e.coordinates == {"theta1": 0.0, "theta2": 0.0}]
    if not (values.get("m1") == values.get("m2") and values.get("l1") == values.get("l2")):
        pytest.skip("closed form is for equal masses and lengths")
    g, l = values["g"], values["l1"]
    expected = sorted([math.sqrt((2 - math.sqrt(2)) * g / l), math.sqrt((2 + math.sqrt(2)) * g / l)])
    got = sorted({round(abs(s), 12) for s in down.stability.eigenvalues})
    assert got == pytest.approx(expected, rel=1e-10)


def test_constrained_equilibria_and_cli():
    from click.testing import CliRunner

    from lagcli.cli import cli
    from conftest import spec_path

    result = CliRunner().invoke(cli, ["equilibria", str(spec_path("cartesian_pendulum")),
                                      "--guess", "x=0.1,y=-1", "--guess", "x=0.1,y=1", "--json"])
    assert result.exit_code == 0, result.output
    import json
    found = json.loads(result.output)["equilibria"]
    assert sorted(round(e["coordinates"]["y"], 12) for e in found) == [-1.0, 1.0]
    assert {e["verdict"] for e in found} == {"unstable", "stable"}


def test_explicitly_time_dependent_system_has_no_equilibria(derived):
    from lagcli.errors import UsageError

    d = derived("kapitza_pendulum")
    with pytest.raises(UsageError, match="depend explicitly on t"):
        find(d)


def test_nonholonomic_rest_states_are_reported_once(derived):
    found = find(derived("chaplygin_sled"))
    assert len(found) == 1 and found[0].coordinates == {"x": 0.0, "y": 0.0, "phi": 0.0}
