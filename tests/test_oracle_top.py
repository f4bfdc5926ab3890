"""Heavy symmetric top (specs/heavy_symmetric_top.yaml) against sympy.physics.mechanics.

Oracle (tests/oracles.py): KanesMethod with a ReferenceFrame oriented body-fixed
'ZXZ' by (psi, theta, phi), a RigidBody with central inertia (A, A, C) at h B.z,
gravity -m g N.z, u_i = q_i'. Checked: M, F and q'' = M^-1 F at seeded random
states (1e-10 relative); psi, phi ignorable; p_psi = H_O . N.z, p_phi = H_O . B.z
and the energy T + V match the oracle's angular momentum and energy, and the
Jacobi integral is the energy.
"""
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from oracles import spec_fixtures, assert_close, heavy_top_kane, lambdify_model, lambdify_oracle, param_values

SPEC = Path(__file__).resolve().parent.parent / "specs" / "heavy_symmetric_top.yaml"


model, derivation, oracle = spec_fixtures(SPEC, heavy_top_kane)


def random_states(model, seed, count=8):
    """Random states away from the Euler-angle singularity theta = 0, pi."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        q = np.array([rng.uniform(-np.pi, np.pi), rng.uniform(0.2, np.pi - 0.2),
                      rng.uniform(-np.pi, np.pi)])
        qd = np.array([rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-50, 50)])
        yield q, qd, param_values(model, rng)


def test_centre_of_mass_is_R_times_h_ez(model, oracle):
    """The spec's hand-written CM position equals the oracle's h B.z."""
    (top,) = model.bodies
    lag = lambdify_model(model, top.position)
    ref = lambdify_oracle(oracle, model, sp.Matrix(oracle.extras["cm"]))
    for q, qd, p in random_states(model, seed=3, count=4):
        assert_close(lag(q, qd, p)[0], ref(q, qd, p)[0], what="CM position")


def test_accelerations_match_kane(model, derivation, oracle):
    lag = lambdify_model(model, derivation.mass_matrix, derivation.forcing)
    ref = lambdify_oracle(oracle, model, oracle.mass_matrix, oracle.forcing)
    for q, qd, p in random_states(model, seed=11):
        M, F = lag(q, qd, p)
        M0, F0 = ref(q, qd, p)
        assert_close(M, M0, what="mass matrix")
        assert_close(F, F0, what="forcing")
        assert_close(np.linalg.solve(M, F), np.linalg.solve(M0, F0), what="q''")


def test_psi_and_phi_are_ignorable(model, derivation):
    psi, theta, phi = model.q
    assert derivation.ignorable == (psi, phi)
    assert {c.name for c in derivation.conserved if c.kind == "momentum"} == {"p_psi", "p_phi"}


def test_conserved_quantities_match_oracle(model, derivation, oracle):
    by_name = {c.name: c.expr for c in derivation.conserved}
    assert derivation.jacobi_integral is not None and derivation.energy_is_jacobi
    lag = lambdify_model(model, by_name["p_psi"], by_name["p_phi"], derivation.energy,
                         derivation.jacobi_integral)
    ref = lambdify_oracle(oracle, model, oracle.extras["p_psi"], oracle.extras["p_phi"],
                          oracle.extras["energy"])
    for q, qd, p in random_states(model, seed=12):
        p_psi, p_phi, E, h = lag(q, qd, p)
        p_psi0, p_phi0, E0 = ref(q, qd, p)
        assert_close(p_psi, p_psi0, what="p_psi (angular momentum about the vertical)")
        assert_close(p_phi, p_phi0, what="p_phi (angular momentum about the symmetry axis)")
        assert_close(E, E0, what="T + V")
        assert_close(h, E0, what="Jacobi integral")


def test_conserved_quantities_are_constant_along_the_motion(model, derivation):
    """d/dt of p_psi, p_phi and T + V vanish with q'' = M^-1 F (chain rule, numerically)."""
    by_name = {c.name: c.expr for c in derivation.conserved}
    exprs = [by_name["p_psi"], by_name["p_phi"], derivation.energy]
    grads = [sp.Matrix([e]).jacobian([*model.q, *model.qd]) for e in exprs]
    lag = lambdify_model(model, derivation.mass_matrix, derivation.forcing, *grads, *exprs)
    for q, qd, p in random_states(model, seed=13):
        M, F, *rest = lag(q, qd, p)
        qdd = np.linalg.solve(M, F.ravel())
        for grad, value in zip(rest[:3], rest[3:]):
            rate = grad.ravel() @ np.concatenate([qd, qdd])
            scale = max(abs(float(value)), np.abs(grad).max() * np.abs(np.concatenate([qd, qdd])).max())
            assert abs(rate) <= 1e-10 * scale
