"""The explicit form of Lagrange's equations (seed notes, section 6.6):

    M q'' + c + M_t q' + gamma q' + a_t + (dV/dq - dT0/dq) = Q'
    c_i     = sum_j (sum_l dM_ij/dq_l q'_l) q'_j - 1/2 q'^T (dM/dq_i) q'
              (= sum_jl 1/2 (dM_ij/dq_l + dM_il/dq_j - dM_jl/dq_i) q'_j q'_l)
    gamma_ij = da_i/dq_j - da_j/dq_i
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagcli.derive.energy import Energies
from lagcli.model_types import Model


@dataclass(frozen=True)
class ExplicitForm:
    velocity_terms: sp.ImmutableMatrix
    mass_rate_terms: sp.ImmutableMatrix
    gyroscopic_matrix: sp.ImmutableMatrix
    t1_rate_terms: sp.ImmutableMatrix
    position_terms: sp.ImmutableMatrix
    mass_derivatives: tuple[sp.ImmutableMatrix, ...]  # dM/dq_l, reused for invariants


def explicit_form(model: Model, e: Energies) -> ExplicitForm:
    q, qd, t = model.q, sp.Matrix(model.qd), model.t
    n = len(q)
    M, a = e.mass_matrix, e.t1_coefficients
    dM = tuple(M.diff(ql) for ql in q)
    M_dot = sp.zeros(n, n)
    for dM_l, qd_l in zip(dM, qd):
        M_dot += dM_l * qd_l
    c = M_dot * qd - sp.Matrix([(qd.T * dM_i * qd)[0] / 2 for dM_i in dM])
    gamma = sp.Matrix(n, n, lambda i, j: a[i].diff(q[j]) - a[j].diff(q[i]) if i != j else 0)
    position = sp.Matrix([e.V.diff(qi) - e.T0.diff(qi) for qi in q])
    return ExplicitForm(
        velocity_terms=sp.ImmutableMatrix(c),
        mass_rate_terms=sp.ImmutableMatrix(M.diff(t) * qd),
        gyroscopic_matrix=sp.ImmutableMatrix(gamma),
        t1_rate_terms=sp.ImmutableMatrix(a.diff(t)),
        position_terms=sp.ImmutableMatrix(position),
        mass_derivatives=dM,
    )


def forcing(form: ExplicitForm, Q_applied: sp.ImmutableMatrix, qd) -> sp.ImmutableMatrix:
    """F such that M q'' = F (+ A^T lambda)."""
    qd = sp.Matrix(qd)
    return sp.ImmutableMatrix(Q_applied - form.velocity_terms - form.mass_rate_terms
                              - form.gyroscopic_matrix * qd - form.t1_rate_terms - form.position_terms)
