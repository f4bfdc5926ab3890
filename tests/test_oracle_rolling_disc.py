"""Rolling disc (specs/rolling_disc.yaml) against sympy.physics.mechanics.

Oracle (tests/oracles.py): KanesMethod with independent speeds (psi', theta', phi'),
dependent speeds (x', y') and the velocity constraints v_C . N.x = v_C . N.y = 0,
v_C from the two-point theorem on the contact point C = G - r A.z fixed in the
disc. The constraints are NOT substituted into T (that is wrong for this system).

lagcli solves, at a state consistent with the constraints,

    [ M  -A^T ] [ q''    ]   [ F               ]
    [ A   0   ] [ lambda ] = [ constraint_bias ]

Checked at seeded random consistent states: q'' against Kane's (1e-10 relative);
the multipliers are the horizontal ground force on the disc (the constraints are
written `x_dot - (...)`, `y_dot - (...)`, so a_x,x = a_y,y = 1 and the generalized
constraint forces on x, y are lambda_roll_x, lambda_roll_y): m x'' = lambda_roll_x,
m y'' = lambda_roll_y, and with the normal force m (z'' + g) they satisfy the
angular-momentum balance dH_G/dt = (C - G) x F_contact; the hand-derived
constraints equal the oracle's v_C; T + V is conserved and is the Jacobi integral.
"""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from oracles import (spec_fixtures, assert_close, lambdify_model, lambdify_oracle, param_values,
                     rolling_disc_kane, time_derivative, to_model)

SPEC = Path(__file__).resolve().parent.parent / "specs" / "rolling_disc.yaml"


model, derivation, oracle = spec_fixtures(SPEC, rolling_disc_kane)


@pytest.fixture(scope="module")
def lagcli_solve(model, derivation):
    """(q, qd, p) -> (q'', lambda) from lagcli's augmented system."""
    f = lambdify_model(model, derivation.mass_matrix, derivation.constraint_matrix,
                       derivation.forcing, derivation.constraint_bias)

    def solve(q, qd, p):
        M, A, F, b = f(q, qd, p)
        n, m = M.shape[0], A.shape[0]
        K = np.block([[M, -A.T], [A, np.zeros((m, m))]])
        sol = np.linalg.solve(K, np.concatenate([F.ravel(), b.ravel()]))
        return sol[:n], sol[n:]

    return solve


def consistent_states(model, oracle, seed, count=8):
    """Random q and (psi', theta', phi'); x', y' solved from the oracle's v_C = 0."""
    v = lambdify_oracle(oracle, model, sp.Matrix(oracle.extras["v_contact"][:2]))
    rng = np.random.default_rng(seed)
    for _ in range(count):
        q = np.array([*rng.uniform(-2, 2, 2), rng.uniform(-np.pi, np.pi),
                      rng.uniform(-1.2, 1.2), rng.uniform(-np.pi, np.pi)])
        qd = np.array([0.0, 0.0, *rng.uniform(-3, 3, 2), rng.uniform(-20, 20)])
        p = param_values(model, rng)
        qd[:2] = -v(q, qd, p)[0].ravel()     # v_C is x_dot (y_dot) + terms without them
        assert np.allclose(v(q, qd, p)[0], 0, atol=1e-12)
        yield q, qd, p


def test_constraints_as_written(model, derivation, oracle):
    """The hand-derived rolling constraints equal the oracle's v_C . N.x, v_C . N.y
    (and v_C . N.z vanishes identically)."""
    rows = derivation.constraints
    assert [c.label for c in rows] == ["roll_x", "roll_y"]
    assert [c.kind for c in rows] == ["nonholonomic", "nonholonomic"]
    assert [s.name for s in derivation.multipliers] == ["lambda_roll_x", "lambda_roll_y"]
    v_c = [to_model(oracle.plain(v), model) for v in oracle.extras["v_contact"]]
    assert sp.simplify(v_c[2]) == 0
    for row, expected in zip(rows, v_c[:2]):
        assert sp.simplify(row.expr - expected) == 0
        assert sp.simplify(row.d) == 0
        a = sp.Matrix([expected]).jacobian(model.qd)
        assert sp.simplify(sp.Matrix([row.a]) - a) == sp.zeros(1, 5)
    A = sp.Matrix(derivation.constraint_matrix)
    assert A.shape == (2, 5) and A[0, 0] == 1 and A[1, 1] == 1
    assert derivation.dof == 3


