"""Routh reduction (lagcli/analysis/routh.py): the spherical pendulum's conical motions."""
from __future__ import annotations

import math

import pytest
import sympy as sp

from lagcli.analysis.routh import routhian, steady_motions


@pytest.mark.parametrize("theta0", [0.4, 0.9, 1.3])
def test_spherical_pendulum_conical_motion(derived, theta0, assert_zero):
    d = derived("spherical_pendulum")
    m, L, g = 1.0, 1.0, 9.81
    reduction = routhian(d)
    assert [c.name for c in reduction.cyclic] == ["phi"]
    # V_eff = p^2 / (2 m L^2 sin^2 theta) - m g L cos theta (hand-derived)
    theta, p = d.model.symbol("theta"), reduction.momenta[0]
    ms, Ls, gs = (d.model.symbol(n) for n in ("m", "L", "g"))
    assert_zero(reduction.effective_potential - (p**2 / (2 * ms * Ls**2 * sp.sin(theta)**2) - ms * gs * Ls * sp.cos(theta)))
    Omega = math.sqrt(g / (L * math.cos(theta0)))     # conical pendulum: Omega^2 = g / (l cos theta0)
    momentum = m * L**2 * math.sin(theta0)**2 * Omega
    params = {p_.symbol.name: p_.value for p_ in d.model.parameters}
    (motion,) = steady_motions(d, reduction, {"p_phi": momentum}, params, [{"theta": theta0 + 0.1}])
    assert motion.coordinates["theta"] == pytest.approx(theta0, rel=1e-10)
    assert motion.cyclic_rates["phi_dot"] == pytest.approx(Omega, rel=1e-10)
    omega = Omega * math.sqrt(1 + 3 * math.cos(theta0)**2)   # small oscillations about the cone
    assert motion.frequencies == pytest.approx((omega,), rel=1e-10)


def test_routh_refuses_constrained_and_non_cyclic(derived):
    from lagcli.errors import UsageError

    with pytest.raises(UsageError):
        routhian(derived("cartesian_pendulum"))
    with pytest.raises(UsageError):
        routhian(derived("double_pendulum"))


def test_cli_routh_json_and_errors():
    import json

    from click.testing import CliRunner

    from lagcli.cli import cli
    from conftest import spec_path

    runner = CliRunner()
    path = str(spec_path("spherical_pendulum"))
    result = runner.invoke(cli, ["routh", path, "--momentum", "p_phi=0.5", "--guess", "theta=1", "--json"])
    assert result.exit_code == 0, result.output
    content = json.loads(result.output)
    assert content["cyclic"] == ["phi"] and len(content["steady_motions"]) == 1
    bad = runner.invoke(cli, ["routh", path, "--momentum", "p_ph=0.5"])
    assert bad.exit_code == 2 and "did you mean 'p_phi'" in bad.output
    bad = runner.invoke(cli, ["routh", str(spec_path("double_pendulum"))])
    assert bad.exit_code == 2 and "no ignorable coordinate" in bad.output
