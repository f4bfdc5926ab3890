"""Two derivations of the same right-hand side must agree, for every bundled spec:

- `forcing` (Kane's form: sum of m r''_0 . dr/dq over points, Euler's equations for bodies), and
- the notes' explicit form, term by term from T = 1/2 q'^T M q' + a.q' + T0 (section 6.6):
  F = Q' - c - M_t q' - gamma q' - a_t - (dV/dq - dT0/dq).

Also: gamma is skew-symmetric, c is quadratic in q', and the equations' lhs is M q'' - F.
"""
from pathlib import Path

import pytest
import sympy as sp

from lagcli.derive.pipeline import load_model
from lagcli.model.calculus import numerically_zero
from lagcli.derive import derive

SPECS = sorted((Path(__file__).parent.parent / "specs").glob("*.yaml"))


@pytest.fixture(scope="module", params=SPECS, ids=lambda p: p.stem)
def derivation(request):
    return derive(load_model(request.param))


def test_forcing_equals_explicit_form(derivation):
    d = derivation
    qd = sp.Matrix(d.model.qd)
    explicit = (d.nonconservative_forces - d.velocity_terms - d.mass_rate_terms
                - d.gyroscopic_matrix * qd - d.t1_rate_terms - d.position_terms)
    assert numerically_zero(list(explicit - d.forcing), trials=4)


def test_gyroscopic_matrix_is_skew(derivation):
    G = derivation.gyroscopic_matrix
    assert numerically_zero(list(G + G.T))


def test_velocity_terms_are_quadratic(derivation):
    d = derivation
    scale = sp.Symbol("scale_test", positive=True)
    scaled = d.velocity_terms.subs({v: scale * v for v in d.model.qd}, simultaneous=True)
    assert numerically_zero(list(scaled - scale**2 * d.velocity_terms))


def test_equations_are_mass_matrix_form(derivation):
    d = derivation
    qdd = sp.Matrix(d.model.qdd)
    lhs = sp.Matrix([eq.lhs for eq in d.equations])
    assert numerically_zero(list(lhs - (d.mass_matrix * qdd - d.forcing)))


def test_augmented_system_reproduces_equations_and_constraints(derivation):
    """Solving [[M, -A^T], [A, 0]] [q''; lambda] = [F; b] must satisfy every equation
    lhs = rhs and the differentiated constraints, at a random state."""
    import numpy as np

    d = derivation
    m = d.model
    rng = np.random.default_rng(7)
    # xreplace, not subs: the same values, minutes faster on the bicycle's large expressions
    values = {s: float(rng.uniform(0.3, 1.3)) for s in (m.t, *m.q, *m.qd, *m.parameter_symbols, *m.input_symbols)}
    K = np.array(d.augmented_matrix.xreplace(values).evalf(), dtype=float)
    b = np.array(d.augmented_rhs.xreplace(values).evalf(), dtype=float).ravel()
    solution = np.linalg.solve(K, b)
    n = len(m.q)
    values.update(zip(m.qdd, solution[:n]))
    values.update(zip(d.multipliers, solution[n:]))
    residuals = [float((eq.lhs - eq.rhs).xreplace(values)) for eq in d.equations]
    for row in d.constraints:  # d/dt (a.q' + d) = 0 along the solution
        velocity_form = sum((ak * v for ak, v in zip(row.a, m.qd)), row.d)
        residuals.append(float(_total_derivative(m, velocity_form).xreplace(values)))
    assert np.allclose(residuals, 0, atol=1e-9 * (1 + np.abs(b).max()))


def _total_derivative(m, expr):
    # written out here (not lagcli.model.calculus.TimeDerivative) to stay independent of the engine
    result = expr.diff(m.t)
    for q, v, a in zip(m.q, m.qd, m.qdd):
        result += expr.diff(q) * v + expr.diff(v) * a
    return result
