"""Hamilton's form (lagcli/derive/hamilton_form.py, lagcli/analysis/hamiltonian.py) against the Lagrangian equations.

For every bundled unconstrained spec, Hamilton's equations in (q, p) are integrated
with scipy and compared with an integration of M q'' = F (the derivation's own
Lagrangian form) from the same state: q and q'(q, p) agree to 1e-8. Where the
Jacobi integral exists, H(q, p) equals it along the way and stays constant.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from lagcli.analysis.hamiltonian import HamiltonRhs
from lagcli.derive.hamilton_form import hamilton_form
from lagcli.interface import layout_of

from conftest import SPECS, spec_path

UNCONSTRAINED = sorted(p.stem for p in SPECS.glob("*.yaml")
                       if "\nconstraints:" not in p.read_text(encoding="utf-8")
                       and "\nrolling:" not in p.read_text(encoding="utf-8"))
T_END = 1.0


def lagrangian_rhs(d, params):
    model = d.model
    values = {p.symbol: params[p.symbol.name] for p in (*model.parameters, *model.inputs)}
    args = [model.t, list(model.q), list(model.qd)]
    M = sp.lambdify(args, sp.Matrix(d.mass_matrix).xreplace(values), "numpy", cse=True)
    F = sp.lambdify(args, sp.Matrix(d.forcing).xreplace(values), "numpy", cse=True)
    n = len(model.q)

    def rhs(t, y):
        q, qd = y[:n], y[n:]
        qdd = np.linalg.solve(np.asarray(M(t, q, qd), float).reshape(n, n), np.asarray(F(t, q, qd), float).reshape(n))
        return np.concatenate([qd, qdd])
    return rhs


@pytest.mark.parametrize("name", UNCONSTRAINED)
def test_hamilton_equations_agree_with_lagrange(derived, name):
    d = derived(name)
    model = d.model
    n = len(model.q)
    params = {p.symbol.name: p.value for p in (*model.parameters, *model.inputs)}   # inputs held
    y0 = np.array([model.initial.get(s.name, 0.0) for s in (*model.q, *model.qd)], dtype=float)
    y0[:n] += 0.1      # away from symmetric starts, so every coordinate moves
    ham = HamiltonRhs(d, params)
    values = {p.symbol: params[p.symbol.name] for p in (*model.parameters, *model.inputs)}
    momentum = sp.lambdify([model.t, list(model.q), list(model.qd)],
                           (sp.Matrix(d.mass_matrix) * sp.Matrix(model.qd) + sp.Matrix(d.t1_coefficients)).xreplace(values))
    p0 = np.asarray(momentum(0.0, y0[:n], y0[n:]), float).reshape(n)
    times = np.linspace(0, T_END, 11)
    tol = dict(rtol=1e-12, atol=1e-12, method="DOP853", t_eval=times)
    lag = solve_ivp(lagrangian_rhs(d, params), (0, T_END), y0, **tol)
    hamilton = solve_ivp(ham, (0, T_END), np.concatenate([y0[:n], p0]), **tol)
    assert lag.success and hamilton.success
    velocities = np.array([ham.velocities(t, y[:n], y[n:]) for t, y in zip(times, hamilton.y.T)]).T
    np.testing.assert_allclose(hamilton.y[:n], lag.y[:n], atol=1e-8, rtol=0)
    np.testing.assert_allclose(velocities, lag.y[n:], atol=1e-8 * max(1.0, np.max(np.abs(lag.y[n:]))), rtol=0)
    if d.jacobi_integral is not None:
        h = sp.lambdify([model.t, list(model.q), list(model.qd)], d.jacobi_integral.xreplace(values))
        H = [ham.hamiltonian(t, y) for t, y in zip(times, hamilton.y.T)]
        jacobi = [h(t, y[:n], v) for t, y, v in zip(times, hamilton.y.T, velocities.T)]
        np.testing.assert_allclose(H, jacobi, rtol=1e-10, atol=1e-10)
        assert np.ptp(H) < 1e-8 * max(1.0, abs(H[0]))


@pytest.mark.core_specs
@pytest.mark.parametrize("name", UNCONSTRAINED)
def test_generated_hamiltonian_module_agrees_with_lagrange(derived, name, tmp_path):
    """`lagcli generate --lang python --form hamiltonian`: its rhs(t, x, p) integrated in
    (q, p) follows the Lagrangian integration of M q'' = F (from the Derivation, not from
    any emitter) to 1e-8, and its hamiltonian(t, x, p) equals the Jacobi integral."""
    import importlib.util

    from lagcli.targets.hamilton import hamilton_module

    d = derived(name)
    model = d.model
    n = len(model.q)
    path = tmp_path / f"{name}_hamiltonian.py"
    path.write_text(hamilton_module(d, layout_of(d)))     # what `generate --form hamiltonian` writes
    spec = importlib.util.spec_from_file_location(f"{name}_hamiltonian", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.STATE == [q.name for q in model.q] + [f"p_{q.name}" for q in model.q]
    params = {p.symbol.name: p.value for p in (*model.parameters, *model.inputs)}
    y0 = np.array([model.initial.get(s.name, 0.0) for s in (*model.q, *model.qd)], dtype=float)
    y0[:n] += 0.1
    x0 = module.from_lagrangian(0.0, y0, None)
    times = np.linspace(0, T_END, 11)
    tol = dict(rtol=1e-12, atol=1e-12, method="DOP853", t_eval=times)
    lag = solve_ivp(lagrangian_rhs(d, params), (0, T_END), y0, **tol)
    ham = solve_ivp(lambda t, x: module.rhs(t, x, None), (0, T_END), x0, **tol)
    assert lag.success and ham.success
    velocities = np.array([module.velocities(t, x, None) for t, x in zip(times, ham.y.T)]).T
    np.testing.assert_allclose(ham.y[:n], lag.y[:n], atol=1e-8, rtol=0)
    np.testing.assert_allclose(velocities, lag.y[n:], atol=1e-8 * max(1.0, np.max(np.abs(lag.y[n:]))), rtol=0)
    if d.jacobi_integral is not None:
        values = {p.symbol: params[p.symbol.name] for p in (*model.parameters, *model.inputs)}
        h = sp.lambdify([model.t, list(model.q), list(model.qd)], d.jacobi_integral.xreplace(values))
        H = [module.hamiltonian(t, x, None) for t, x in zip(times, ham.y.T)]
        jacobi = [h(t, y[:n], y[n:]) for t, y in zip(times, lag.y.T)]
        np.testing.assert_allclose(H, jacobi, rtol=1e-9, atol=1e-9)


def test_generated_hamiltonian_module_refusals(tmp_path):
    from click.testing import CliRunner

    from lagcli.cli import cli

    runner = CliRunner()
    constrained = runner.invoke(cli, ["generate", str(SPECS / "cartesian_pendulum.yaml"), "--lang", "python",
                                      "--form", "hamiltonian"])
    assert constrained.exit_code == 2 and "unconstrained systems" in constrained.output
    c = runner.invoke(cli, ["generate", str(SPECS / "cart_pole.yaml"), "--lang", "c", "--form", "hamiltonian",
                            "-o", str(tmp_path / "c")])
    assert c.exit_code == 2 and "--lang python only" in c.output
    path = tmp_path / "sp.py"
    done = runner.invoke(cli, ["generate", str(SPECS / "spherical_pendulum.yaml"), "--lang", "python",
                               "--form", "hamiltonian", "-o", str(path)])
    assert done.exit_code == 0 and "def rhs(t, x, p):" in path.read_text()


def test_spherical_pendulum_hamiltonian_closed_form(derived, assert_zero):
    d = derived("spherical_pendulum")
    form = hamilton_form(d)
    th = d.model.symbol("theta")
    m, L, g = (d.model.symbol(n) for n in ("m", "L", "g"))
    p_th, p_ph = form.momenta
    # H = p_th^2/(2 m L^2) + p_ph^2/(2 m L^2 sin^2 th) - m g L cos th  (textbook)
    assert_zero(form.H - (p_th**2 / (2 * m * L**2) + p_ph**2 / (2 * m * L**2 * sp.sin(th)**2) - m * g * L * sp.cos(th)))
    assert form.pdot[1] == 0


def test_cli_hamiltonian_formats():
    from click.testing import CliRunner

    from lagcli.cli import cli
    from conftest import spec_path

    runner = CliRunner()
    path = str(spec_path("bead_on_spinning_hoop"))
    assert "H = " in runner.invoke(cli, ["hamiltonian", path]).output
    assert r"\begin{align*}" in runner.invoke(cli, ["hamiltonian", path, "--latex"]).output
    bad = runner.invoke(cli, ["hamiltonian", str(spec_path("cartesian_pendulum"))])
    assert bad.exit_code == 2 and "unconstrained" in bad.output


@pytest.mark.parametrize("name", ["bead_on_spinning_hoop", "spherical_pendulum", "cart_pole"])
def test_momenta_are_shown_tidy(name):
    """The momenta p = M q' + a get the reports' tidying (issue 21): the bead on the
    spinning hoop's p_theta is m R**2 theta_dot, not m*(R**2*sin(theta)**2 + ...)."""
    import re

    from lagcli.commands import hamiltonian

    text = hamiltonian(str(spec_path(name)))
    assert not re.search(r"sin\((\w+(?:\*\w+)?)\)\*\*2(\*\w+\(\w+(?:\*\w+)?\)\*\*2)?\s*\+\s*\S*cos\(\1\)\*\*2", text), text
    if name == "bead_on_spinning_hoop":
        assert "p_theta = m*R**2*theta_dot" in text


