"""Kinetic and potential energy, split as T = 1/2 q'^T M q' + a^T q' + T0.

For each point with position r(q, t) (particle or centre of mass) and each
body angular velocity w = J_w q' + w_t (body axes):

    M  += m J^T J + J_w^T I J_w          J = dr/dq
    a  += m J^T r_t + J_w^T I w_t        r_t = dr/dt
    T0 += 1/2 m r_t.r_t + 1/2 w_t^T I w_t

This is the notes' construction (section 6.6) and avoids differentiating T twice.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import sympy as sp

from lagcli.calculus import TimeDerivative, almost_everywhere
from lagcli.model_types import Model, RigidBody, elementary_rotation

AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class Energies:
    mass_matrix: sp.ImmutableMatrix
    t1_coefficients: sp.ImmutableMatrix
    T0: sp.Expr
    V: sp.Expr


@functools.lru_cache(maxsize=256)  # energy, forcing and torques all need it, per derivation
def body_angular_velocity(body: RigidBody, D: TimeDerivative) -> sp.ImmutableMatrix:
    """Angular velocity in body axes for successive body-fixed rotations R = R1 R2 ... Rk:
    w_body = sum_i (R_{i+1} ... R_k)^T e_i  d(angle_i)/dt, accumulated as w <- R_i^T w + e_i angle_i'."""
    omega = sp.zeros(3, 1)
    for axis, angle in body.rotations:
        unit = sp.zeros(3, 1)
        unit[AXES[axis]] = 1
        omega = elementary_rotation(axis, angle).T * omega + unit * D(angle)
    return sp.ImmutableMatrix(omega)


def kinetic_parts(model: Model, D: TimeDerivative) -> tuple[sp.Matrix, sp.Matrix, sp.Expr]:
    n = len(model.q)
    M, a, T0 = sp.zeros(n, n), sp.zeros(n, 1), sp.S.Zero
    q, t = sp.Matrix(model.q), model.t
    for mass, r in model.mass_points:
        J, r_t = r.jacobian(q), r.diff(t)
        M += mass * (J.T * J)
        a += mass * (J.T * r_t)
        T0 += mass * r_t.dot(r_t) / 2
    for body in model.bodies:
        omega = body_angular_velocity(body, D)
        J_w = omega.jacobian(sp.Matrix(model.qd))
        w_t = omega.subs({v: 0 for v in model.qd})
        I_J = body.inertia * J_w
        M += J_w.T * I_J
        a += I_J.T * w_t
        T0 += (w_t.T * body.inertia * w_t)[0] / 2
    extra_M, extra_a, extra_T0 = _split_extra_kinetic(model)
    return M + extra_M, a + extra_a, T0 + extra_T0


def _split_extra_kinetic(model: Model):
    """The `kinetic:` term, split by degree in q' (the model checked it is at most quadratic)."""
    K, qd = model.kinetic, sp.Matrix(model.qd)
    if K == 0:  # the usual case: skip n^2 substitutions into zeros
        return sp.zeros(len(qd), len(qd)), sp.zeros(len(qd), 1), sp.S.Zero
    zero = {v: 0 for v in model.qd}
    M = sp.hessian(K, qd)
    a = sp.Matrix([K.diff(v).subs(zero) for v in qd])
    return M.subs(zero), a, K.subs(zero)


def potential_energy(model: Model) -> sp.Expr:
    """V = -sum m g.r (gravity) + sum 1/2 k (|r_a - r_b| - L0)^2 + potential."""
    V = model.potential
    if model.gravity is not None:
        for mass, r in model.mass_points:
            V -= mass * model.gravity.dot(r)
    for spring in model.springs:
        delta = spring.end_a - spring.end_b
        squared = delta.dot(delta)
        stretch = sp.sqrt(squared) - spring.rest_length if spring.rest_length != 0 else None
        V += spring.stiffness * (stretch ** 2 if stretch is not None else squared) / 2
    return V


def energies(model: Model, D: TimeDerivative) -> Energies:
    M, a, T0 = kinetic_parts(model, D)
    return Energies(almost_everywhere(M), almost_everywhere(a), almost_everywhere(T0), potential_energy(model))
