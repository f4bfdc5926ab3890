"""Conserved quantities (CONTRACT §1 "Conserved quantities").

- q_s is ignorable when dL/dq_s = 0, Q'_s = 0 and no constraint row involves
  q_s or q_s'; then p_s = dL/dq_s' = (M q' + a)_s is conserved.
- The Jacobi integral h = T2 - T0 + V exists when dL/dt = 0, Q' = 0 and every
  constraint row has a independent of t and d = 0.

L = 1/2 q'^T M q' + a.q' + (T0 - V) is independent of a symbol exactly when each
of M, a and T0 - V is (they are its homogeneous parts in q'), so the checks
probe those, smallest first. They are numeric (`DependenceProbe`) because a
prescribed rotation W t often cancels out of L only after trigonometric
simplification (bead on a spinning hoop). When L has no explicit t, h = T2 - T0 + V
has none either, so it is reported with t set to 0.
"""
from __future__ import annotations

import sympy as sp

from lagcli.calculus import DependenceProbe, depends_on, numerically_zero
from lagcli.derive.result import Conserved


class LagrangianProbe:
    """Does L depend on a symbol? Probes T0 - V, then a, then M (each compiled once, lazily)."""

    def __init__(self, M, a, T0, V):
        n = M.rows
        self.groups = [[T0 - V], list(a), [M[i, j] for i in range(n) for j in range(i, n)]]
        self.probes: list[DependenceProbe | None] = [None] * len(self.groups)

    def depends_on(self, symbol: sp.Symbol) -> bool:
        for k, group in enumerate(self.groups):
            if not any(depends_on(e, (symbol,)) for e in group):
                continue
            if self.probes[k] is None:
                self.probes[k] = DependenceProbe(group)
            if self.probes[k].depends_on(symbol):
                return True
        return False


def ignorable_coordinates(model, probe: LagrangianProbe, Q_applied, rows) -> tuple[sp.Symbol, ...]:
    result = []
    for s, qs in enumerate(model.q):
        if not numerically_zero([Q_applied[s]]) or any(depends_on(r.expr, (qs, model.qd[s])) for r in rows):
            continue
        if not probe.depends_on(qs):
            result.append(qs)
    return tuple(result)


def jacobi_integral(model, probe: LagrangianProbe, T2, T0, V, Q_applied, rows) -> sp.Expr | None:
    if not numerically_zero(list(Q_applied)):
        return None
    t = model.t
    for row in rows:
        if any(depends_on(ak, (t,)) for ak in row.a) and not numerically_zero([ak.diff(t) for ak in row.a]):
            return None
        if row.d != 0 and not numerically_zero([row.d]):
            return None
    if probe.depends_on(t):
        return None
    h = T2 - T0 + V
    return h.subs(t, 0) if depends_on(h, (t,)) else h


def conserved_quantities(model, ignorable, momenta, h, energy_is_jacobi):
    found = [Conserved(f"p_{qs.name}", "momentum", p) for qs, p in zip(ignorable, momenta)]
    if h is not None:
        found.append(Conserved("jacobi", "jacobi", h))
        if energy_is_jacobi:
            found.append(Conserved("energy", "energy", h))
    return tuple(found)
