"""Plane pendulum in Cartesian coordinates with the holonomic rod constraint
x^2 + y^2 - l^2 = 0 (axes: y up, gravity -g j).

The constraint row is a = (2x, 2y), so the constraint force on the bob is
lambda (2x, 2y). The rod pulls the bob towards O with the tension
    tension = m v^2 / l - m g y / l       (radial balance, y = -l cos theta)
i.e. lambda (2x, 2y) = -tension (x, y) / l, so lambda = -tension / (2 l).
"""
import numpy as np
import pytest
import sympy as sp

SPEC = "cartesian_pendulum"


def test_counts_and_row(derived, assert_zero):
    d = derived(SPEC)
    x, y = d.model.q
    assert d.n == 2 and d.n_holonomic == 1 and d.n_nonholonomic == 0 and d.dof == 1
    (row,) = d.constraints
    assert row.kind == "holonomic"
    assert_zero(sp.Matrix(row.a) - sp.Matrix([2 * x, 2 * y]), "a")
    assert_zero(row.d, "d")
    assert d.multipliers[0].name == "lambda_rod"


def test_equations(derived, assert_zero):
    d = derived(SPEC)
    model = d.model
    x, y = model.q
    xdd, ydd = model.qdd
    m, g = model.symbol("m"), model.symbol("g")
    (lam,) = d.multipliers
    ex, ey = d.equations
    assert_zero((ex.lhs - ex.rhs) - (m * xdd - 2 * x * lam), "x equation")
    assert_zero((ey.lhs - ey.rhs) - (m * ydd + m * g - 2 * y * lam), "y equation")


def test_multiplier_is_tension_and_motion_is_the_polar_pendulum(derived, augmented, rng):
    d = derived(SPEC)
    model = d.model
    p = {info.symbol.name: info.value for info in model.parameters}
    m, l, g = p["m"], p["l"], p["g"]
    for _ in range(5):
        th, thd = rng.uniform(-2.5, 2.5), rng.uniform(-3.0, 3.0)
        x, y = l * np.sin(th), -l * np.cos(th)
        xd, yd = l * np.cos(th) * thd, l * np.sin(th) * thd
        state = dict(zip((*model.q, *model.qd), (x, y, xd, yd)))
        qdd, lam = augmented(d, state)
        tension = m * (xd**2 + yd**2) / l - m * g * y / l
        assert lam[0] == pytest.approx(-tension / (2 * l), rel=1e-10)
        thdd = -g / l * np.sin(th)
        xdd = l * (np.cos(th) * thdd - np.sin(th) * thd**2)
        ydd = l * (np.sin(th) * thdd + np.cos(th) * thd**2)
        assert qdd == pytest.approx([xdd, ydd], rel=1e-10, abs=1e-10)


def test_energy_is_jacobi(derived, assert_zero):
    d = derived(SPEC)
    assert d.ignorable == ()
    assert d.jacobi_integral is not None and d.energy_is_jacobi is True
    assert_zero(d.jacobi_integral - d.energy, "h - E")
