"""The right-hand side F of M q'' = F (+ A^T lambda), from accelerations.

Lagrange's operator applied to T equals the generalized inertia force (lecture notes, 6.6):

    d/dt(dT/dq'_j) - dT/dq_j = sum_points m r'' . dr/dq_j
                               + sum_bodies dw/dq'_j . (I w' + w x I w)     (w in body axes)

so with r'' = J q'' + r''_0 (r''_0 = r'' at q'' = 0, and likewise w'_0):

    F = Q' - dV/dq - sum m J^T r''_0 - sum J_w^T (I w'_0 + w x I w) - K-terms

This is Kane's form of the same equations: each row is a short sum over points,
which is both faster to derive and cheaper to evaluate than the Christoffel form
(`explicit.py`, kept for reports; the tests check both agree). The extra `kinetic:`
energy K has no points, so its terms come from Lagrange's operator directly.

A `Derivation` computes F, the equations' left-hand sides M q'' - F and the total
generalized forces Q' - dV/dq from its M, V and Q' on first use (lagcli/derive/result.py):
the functions here take those, not the derivation's intermediate values.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.calculus import TimeDerivative, almost_everywhere, derivative, gradient, jacobian_columns
from lagcli.derive.energy import body_angular_velocity, nonzero_rows
from lagcli.model.model_types import Model
from lagcli.model.products import product
from lagcli.model.sums import negated_terms, negative, total

_ZERO = sp.S.Zero     # 0 * y is 0 (y is finite): the z components of a planar model skipped


def potential_gradient(model: Model, V: sp.Expr) -> list[sp.Expr]:
    """dV/dq_i, one per coordinate."""
    return gradient(V, model.q, {}, {})


def forcing(model: Model, Q_applied: sp.ImmutableMatrix, dV: list) -> sp.ImmutableMatrix:
    """F of M q'' = F, from the applied forces Q' and the gradient dV of V."""
    D = TimeDerivative(model.t, model.q, model.qd, model.qdd)
    q, qd, n = model.q, model.qd, len(model.q)
    terms = [[Q_applied[i], *negated_terms(dV[i])] for i in range(n)]   # each F_i summed (sorted) once
    for mass, r in model.mass_points:
        acceleration = D.matrix(D.matrix(r), accelerations=False)
        _subtract(terms, jacobian_columns(r, q, D.free, D.partials), acceleration, mass)
    for body in model.bodies:
        omega = body_angular_velocity(body, D)
        spin = D.matrix(omega, accelerations=False)
        inertia_torque = body.inertia * spin + omega.cross(body.inertia * omega)
        _subtract(terms, jacobian_columns(omega, qd, D.free), inertia_torque, 1)
    if model.kinetic != 0:
        K = model.kinetic
        for i, (qi, v) in enumerate(zip(q, qd)):
            terms[i].append(-(D(derivative(K, v), accelerations=False) - derivative(K, qi)))
    return almost_everywhere(sp.ImmutableMatrix(n, 1, [total(row) for row in terms]))


def equation_lhs(M: sp.MatrixBase, F: sp.MatrixBase, qdd) -> list[sp.Expr]:
    """M q'' - F, row by row, as sympy's `-` builds it (Add(a, -b)), each row's terms sorted
    once (`negated_terms`)."""
    return [total([*(product(M_ij, qdd[j]) for j, M_ij in row), *negated_terms(F_i)])
            for row, F_i in zip(nonzero_rows(M), F)]


def total_generalized_forces(Q_applied: sp.MatrixBase, dV: list) -> sp.ImmutableMatrix:
    """Q' - dV/dq: the total generalized forces by virtual work."""
    return almost_everywhere(sp.Matrix(len(dV), 1, [total([Q, negative(dV_i)]) for Q, dV_i in zip(Q_applied, dV)]))


def _subtract(terms, J, vector, mass) -> None:
    """terms_i += -mass * (J^T vector)_i, J given by its nonzero columns (`jacobian_columns`)."""
    vector = tuple(vector)
    for i, column in J:
        entry = total([product(x, y) for x, y in zip(column, vector) if x is not _ZERO and y is not _ZERO])
        if entry != 0:
            terms[i].append(-product(mass, entry))
