"""Double pendulum (specs/double_pendulum.yaml) against sympy.physics.mechanics.

Oracles, built from scratch in tests/oracles.py: LagrangesMethod on L = T - V of two
particles, and KanesMethod with u_i = theta_i' (so its rows are Lagrange's). Both
give M q'' = F; lagcli's M, F (unconstrained: no A^T lambda) must agree with them
symbolically and numerically, and its equation left-hand sides with
LagrangesMethod's `eom` (d/dt dL/dq' - dL/dq).
"""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from oracles import (spec_fixtures, assert_close, double_pendulum_lagrange, lambdify_model, lambdify_oracle,
                     param_values, planar_chain_kane, to_model)

SPEC = Path(__file__).resolve().parent.parent / "specs" / "double_pendulum.yaml"


model, derivation, oracle = spec_fixtures(SPEC, double_pendulum_lagrange)


def random_states(model, seed, count=8):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield (rng.uniform(-np.pi, np.pi, 2), rng.uniform(-3, 3, 2),
               param_values(model, rng), rng.uniform(-5, 5, 2))


def test_coordinates_and_parameters(model):
    assert [s.name for s in model.q] == ["theta1", "theta2"]
    assert [s.name for s in model.qd] == ["theta1_dot", "theta2_dot"]
    assert [p.symbol.name for p in model.parameters] == ["m1", "m2", "l1", "l2", "g"]


def test_mass_matrix_symbolic(model, derivation, oracle):
    expected = to_model(oracle.plain(oracle.mass_matrix), model)
    assert sp.simplify(sp.Matrix(derivation.mass_matrix) - expected) == sp.zeros(2, 2)


def test_forcing_symbolic(model, derivation, oracle):
    expected = to_model(oracle.plain(oracle.forcing), model)
    assert sp.simplify(sp.Matrix(derivation.forcing) - expected) == sp.zeros(2, 1)


def test_equations_lhs_match_lagranges_method(model, derivation, oracle):
    eom = to_model(oracle.plain(oracle.extras["eom"]), model)
    assert [e.coordinate for e in derivation.equations] == list(model.q)
    for eq, expected in zip(derivation.equations, eom):
        assert sp.simplify(eq.lhs - expected) == 0
        assert sp.simplify(eq.rhs) == 0


@pytest.mark.parametrize("make_oracle", [double_pendulum_lagrange, lambda: planar_chain_kane(2)],
                         ids=["lagrange", "kane"])
def test_numeric_at_random_states(model, derivation, make_oracle):
    oracle = make_oracle()
    lag = lambdify_model(model, derivation.mass_matrix, derivation.forcing,
                         sp.Matrix([e.lhs for e in derivation.equations]))
    ref = lambdify_oracle(oracle, model, oracle.mass_matrix, oracle.forcing)
    for q, qd, p, qdd in random_states(model, seed=1):
        M, F, lhs = lag(q, qd, p, qdd)
        M0, F0 = ref(q, qd, p)
        assert_close(M, M0, what="mass matrix")
        assert_close(F, F0, what="forcing")
        assert_close(np.linalg.solve(M, F), np.linalg.solve(M0, F0), what="q''")
        # lhs = M q'' - F for an unconstrained system
        assert_close(lhs.ravel(), (M0 @ qdd - F0.ravel()), what="equation lhs")


def test_energy_and_jacobi(model, derivation, oracle):
    lag = lambdify_model(model, derivation.energy)
    ref = lambdify_oracle(oracle, model, oracle.extras["energy"])
    for q, qd, p, _ in random_states(model, seed=2):
        assert_close(lag(q, qd, p)[0], ref(q, qd, p)[0], what="T + V")
    assert derivation.jacobi_integral is not None
    assert derivation.energy_is_jacobi
    assert sp.simplify(derivation.jacobi_integral - derivation.energy) == 0
    assert derivation.ignorable == ()
    assert derivation.scleronomic
