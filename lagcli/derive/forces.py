"""Generalized forces by virtual work, and a potential for them when one exists.

    Q'_j = sum F . dr/dq_j + sum tau . dw/dq'_j + (generalized_forces)_j - dR/dq'_j
                                            (R: Rayleigh dissipation, derive/dissipation.py)
    Q_j  = Q'_j - dV/dq_j          (gravity, springs and `potential` live in V)
"""
from __future__ import annotations

import sympy as sp


from lagcli.model.calculus import TimeDerivative, depends_on, numerically_zero
from lagcli.derive.dissipation import dissipative_forces
from lagcli.derive.energy import body_angular_velocity
from lagcli.model.model_types import Model

MAX_OPS_FOR_POTENTIAL = 400  # beyond this, searching for a closed-form potential is not worth it


def applied_generalized_forces(model: Model, D: TimeDerivative) -> sp.ImmutableMatrix:
    q, qd = sp.Matrix(model.q), sp.Matrix(model.qd)
    Q = sp.Matrix(model.generalized_forces)
    bodies = {b.name: b for b in model.bodies}
    for force in model.forces:
        if force.force is not None and force.point is not None:
            Q += force.point.jacobian(q).T * force.force
        if force.torque is not None:
            body = bodies[force.body]
            omega = body.rotation * body_angular_velocity(body, D)
            Q += omega.jacobian(qd).T * force.torque
    Q += dissipative_forces(model, D)
    return sp.ImmutableMatrix(Q)


def find_potential(model: Model, Q: sp.ImmutableMatrix) -> tuple[bool, sp.Expr | None]:
    """(conservative, V') with Q = -dV'/dq, for forces depending on q only (lecture notes, Ex 18).

    Conservative means Q(q) with a symmetric Jacobian dQ_i/dq_j (tested at random
    points). V' is then built coordinate by coordinate, as in the notes:
    V' = -int Q_1 dq_1 + h(q_2, ...), and so on, and checked by differentiation.
    """
    if all(e == 0 for e in Q):
        return True, sp.S.Zero
    moving = {model.t, *model.qd, *model.qdd, *model.input_symbols}  # an input u(t) varies in time
    if any(depends_on(e, moving) for e in Q):
        return False, None
    n = len(model.q)
    asymmetry = [Q[i].diff(model.q[j]) - Q[j].diff(model.q[i]) for i in range(n) for j in range(i + 1, n)]
    if not numerically_zero(asymmetry):
        return False, None
    if sum(sp.count_ops(e) for e in Q) > MAX_OPS_FOR_POTENTIAL:
        return True, None
    return True, _integrate_potential(model.q, Q)


def _integrate_potential(q, Q) -> sp.Expr | None:
    """V' coordinate by coordinate with sympy's rule-based `manualintegrate` (a
    bounded search, unlike `integrate`'s Risch and Meijer-G fallbacks, so the same
    forces give the same answer in the same time everywhere); None when a part has
    no closed form by those rules."""
    from sympy.integrals.manualintegrate import manualintegrate   # only specs with Q' need it

    V = sp.S.Zero
    for j, qj in enumerate(q):
        remainder = sp.expand(-Q[j] - V.diff(qj))
        if numerically_zero([remainder]):
            continue
        part = manualintegrate(remainder, qj)
        if part.has(sp.Integral):
            return None
        V += part
    residual = [e + V.diff(qj) for e, qj in zip(Q, q)]
    return V if numerically_zero(residual) else None
