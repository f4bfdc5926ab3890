"""Routh reduction (lagcli/analysis/routh.py): the spherical pendulum's conical motions."""
from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner

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


POLAR_SPHERICAL_PENDULUM = """\
name: spherical_pendulum_polar
coordinates: [r, theta, phi]
parameters: {m: 1.0, L: 1.0, g: 9.81}
gravity: [0, 0, -g]
particles:
  bob: {mass: m, position: ['r*sin(theta)*cos(phi)', 'r*sin(theta)*sin(phi)', '-r*cos(theta)']}
constraints:
  - {name: rod, expr: r - L}
"""


def test_routh_reduction_of_a_constrained_system():
    """phi appears in no constraint of the spherical pendulum written in (r, theta, phi)
    with the rod r = L as a constraint: the Routhian is the textbook one on r = L, and
    the reduced equations keep the multiplier (the rod's tension) in the r row."""
    import lagcli
    from lagcli.model.calculus import numerically_zero
    from lagcli.errors import UsageError

    d = lagcli.load(POLAR_SPHERICAL_PENDULUM).derivation
    reduction = routhian(d)
    s = {n: d.model.symbol(n) for n in ("r", "theta", "m", "L", "g", "r_dot", "theta_dot", "r_ddot", "theta_ddot")}
    p, lam = reduction.momenta[0], d.multipliers[0]
    r, th, m, L, g = s["r"], s["theta"], s["m"], s["L"], s["g"]
    on_rod = {r: L, s["r_dot"]: 0, s["r_ddot"]: 0}
    textbook_R = (m * L**2 * s["theta_dot"]**2 / 2 - p**2 / (2 * m * L**2 * sp.sin(th)**2)
                  + m * g * L * sp.cos(th))
    radial, polar = reduction.equations
    assert numerically_zero([reduction.R.xreplace(on_rod) - textbook_R])
    assert numerically_zero([polar.xreplace(on_rod) - (m * L**2 * s["theta_ddot"]
                             - p**2 * sp.cos(th) / (m * L**2 * sp.sin(th)**3) + m * g * L * sp.sin(th))])
    # r row: m r'' - m r theta'^2 - p^2/(m r^3 sin^2) - m g cos(theta) = lambda_rod
    assert numerically_zero([radial - (m * s["r_ddot"] - m * r * s["theta_dot"]**2
                                       - p**2 / (m * r**3 * sp.sin(th)**2) - m * g * sp.cos(th) - lam)])
    with pytest.raises(UsageError, match="steady motions of a constrained"):
        steady_motions(d, reduction, {"p_phi": 1.0}, {"m": 1.0, "L": 1.0, "g": 9.81}, [{}])


def test_routh_refuses_an_ignorable_coordinate_inside_a_constraint():
    """Ex. 6-9: p_phi is conserved, but phi is inside the rolling constraints (sin(phi))."""
    from click.testing import CliRunner

    from lagcli.cli import cli
    from conftest import spec_path

    result = CliRunner().invoke(cli, ["routh", str(spec_path("ex6_9_two_wheels_axle"))])
    assert result.exit_code == 2 and "Traceback" not in result.output
    assert "ex6_9_two_wheels_axle.yaml:" in result.output and "constraints[0]:" in result.output
    assert "'phi' is ignorable (p_phi is conserved) but this constraint contains it" in result.output


def test_routh_of_the_heavy_top_at_given_momenta_needs_no_cyclic_angle():
    # the Routhian held sin^2 + cos^2 of the cyclic phi (NameError at the numbers); the steady
    # motion is the root of the closed-form V_eff' of the top (Goldstein 5.7), A' = A + m h^2:
    # V_eff = (p_psi - p_phi cos th)^2 / (2 A' sin^2 th) + p_phi^2 / (2 C) + m g h cos th
    from scipy.optimize import brentq

    from lagcli.cli import cli

    A, C, m, g, h, a, b = 2e-4 + 0.5 * 0.04**2, 3e-4, 0.5, 9.81, 0.04, 0.002, 0.0045
    slope = lambda t: (-(a - b * np.cos(t))**2 * np.cos(t) / (A * np.sin(t)**3)          # noqa: E731
                       + (a - b * np.cos(t)) * b / (A * np.sin(t)) - m * g * h * np.sin(t))
    expected = brentq(slope, 2.3, 2.6)
    args = ["routh", "specs/heavy_symmetric_top.yaml", "--momentum", "p_psi=0.002", "--momentum", "p_phi=0.0045"]
    for guess in ("0.4", "2.4"):
        result = CliRunner().invoke(cli, [*args, "--guess", f"theta={guess}"])
        assert result.exit_code == 0 and result.exception is None, result.output
    found = float(result.output.split("steady motion 1: theta = ")[1].split(",")[0])
    assert found == pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize("name", ["spherical_pendulum", "heavy_symmetric_top"])
def test_reduced_equations_in_the_derive_order_equal_sympys_euler_lagrange(derived, name):
    """Each reduced equation's printed terms: the q_r'' terms first, the velocity terms before
    the velocity-free ones (the derive report's order, issue 21); their sum equals
    d/dt(dR/dq'_r) - dR/dq_r taken by sympy's own diff on functions of t, at random states."""
    d = derived(name)
    model, reduction = d.model, routhian(d)
    t, r = model.t, [model.q.index(q) for q in reduction.reduced]
    curves = {model.q[k]: sp.Function(f"c{k}")(t) for k in r}
    on_t = {**curves, **{model.qd[k]: curves[model.q[k]].diff(t) for k in r}}
    back = {**{c.diff(t, 2): model.qdd[k] for k, c in zip(r, curves.values())},
            **{c.diff(t): model.qd[k] for k, c in zip(r, curves.values())},
            **{c: model.q[k] for k, c in zip(r, curves.values())}}
    rng = np.random.default_rng(21)
    symbols = [*model.parameter_symbols, *reduction.momenta, *model.q, *model.qd, *model.qdd]
    for k, terms in zip(r, reduction.equation_terms):
        accelerations = [any(term.has(model.qdd[j]) for j in r) for term in terms]
        moving = [any(term.has(model.qd[j]) for j in r) for term in terms]
        first = accelerations.index(False)
        assert all(accelerations[:first]) and not any(accelerations[first:])
        assert moving[first:] == sorted(moving[first:], reverse=True)
        lagrange = sp.diff(reduction.R.diff(model.qd[k]).xreplace(on_t), t) - reduction.R.diff(model.q[k]).xreplace(on_t)
        lagrange = lagrange.subs(back)
        for _ in range(5):
            at = {s: sp.Float(v) for s, v in zip(symbols, rng.uniform(0.3, 1.2, len(symbols)))}
            assert float(sp.Add(*terms).xreplace(at)) == pytest.approx(float(lagrange.xreplace(at)), rel=1e-9, abs=1e-9)


def test_cli_routh_prints_the_acceleration_first():
    from lagcli.cli import cli

    result = CliRunner().invoke(cli, ["routh", "specs/spherical_pendulum.yaml"])
    (row,) = result.output.split("reduced equations (= 0):\n")[1].splitlines()[:1]
    assert row == "  m*L**2*theta_ddot + L*g*m*sin(theta) - p_phi**2*cos(theta)/(L**2*m*sin(theta)**3)"
