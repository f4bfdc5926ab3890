"""Points of rest in closed form: the equations at rest solved by elimination, in bounded work.

sympy's `solve` on a coupled system has no work budget of its own (on the two coupled
equations of the notes' Ex. 20 it ran for minutes). Here the equations are split by
their factors (`factor_terms`) and solved one factor, for one unknown, at a time, the
solution substituted into the rest, branch by branch:

    Cartesian pendulum:  2 lambda x = 0,  2 lambda y + m g = 0,  x^2 + y^2 - l^2 = 0
      lambda = 0   ->  m g = 0: no solution on this branch
      x = 0        ->  y = l | y = -l  ->  lambda = -m g/(2 y)

An equation is taken up when each of its factors either has one unknown (handed to
sympy's `solve`, when it has at most `FACTOR_OPS` operations) or is linear in one
unknown with a coefficient free of the unknowns; equations in one unknown first.
A factor linear with a coefficient that depends on other unknowns is taken last, and
then the elimination is no longer `complete` (the coefficient's zeros are not
examined). Budgets, all counts: `SOLVES` calls of `solve`, `BRANCHES` branches,
`EQUATION_OPS` operations of an equation after substitution. When one is hit, or no
equation can be taken up, that branch is given up (the numeric search still runs) and
the result is not complete. An equation that becomes a number is checked at the
parameters' values: not zero, the branch has no solution. A complete elimination that
finds nothing proves there is no point of rest.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

FACTOR_OPS = 80           # count_ops of a factor handed to solve
EQUATION_OPS = 400        # count_ops of an equation after substitution
TOTAL_OPS = 2000          # count_ops of all equations at the start
SOLVES = 32               # calls of solve in one elimination
BRANCHES = 64             # branches of one elimination
ZERO = 1e-12              # |value| of a number-only equation that counts as 0 (relative to its terms)


@dataclass
class Elimination:
    """Solutions {unknown: expression} (an unknown missing: free, a family) and whether every
    branch was finished."""

    solutions: list = field(default_factory=list)
    complete: bool = True
    solves: int = SOLVES
    branches: int = BRANCHES


def eliminate(equations, unknowns, numbers: dict) -> Elimination:
    """Solve `equations` = 0 for `unknowns` (module docstring); `numbers`: {parameter: value}."""
    result = Elimination()
    equations = [sp.sympify(e) for e in equations]
    if sum(sp.count_ops(e) for e in equations) > TOTAL_OPS:
        result.complete = False
        return result
    _branch(equations, {}, list(unknowns), numbers, result)
    return result


def _branch(equations, solved: dict, unknowns, numbers, result: Elimination) -> None:
    result.branches -= 1
    if result.branches < 0:
        result.complete = False
        return
    left = []
    for e in equations:
        e = sp.factor_terms(e.xreplace(solved))
        if not e.free_symbols & set(unknowns):
            if _nonzero(e, numbers):
                return                                    # no solution on this branch
            continue
        if sp.count_ops(e) > EQUATION_OPS:
            result.complete = False
            return
        left.append(e)
    if not left:
        result.solutions.append(solved)
        return
    choice = _choose(left, unknowns, numbers)
    if choice is None:
        result.complete = False
        return
    k, plan, exact = choice
    result.complete &= exact
    rest = left[:k] + left[k + 1:]
    for factor, unknown in plan:
        values = _solve(factor, unknown, numbers, result)
        if values is None:
            result.complete = False
            continue
        for v in values:
            step = {unknown: v}
            _branch(rest, {u: x.xreplace(step) for u, x in solved.items()} | step, unknowns, numbers, result)


def _choose(equations, unknowns, numbers):
    """(index, [(factor, unknown)...], exact) of the equation to take up next, or None."""
    best = None
    for k, e in enumerate(equations):
        plan, rank = [], 0
        for factor in sp.Mul.make_args(e):
            inside = [u for u in unknowns if factor.has(u)]
            if not inside:
                if not _nonzero(factor, numbers):
                    return k, [], True                    # holds identically at these values
                continue
            if len(inside) == 1:
                plan.append((factor, inside[0]))
                continue
            linear = _linear_in(factor, inside, unknowns, numbers)
            if linear is None:
                break
            plan.append((factor, linear[0]))
            rank = max(rank, 1 if linear[1] else 2)
        else:
            key = (rank, len(plan), k)
            if best is None or key < best[0]:
                best = (key, k, plan, rank < 2)
    return None if best is None else best[1:]


def _linear_in(factor, inside, unknowns, numbers):
    """(unknown, coefficient is a nonzero number) for the first unknown `factor` is linear in."""
    found = None
    for u in inside:
        d = factor.diff(u)
        if d.has(u):
            continue
        constant = not d.free_symbols & set(unknowns)
        if constant and not _nonzero(d, numbers):
            continue
        if constant:
            return u, True
        found = found or (u, False)
    return found


def _solve(factor, unknown, numbers, result: Elimination):
    """The values of `unknown` that make `factor` zero, or None beyond the budget."""
    d = factor.diff(unknown)
    if not d.has(unknown):
        return [sp.cancel(-factor.xreplace({unknown: 0}) / d)]
    if sp.count_ops(factor) > FACTOR_OPS or result.solves <= 0:
        return None
    result.solves -= 1
    try:
        return sp.solve(factor, unknown)
    except (NotImplementedError, ValueError):
        return None


def _nonzero(e, numbers) -> bool:
    """The number-only expression `e` is not 0 at the parameters' values."""
    value = complex(sp.sympify(e).xreplace(numbers).evalf(30))
    scale = max(abs(complex(a.xreplace(numbers).evalf(30))) for a in sp.Add.make_args(sp.expand(e)))
    return abs(value) > ZERO * scale