@pytest.mark.parametrize("name, denominator, force", [
    ("cart_pole", "mc + m*sin(theta)**2", "p_theta_dot = g*l*m*sin(theta) + "),
    ("double_pendulum", "m1 + m2*sin(theta1 - theta2)**2", "p_theta1_dot = -g*l1*(m1 + m2)*sin(theta1) + ")])
def test_solved_forms_share_the_textbook_denominator(derived, name, denominator, force):
    """Issue 21: H, q' and p' over one form of det M (the textbook's mc + m sin^2, not
    m + mc - m cos^2 in some rows), p' with the potential's force apart from the kinetic
    fraction; p' equal by value to -dH/dq + Q' from sympy's own inverse of the raw M."""
    from lagcli.commands import hamiltonian

    text = hamiltonian(str(spec_path(name)))
    rows = [line for line in text.splitlines() if line.startswith(("H = ", "  ")) and "/(" in line]
    assert len(rows) >= 4 and all(denominator in row for row in rows), text
    assert force in text
    d = derived(name)
    model, form = d.model, hamilton_form(d)
    M, a = sp.Matrix(d.mass_matrix), sp.Matrix(d.t1_coefficients)
    p = sp.Matrix(form.momenta)
    velocity = M.inv() * (p - a)
    H = ((p - a).T * velocity)[0] / 2 - d.T0 + d.V
    Q = sp.Matrix(d.nonconservative_forces).xreplace(dict(zip(model.qd, velocity)))
    rng = np.random.default_rng(21)
    symbols = [*model.parameter_symbols, *model.input_symbols, *model.q, *form.momenta]
    for _ in range(5):
        at = {s: sp.Float(v) for s, v in zip(symbols, rng.uniform(0.3, 1.2, len(symbols)))}
        for k, q in enumerate(model.q):
            expected = float((-H.diff(q) + Q[k]).xreplace(at))
            assert float(form.pdot[k].xreplace(at)) == pytest.approx(expected, rel=1e-9, abs=1e-9)


def test_fewest_squares_against_sympy():
    from lagcli.render.tidy import fewest_squares

    m, mc, x, y = sp.symbols("m mc x y")
    cases = {m + mc - m * sp.cos(x)**2: mc + m * sp.sin(x)**2,
             m - m * sp.sin(x - y)**2: m * sp.cos(x - y)**2,
             mc + m * sp.sin(x)**2: mc + m * sp.sin(x)**2}
    for given, expected in cases.items():
        assert fewest_squares(given) == expected
        assert sp.simplify(fewest_squares(given) - given) == 0
