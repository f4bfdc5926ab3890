"""Conserved quantities (CONTRACT §1 "Conserved quantities").

- q_s is ignorable when dL/dq_s = 0, Q'_s = 0 and no constraint row involves
  q_s or q_s'; then p_s = dL/dq_s' = (M q' + a)_s is conserved.
- The Jacobi integral h = T2 - T0 + V exists when dL/dt = 0, Q' = 0 and every
  constraint row has a independent of t and d = 0. "dL/dt = 0" is decided at
  random points, because a prescribed rotation W t often cancels out of L only
  after trigonometric simplification (bead on a spinning hoop). When L has no
  explicit t, neither have T2 and T0 - V (each is a homogeneous part of L in q'),
  so h is reported with t set to 0.
"""
from __future__ import annotations

import sympy as sp

from lagcli.calculus import depends_on, numerically_zero
from lagcli.derive.result import Conserved


def ignorable_coordinates(model, energies, dM, Q_applied, rows) -> tuple[sp.Symbol, ...]:
    qd = sp.Matrix(model.qd)
    result = []
    for s, (qs, dM_s) in enumerate(zip(model.q, dM)):
        if Q_applied[s] != 0 or any(depends_on(r.expr, (qs, model.qd[s])) for r in rows):
            continue
        dL = ((qd.T * dM_s * qd)[0] / 2 + energies.t1_coefficients.diff(qs).dot(qd)
              + energies.T0.diff(qs) - energies.V.diff(qs))
        if numerically_zero([dL]):
            result.append(qs)
    return tuple(result)


def jacobi_integral(model, T2, T0, V, L, Q_applied, rows) -> sp.Expr | None:
    if any(e != 0 for e in Q_applied):
        return None
    t = model.t
    for row in rows:
        if any(depends_on(ak, (t,)) for ak in row.a) and not numerically_zero([ak.diff(t) for ak in row.a]):
            return None
        if row.d != 0 and not numerically_zero([row.d]):
            return None
    if depends_on(L, (t,)) and not numerically_zero([L.diff(t)]):
        return None
    h = T2 - T0 + V
    return h.subs(t, 0) if depends_on(h, (t,)) else h


def conserved_quantities(model, ignorable, momenta, h, energy_is_jacobi) -> tuple[Conserved, ...]:
    found = [Conserved(f"p_{qs.name}", "momentum", p) for qs, p in zip(ignorable, momenta)]
    if h is not None:
        found.append(Conserved("jacobi", "jacobi", h))
        if energy_is_jacobi:
            found.append(Conserved("energy", "energy", h))
    return tuple(found)
