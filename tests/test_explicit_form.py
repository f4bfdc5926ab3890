"""Two derivations of the same right-hand side must agree, for every bundled spec:

- `forcing` (Kane's form: sum of m r''_0 . dr/dq over points, Euler's equations for bodies), and
- the notes' explicit form, term by term from T = 1/2 q'^T M q' + a.q' + T0 (section 6.6):
  F = Q' - c - M_t q' - gamma q' - a_t - (dV/dq - dT0/dq).

Also: gamma is skew-symmetric, c is quadratic in q', and the equations' lhs is M q'' - F.
"""
from pathlib import Path

import pytest
import sympy as sp

from lagcli.api import load_model
from lagcli.calculus import numerically_zero
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
