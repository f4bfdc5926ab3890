"""Symbolic A and B (`lagcli linearize --symbolic`) for small unconstrained systems.

x = (q, q'), q'' = f(q, q', u) = M^-1 F with M^-1 F formed by LU solve (only for at
most `MAX_COORDINATES` coordinates and M, F within `MAX_OPS` operations, so the work
is bounded by the expressions' size, not by a clock). The Jacobians are taken first
and the operating point substituted afterwards (no 0/0), then each entry is tidied
(`lagcli.derive.hamilton_form.tidy_fraction`, as Hamilton's form and the Routhian are;
trigsimp too when small).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagcli.errors import UsageError
from lagcli.analysis.linearize import input_symbols
from lagcli.derive.hamilton_form import tidy_fraction

MAX_COORDINATES = 3
MAX_OPS = 600
TIDY_OPS = 300


@dataclass(frozen=True)
class SymbolicLinear:
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    A: sp.ImmutableMatrix
    B: sp.ImmutableMatrix


def symbolic_linear(d, at, inputs=()) -> SymbolicLinear:
    model = d.model
    if d.constraints or len(model.q) > MAX_COORDINATES:
        raise UsageError(f"--symbolic: only for unconstrained systems of at most {MAX_COORDINATES} "
                         "coordinates; use the numeric output")
    M, F = sp.Matrix(d.mass_matrix), sp.Matrix(d.forcing)
    if sum(sp.count_ops(e) for e in (*M, *F)) > MAX_OPS:
        raise UsageError(f"--symbolic: the equations are too large (more than {MAX_OPS} operations); "
                         "use the numeric output")
    if at.sweep is not None:
        raise UsageError("--symbolic does not go with --sweep")
    u = list(input_symbols(model, inputs))
    f = M.LUsolve(F)
    n = len(model.q)
    top = sp.zeros(n, n).row_join(sp.eye(n))
    A = top.col_join(f.jacobian(list(model.q)).row_join(f.jacobian(list(model.qd))))
    B = sp.zeros(n, len(u)).col_join(f.jacobian(u)) if u else sp.zeros(2 * n, 0)
    point = {s: 0 for s in (*model.q, *model.qd)} | {model.t: 0}
    point.update({model.symbol(name): expr for name, expr in at.values.items()})
    return SymbolicLinear(tuple(s.name for s in (*model.q, *model.qd)), tuple(s.name for s in u),
                          _at(A, point), _at(B, point))


def _at(matrix: sp.Matrix, point: dict) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(matrix.shape[0], matrix.shape[1],
                              [_tidy(e.xreplace(point)) for e in matrix])


def _tidy(expr: sp.Expr) -> sp.Expr:
    """The shorter of the solved forms' tidying (`tidy_fraction`, as `lagcli hamiltonian`
    and `routh` print theirs) and trigsimp of the cancelled entry (when small)."""
    cancelled = sp.cancel(expr)
    candidates = [tidy_fraction(cancelled)]
    if sp.count_ops(cancelled) <= TIDY_OPS:
        candidates.append(sp.trigsimp(cancelled))
    return min(candidates, key=sp.count_ops)
