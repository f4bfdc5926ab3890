"""Uniform disc rolling down an incline, coordinates (s, theta) and the holonomic
rolling constraint s - r theta = 0, i.e. a = (1, -r).

By hand: T = m s'^2/2 + (m r^2/2) theta'^2/2, V = -m g s sin(alpha);
    m s'' - m g sin(alpha) = lambda,   (m r^2/2) theta'' = -r lambda,  s'' = r theta''
 -> s'' = (2/3) g sin(alpha),  lambda = -(1/3) m g sin(alpha).
lambda is the friction force's component along s (positive downhill): friction of
size m g sin(alpha)/3 acts uphill; its generalized force on theta is -r lambda,
the moment of that friction about the centre.
"""
import sympy as sp

from oracles import solve_augmented
from sympy import sin

SPEC = "disc_on_incline"


def _syms(d):
    model = d.model
    return (*model.q, *model.qd, *model.qdd, *(model.symbol(n) for n in ("m", "r", "g", "alpha")))


def test_counts_and_row(derived, assert_zero):
    d = derived(SPEC)
    s, th, sd, thd, sdd, thdd, m, r, g, alpha = _syms(d)
    assert d.n_holonomic == 1 and d.n_nonholonomic == 0 and d.dof == 1
    (row,) = d.constraints
    assert row.kind == "holonomic"
    assert_zero(sp.Matrix(row.a) - sp.Matrix([1, -r]), "a")
    assert d.multipliers[0].name == "lambda_rolling"


def test_energies(derived, assert_zero):
    d = derived(SPEC)
    s, th, sd, thd, sdd, thdd, m, r, g, alpha = _syms(d)
    assert_zero(d.T - (m * sd**2 / 2 + m * r**2 * thd**2 / 4), "T")
    for q in (s, th):
        assert_zero(sp.diff(d.V + m * g * s * sin(alpha), q), f"dV/d{q}")


def test_acceleration_and_friction(derived, assert_zero):
    d = derived(SPEC)
    s, th, sd, thd, sdd, thdd, m, r, g, alpha = _syms(d)
    qdd, lam = solve_augmented(d)
    assert_zero(qdd[0] - sp.Rational(2, 3) * g * sin(alpha), "s''")
    assert_zero(qdd[1] - sp.Rational(2, 3) * g * sin(alpha) / r, "theta''")
    assert_zero(lam[0] + m * g * sin(alpha) / 3, "lambda")


def test_generalized_constraint_forces(derived, assert_zero):
    d = derived(SPEC)
    s, th, sd, thd, sdd, thdd, m, r, g, alpha = _syms(d)
    (lam,) = d.multipliers
    assert_zero(sp.Matrix(d.generalized_constraint_forces) - sp.Matrix([lam, -r * lam]), "C")
