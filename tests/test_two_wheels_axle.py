"""Seed Ex 6-9: two hub-mass wheels on an axle rolling without slipping.

Two corrections to the notes (see specs/ex6_9_two_wheels_axle.yaml):
- the printed wheel positions put the axle along (sin phi, cos phi), which
  contradicts the printed constraint x' sin phi - y' cos phi = 0 and the printed
  solution; the spec uses W1,2 = (x -+ (l/2) sin phi, y +- (l/2) cos phi);
- dT/dphi' = m l^2 phi'/12 is a typo: T = m (x'^2 + y'^2) + m l^2 phi'^2 / 4,
  so the phi equation is (m l^2 / 2) phi'' = 0.
"""
import numpy as np
import pytest
import sympy as sp
from sympy import cos, sin

SPEC = "ex6_9_two_wheels_axle"


def _syms(d):
    model = d.model
    return (*model.q, *model.qd, *model.qdd, model.symbol("m"), model.symbol("l"))


def test_counts(derived):
    d = derived(SPEC)
    assert d.n == 3
    assert d.n_holonomic == 0
    assert d.n_nonholonomic == 1
    assert d.dof == 2
    assert len(d.multipliers) == 1


def test_constraint_row(derived, assert_zero):
    d = derived(SPEC)
    x, y, ph, *_ = _syms(d)
    (row,) = d.constraints
    assert row.kind == "nonholonomic"
    assert row.integrable is False
    assert_zero(sp.Matrix(row.a) - sp.Matrix([sin(ph), -cos(ph), 0]), "a")
    assert_zero(row.d, "d")
    assert_zero(sp.Matrix(d.constraint_matrix) - sp.Matrix([[sin(ph), -cos(ph), 0]]), "A")


def test_kinetic_energy(derived, assert_zero):
    d = derived(SPEC)
    x, y, ph, xd, yd, phd, xdd, ydd, phdd, m, l = _syms(d)
    assert_zero(d.T - (m * (xd**2 + yd**2) + m * l**2 * phd**2 / 4), "T")


def test_equations(derived, assert_zero):
    # 2 m x'' = lambda sin phi ; 2 m y'' = -lambda cos phi ; (m l^2/2) phi'' = 0
    d = derived(SPEC)
    x, y, ph, xd, yd, phd, xdd, ydd, phdd, m, l = _syms(d)
    (lam,) = d.multipliers
    ex, ey, eph = d.equations
    assert_zero((ex.lhs - ex.rhs) - (2 * m * xdd - lam * sin(ph)), "x equation")
    assert_zero((ey.lhs - ey.rhs) - (2 * m * ydd + lam * cos(ph)), "y equation")
    assert_zero((eph.lhs - eph.rhs) - m * l**2 * phdd / 2, "phi equation")


def test_closed_form_circular_path(derived, assert_zero):
    # x = (v0/w) sin wt, y = (v0/w)(1 - cos wt), phi = wt, lambda = -2 m v0 w
    d = derived(SPEC)
    model = d.model
    x, y, ph, xd, yd, phd, xdd, ydd, phdd, m, l = _syms(d)
    (lam,) = d.multipliers
    t = model.t
    v0, w = sp.symbols("v0 omega", positive=True)
    path = [v0 / w * sin(w * t), v0 / w * (1 - cos(w * t)), w * t]
    subs = {}
    for q, qd, qdd, f in zip(model.q, model.qd, model.qdd, path):
        subs.update({q: f, qd: sp.diff(f, t), qdd: sp.diff(f, t, 2)})
    subs[lam] = -2 * m * v0 * w
    for eq in d.equations:
        assert_zero((eq.lhs - eq.rhs).xreplace(subs), f"equation {eq.coordinate} on the path")
    (row,) = d.constraints
    residual = sum(a * qd for a, qd in zip(row.a, model.qd)) + row.d
    assert_zero(residual.xreplace(subs), "constraint on the path")
    # the path is the circle x^2 + (y - v0/w)^2 = (v0/w)^2 of the notes, eq. (11)
    assert_zero((path[0] ** 2 + (path[1] - v0 / w) ** 2 - (v0 / w) ** 2), "circle")


def test_closed_form_numerically(derived, augmented):
    # the same path, through the augmented system at a few times (spec parameters)
    d = derived(SPEC)
    model = d.model
    mass = {info.symbol.name: info.value for info in model.parameters}["m"]
    v0, w = 1.0, 2.0
    for t in (0.0, 0.3, 1.1, 2.7):
        q = [v0 / w * np.sin(w * t), v0 / w * (1 - np.cos(w * t)), w * t]
        qd = [v0 * np.cos(w * t), v0 * np.sin(w * t), w]
        state = dict(zip((*model.q, *model.qd), (*q, *qd)))
        state[model.t] = t
        qdd, lam = augmented(d, state)
        expected = [-v0 * w * np.sin(w * t), v0 * w * np.cos(w * t), 0.0]
        assert qdd == pytest.approx(expected, abs=1e-10)
        assert lam[0] == pytest.approx(-2 * mass * v0 * w, rel=1e-10)


def test_phi_is_ignorable_and_energy_conserved(derived, assert_zero):
    # x, y and phi are all absent from L. x_dot and y_dot have coefficients in the
    # constraint x_dot sin(phi) - y_dot cos(phi) = 0, so x and y are not ignorable;
    # phi appears there only through sin/cos, its column of A is 0, so phi is:
    # its equation (m l^2/2) phi'' = 0 has no multiplier term (docs/derive.md).
    d = derived(SPEC)
    x, y, ph, xd, yd, phd, xdd, ydd, phdd, m, l = _syms(d)
    assert d.ignorable == (ph,)
    (momentum,) = [c for c in d.conserved if c.kind == "momentum"]
    assert momentum.name == "p_phi"
    assert_zero(momentum.expr - m * l**2 * phd / 2, "p_phi = dT/dphi_dot (hand-derived T)")
    assert d.jacobi_integral is not None
    assert d.energy_is_jacobi is True
    assert_zero(d.jacobi_integral - d.energy, "h - E")


def test_p_phi_column_is_constant_along_a_simulation(tmp_path, monkeypatch):
    # independent of the derivation: the CSV's p_phi must equal m l^2 phi_dot / 2 from the
    # hand-derived T at every row, and stay at its initial value along a curved path
    from click.testing import CliRunner

    from conftest import spec_path
    from lagcli.cli import cli
    from lagcli.run.rows import parse_csv

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    v, heading = 1.0, 0.4
    result = CliRunner().invoke(cli, [
        "simulate", str(spec_path(SPEC)), "--backend", "python", "--t-end", "3", "--dt", "0.1",
        "--init", f"phi={heading}", "--init", "phi_dot=1.5",
        "--init", f"x_dot={v * np.cos(heading)}", "--init", f"y_dot={v * np.sin(heading)}"])
    assert result.exit_code == 0, result.output
    header, rows = parse_csv(result.stdout)
    columns = {name: np.array([row[i] for row in rows]) for i, name in enumerate(header)}
    m, l = 1.0, 0.5  # the spec's parameter values
    assert np.allclose(columns["p_phi"], m * l**2 * columns["phi_dot"] / 2, rtol=1e-12, atol=0)
    assert np.max(np.abs(columns["p_phi"] - m * l**2 * 1.5 / 2)) < 1e-10
    assert np.ptp(columns["x"]) > 0.1 and np.ptp(columns["y"]) > 0.1  # the wheels did move
