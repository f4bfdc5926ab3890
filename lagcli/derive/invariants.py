"""Conserved quantities (docs/constraints.md, "Conservation with constraints").

- q_s is ignorable when dL/dq_s = 0, Q'_s = 0 and column s of the constraint
  matrix is identically zero (a row may still contain q_s itself, as sin(phi) in
  the lecture notes' Ex. 6-9); then Lagrange's equation for q_s reads
  d/dt(dL/dq_s') = Q'_s + sum_j lambda_j a_js = 0, so p_s = dL/dq_s' = (M q' + a)_s
  is conserved.
- The Jacobi integral h = T2 - T0 + V exists when dL/dt = 0, Q' = 0 and every
  constraint row has a independent of t and d = 0.

L = 1/2 q'^T M q' + a.q' + (T0 - V) is independent of a symbol exactly when each
of M, a and T0 - V is (they are its homogeneous parts in q'), so the checks
probe those, smallest first. They are numeric (`DependenceProbe`) because a
prescribed rotation W t often cancels out of L only after trigonometric
simplification (bead on a spinning hoop). When L has no explicit t, h = T2 - T0 + V
has none either, so it is reported with t set to 0.

Cost: the free symbols of each group are collected once, so deciding all n
coordinates is one pass over L plus a probe per coordinate that L mentions.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.calculus import DependenceProbe, depends_on, free_symbols, leaves, numerically_zero
from lagcli.derive.result import Conserved
from lagcli.model.sums import negated_terms, total


class LagrangianProbe:
    """Does L depend on a symbol? Probes T0 - V, then a, then M (each set up once, lazily)."""

    def __init__(self, M, a, T0, V):
        upper = [entry for (i, j), entry in sorted(M.todok().items()) if i <= j]
        self.groups = [[total([T0, *negated_terms(V)])], [e for e in a if e != 0], upper]     # T0 - V; M's last (`mentions`)
        self.memo: dict = {}     # free symbols of shared subexpressions, found once (the probes')
        self.names = [_symbols_of(group) for group in self.groups]
        self.probes: list[DependenceProbe | None] = [None] * len(self.groups)

    def mentions(self, symbol: sp.Symbol, *exprs) -> bool:
        """Is `symbol` among the free symbols of M (or more, `_symbols_of`) or of `exprs`
        (structurally, not probed)?"""
        return symbol in self.names[-1] or any(symbol in free_symbols(sp.sympify(e), self.memo) for e in exprs)

    def depends_on(self, symbol: sp.Symbol) -> bool:
        for k, group in enumerate(self.groups):
            if symbol not in self.names[k]:
                continue
            if self.probes[k] is None:
                self.probes[k] = DependenceProbe(group, free=self.memo)
            if self.probes[k].depends_on(symbol):
                return True
        return False


def _symbols_of(exprs) -> set:
    """The free symbols of `exprs`, or more: those of their leaves (a bound variable too),
    found in one walk that hashes only the leaves (`calculus.leaves`; remembering every
    subexpression's set of symbols cost most of the probe's set-up). More is safe: a
    symbol found here is then probed."""
    return set().union(*(leaf.free_symbols for leaf in leaves(*map(sp.sympify, exprs))))


def ignorable_coordinates(model, probe: LagrangianProbe, Q_applied, rows) -> tuple[sp.Symbol, ...]:
    """The q_s with dL/dq_s = 0, Q'_s = 0 and a zero column s in the constraint matrix."""
    return tuple(qs for s, qs in enumerate(model.q)
                 if _zero([Q_applied[s]]) and _zero([row.a[s] for row in rows])
                 and not probe.depends_on(qs))


def momenta(M, a, qd, ignorable, q) -> list[sp.Expr]:
    """p_s = dL/dq_s' = (M q' + a)_s of each ignorable q_s (M q' + a formed once)."""
    if not ignorable:
        return []
    p = M * sp.Matrix(qd) + a
    return [p[q.index(s)] for s in ignorable]


def _zero(exprs) -> bool:
    """Identically zero: structurally, else numerically."""
    exprs = [e for e in exprs if e != 0]
    return not exprs or numerically_zero(exprs)


def jacobi_integral(model, T2, T0, V, probe: LagrangianProbe) -> sp.Expr:
    """h = T2 - T0 + V (at t = 0 when an explicit t cancels out of L but not of h's form);
    conserved only when `jacobi_obstacle` finds nothing. h's symbols are among those of M
    (T2 = 1/2 q'^T M q'), the velocities, T0 and V, so t is looked for there (`probe`
    knows M's): walking h for it walked T2's n^2 products again. (When t is there but
    cancels out of h, the substitution finds none and returns h itself.)"""
    h = total([total([T2, -T0]), V])
    return h.subs(model.t, 0) if probe.mentions(model.t, T0, V) else h


def jacobi_obstacle(model, probe: LagrangianProbe, Q_applied, rows) -> str | None:
    """Why the Jacobi integral is not conserved, in words for the reports (None: it is):
    Q' not zero, a constraint with a time-dependent row or a d term, or L with an explicit t."""
    if not numerically_zero(list(Q_applied)):
        return "the non-conservative forces Q' are not zero"
    t = model.t
    for number, row in enumerate(rows, start=1):
        if any(depends_on(ak, (t,)) for ak in row.a) and not numerically_zero([ak.diff(t) for ak in row.a]):
            return f"the row a of constraint {number} depends on t"
        if row.d != 0 and not numerically_zero([row.d]):
            return f"constraint {number} has a term d free of velocities"
    if probe.depends_on(t):
        return "L depends explicitly on t"
    return None


def conserved_quantities(model, ignorable, momenta, h, energy_is_jacobi):
    found = [Conserved(f"p_{qs.name}", "momentum", p) for qs, p in zip(ignorable, momenta)]
    if h is not None:
        found.append(Conserved("jacobi", "jacobi", h))
        if energy_is_jacobi:
            found.append(Conserved("energy", "energy", h))
    return tuple(found)