def test_accelerations_match_kane(model, derivation, oracle, lagcli_solve):
    ref = lambdify_oracle(oracle, model, oracle.mass_matrix, oracle.forcing)
    for q, qd, p in consistent_states(model, oracle, seed=21):
        qdd, _ = lagcli_solve(q, qd, p)
        M0, F0 = ref(q, qd, p)
        assert_close(qdd, np.linalg.solve(M0, F0.ravel()), what="q''")


def test_multipliers_are_the_ground_friction_force(model, derivation, oracle, lagcli_solve):
    m_index = [p.symbol.name for p in model.parameters].index("m")
    cm = [to_model(oracle.plain(c), model) for c in oracle.extras["cm"]]
    z_dd = time_derivative(time_derivative(cm[2], model), model)
    f = lambdify_oracle(oracle, model, sp.Matrix(oracle.extras["H_G_rate"]),
                        sp.Matrix(oracle.extras["r_GC"]))
    z_acc = lambdify_model(model, z_dd)
    g_index = [p.symbol.name for p in model.parameters].index("g")
    for q, qd, p in consistent_states(model, oracle, seed=22):
        qdd, lam = lagcli_solve(q, qd, p)
        mass = p[m_index]
        assert_close(lam, mass * qdd[:2], what="lambda = m (x'', y'')")
        normal = mass * (z_acc(q, qd, p, qdd)[0] + p[g_index])
        contact_force = np.array([*lam, normal])
        H_rate, r_gc = f(q, qd, p, qdd)
        assert_close(np.cross(r_gc.ravel(), contact_force), H_rate.ravel(),
                     what="dH_G/dt = (C - G) x F_contact")


def test_generalized_constraint_forces(model, derivation, oracle, lagcli_solve):
    """C_j = sum_k lambda_k a_kj equals M q'' - F (the A^T lambda of the solve)."""
    lam_syms = derivation.multipliers
    f = lambdify_model(model, derivation.mass_matrix, derivation.forcing,
                       derivation.constraint_matrix)
    for q, qd, p in consistent_states(model, oracle, seed=23, count=4):
        qdd, lam = lagcli_solve(q, qd, p)
        M, F, A = f(q, qd, p)
        C = sp.Matrix(derivation.generalized_constraint_forces)
        C_num = lambdify_model(model, C.subs(dict(zip(lam_syms, lam))))(q, qd, p)[0]
        assert_close(C_num.ravel(), M @ qdd - F.ravel(), what="generalized constraint forces")


def test_energy_is_conserved_jacobi_integral(model, derivation, oracle, lagcli_solve):
    assert derivation.ignorable == ()
    assert derivation.jacobi_integral is not None and derivation.energy_is_jacobi
    E = derivation.energy
    grad = sp.Matrix([E]).jacobian([*model.q, *model.qd])
    lag = lambdify_model(model, E, grad, derivation.jacobi_integral)
    ref = lambdify_oracle(oracle, model, oracle.extras["energy"])
    for q, qd, p in consistent_states(model, oracle, seed=24):
        value, dE, h = lag(q, qd, p)
        assert_close(value, ref(q, qd, p)[0], what="T + V")
        assert_close(h, value, what="Jacobi integral")
        qdd, _ = lagcli_solve(q, qd, p)
        rate = dE.ravel() @ np.concatenate([qd, qdd])
        assert abs(rate) <= 1e-10 * np.abs(dE).max() * np.abs(np.concatenate([qd, qdd])).max()
