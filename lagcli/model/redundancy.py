"""Constraint rows that repeat the others: found numerically and dropped with a note.

Two wheels on one axle each roll without sideways slip: their two sideways rows say
the same thing (the axle does not slide sideways). Kept, they make the constraint
matrix A rank-deficient: the DOF count is one too low and the augmented system
[M -A^T; A 0] singular at every state, so a simulation fails at t = 0.

Each row j is written as [a_j | d_j] (a_j . q' + d_j = 0: a nonholonomic row's
velocity coefficients, or a holonomic row's gradient and dphi/dt). A row is dependent
when it adds no rank to the rows kept before it at every one of RANDOM_STATES seeded
random states (q, q', t in [-1, 1], the parameters at their values): a dependence at
every state tried holds identically, not by chance. Such a row is dropped and a warning
names it; the first of a set of equal rows is kept.
"""
from __future__ import annotations

import math
import random

import sympy as sp

from lagcli.errors import Problem, warn_spec
from lagcli.model.constants import ConstantError, value_at

RANDOM_STATES = 3
SEED = 20251125
RANK_TOLERANCE = 1e-9     # relative to the largest singular value


def independent_rows(constraints, q, qd, t, parameters: dict, source: str) -> tuple:
    """`constraints` without the rows that depend on earlier ones (a warning for each)."""
    if len(constraints) < 2:
        return tuple(constraints)
    rows = [_row(c.expr, q, qd, t) for c in constraints]
    rng = random.Random(SEED)
    states = [{**parameters, **{s: rng.uniform(-1.0, 1.0) for s in (*q, *qd, t)}} for _ in range(RANDOM_STATES)]
    numbers = [[_numbers(row, state) for row in rows] for state in states]
    kept: list[int] = []
    for j, constraint in enumerate(constraints):
        if kept and all(_adds_nothing(values, kept, j) for values in numbers):
            label = constraint.label or f"constraints[{j}]"
            warn_spec(Problem(constraint.loc or _source_loc(source),
                              f"the constraint row '{label}' repeats what the rows before it say (a combination "
                              "of them at every state tried): it is dropped",
                              "two elements that impose the same condition (two wheels on one axle both "
                              "forbid the axle's sideways slip) need it only once"))
            continue
        kept.append(j)
    return tuple(constraints[j] for j in kept)


def _row(expr: sp.Expr, q, qd, t) -> list[sp.Expr]:
    if expr.has(*qd):
        a = [expr.diff(v) for v in qd]
        return [*a, expr - sum(ak * v for ak, v in zip(a, qd))]
    return [*(expr.diff(s) for s in q), expr.diff(t)]


def _numbers(row, state) -> list[float] | None:
    try:
        numbers = [value_at(entry, state, {}) for entry in row]
    except (ConstantError, TypeError, ValueError, ArithmeticError):
        return None
    return numbers if all(math.isfinite(v) for v in numbers) else None


def _adds_nothing(values, kept: list[int], j: int) -> bool:
    """Row j lies in the span of the kept rows here (False when a row cannot be evaluated)."""
    import numpy as np

    if values[j] is None or any(values[k] is None for k in kept):
        return False
    before = np.array([values[k] for k in kept], dtype=float)
    with_j = np.vstack([before, np.array(values[j], dtype=float)])
    return _rank(with_j) == _rank(before)


def _rank(matrix) -> int:
    import numpy as np

    s = np.linalg.svd(matrix, compute_uv=False)
    return int(np.sum(s > RANK_TOLERANCE * max(s[0], 1e-300))) if s.size else 0


def _source_loc(source: str):
    from lagcli.errors import Loc

    return Loc(source)
