"""The explicit form of Lagrange's equations (lecture notes, section 6.6), term by term:

    M q'' + c + M_t q' + gamma q' + a_t + (dV/dq - dT0/dq) = Q'
    c_i     = sum_j (sum_l dM_ij/dq_l q'_l) q'_j - 1/2 q'^T (dM/dq_i) q'
              (= sum_jl 1/2 (dM_ij/dq_l + dM_il/dq_j - dM_jl/dq_i) q'_j q'_l)
    gamma_ij = da_i/dq_j - da_j/dq_i

These named terms are for reports; the numerics use `forcing.py`, and the tests
check that both give the same F.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagcli.model.calculus import almost_everywhere
from lagcli.model.model_types import Model


@dataclass(frozen=True)
class ExplicitForm:
    velocity_terms: sp.ImmutableMatrix
    mass_rate_terms: sp.ImmutableMatrix
    gyroscopic_matrix: sp.ImmutableMatrix
    t1_rate_terms: sp.ImmutableMatrix
    position_terms: sp.ImmutableMatrix


def explicit_form(model: Model, M, a, T0, V) -> ExplicitForm:
    q, qd, t = model.q, sp.Matrix(model.qd), model.t
    n = len(q)
    dM = [M.diff(ql) for ql in q]
    M_dot = sp.zeros(n, n)
    for dM_l, qd_l in zip(dM, qd):
        M_dot += dM_l * qd_l
    c = M_dot * qd - sp.Matrix([(qd.T * dM_i * qd)[0] / 2 for dM_i in dM])
    gamma = sp.Matrix(n, n, lambda i, j: a[i].diff(q[j]) - a[j].diff(q[i]) if i != j else 0)
    return ExplicitForm(
        velocity_terms=almost_everywhere(c),
        mass_rate_terms=almost_everywhere(M.diff(t) * qd),
        gyroscopic_matrix=almost_everywhere(gamma),
        t1_rate_terms=almost_everywhere(a.diff(t)),
        position_terms=almost_everywhere(sp.Matrix([V.diff(qi) - T0.diff(qi) for qi in q])),
    )
