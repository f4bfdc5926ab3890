"""Atwood machine, coordinates y1, y2 = depths below the pulley (positive down),
rope constraint y1 + y2 - L = 0, so a = (1, 1).

By hand: T = (m1 y1'^2 + m2 y2'^2)/2, V = -g (m1 y1 + m2 y2);
    m1 y1'' - m1 g = lambda,   m2 y2'' - m2 g = lambda,   y1'' + y2'' = 0
 -> y1'' = (m1 - m2) g / (m1 + m2),  lambda = -2 m1 m2 g / (m1 + m2).
The constraint's generalized force lambda * a_i acts along the downward depth; the
rope pulls each mass up with the tension, so tension = -lambda = 2 m1 m2 g/(m1 + m2).
"""
import sympy as sp

from oracles import solve_augmented

SPEC = "atwood"


def _syms(d):
    model = d.model
    return (*model.q, *model.qd, *model.qdd, *(model.symbol(n) for n in ("m1", "m2", "g", "L")))


def test_row_and_equations(derived, assert_zero):
    d = derived(SPEC)
    y1, y2, y1d, y2d, y1dd, y2dd, m1, m2, g, L = _syms(d)
    (row,) = d.constraints
    assert row.kind == "holonomic"
    assert_zero(sp.Matrix(row.a) - sp.Matrix([1, 1]), "a")
    assert d.dof == 1
    (lam,) = d.multipliers
    assert lam.name == "lambda_rope"
    e1, e2 = d.equations
    assert_zero((e1.lhs - e1.rhs) - (m1 * y1dd - m1 * g - lam), "y1 equation")
    assert_zero((e2.lhs - e2.rhs) - (m2 * y2dd - m2 * g - lam), "y2 equation")


def test_acceleration_and_tension(derived, assert_zero):
    d = derived(SPEC)
    y1, y2, y1d, y2d, y1dd, y2dd, m1, m2, g, L = _syms(d)
    qdd, lam = solve_augmented(d)
    acc = (m1 - m2) * g / (m1 + m2)
    assert_zero(qdd[0] - acc, "y1''")
    assert_zero(qdd[1] + acc, "y2''")
    tension = 2 * m1 * m2 * g / (m1 + m2)
    assert_zero(lam[0] + tension, "lambda + tension")


def test_particle_constraint_force_is_rope_tension(derived, assert_zero):
    # R_i = m_i r_i'' - F_i: on P1 = (-d, -y1) it is (0, tension, 0), pointing up.
    d = derived(SPEC)
    y1, y2, y1d, y2d, y1dd, y2dd, m1, m2, g, L = _syms(d)
    qdd, lam = solve_augmented(d)
    subs = {y1dd: qdd[0], y2dd: qdd[1], d.multipliers[0]: lam[0]}
    tension = 2 * m1 * m2 * g / (m1 + m2)
    for name in ("P1", "P2"):
        R = sp.Matrix(d.particle_constraint_forces[name]).xreplace(subs)
        assert_zero(R[:2, :] - sp.Matrix([0, tension]), f"R_{name}")
        assert_zero(R[2:, :], f"R_{name} (z)")
