"""Tidying one expression before CSE: the cheapest of a few equivalent forms.

Only an optimisation of generated code (fewer operations at run time); every step
is bounded by the size of its input (operation counts, never a clock, so the same
spec gives the same code on any machine), and an expression no step improves stays
as it was.
"""
from __future__ import annotations

import sympy as sp

TIDY_MAX_OPS = 80             # trigsimp only expressions this small (bench/codegen.py: cost vs gain)
COLLECT_MAX_OPS = 5000        # expand + collect only expressions this small
MAX_POWER = 6                 # (a + b)**1000 counts as small, but expanding it would not be
MAX_EXPANDED_TERMS = 20000    # expand only what has at most this many terms once expanded
TRIGSIMP_FUNCTIONS = (sp.sin, sp.cos)   # trigsimp only expressions calling nothing else
PRINTABLE = (sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.atan2, sp.sinh, sp.cosh,
             sp.tanh, sp.exp, sp.log, sp.Abs, sp.sign, sp.Min, sp.Max)



def tidy_expression(expr, velocities=(), cache: dict | None = None) -> sp.Expr:
    """The cheapest (sympy.count_ops) of: expr; expr expanded and collected over the
    `velocities`, each coefficient collected over its function calls (the physical
    grouping of F = sum c_jk q'_j q'_k + c_j q'_j + c_0); and `factor_terms(trigsimp(.))`
    of the better of these two when it has at most TIDY_MAX_OPS operations and calls
    only sin and cos (`trigsimp_safe`). A candidate may not call a function expr does
    not already call: a new cos(q1 - q2) costs more at run time than the
    multiplications it saves. The steps are bounded by operation counts only (sympy's
    trigsimp can grind for minutes on tanh, Max or sign terms: `trigsimp_safe` keeps
    it to what it is fast on), and expressions with high powers are left alone."""
    expr = sp.sympify(expr)
    if cache is not None and expr in cache:
        return cache[expr]
    result = expr
    if not expr.is_Atom and expandable(expr) and sp.count_ops(expr) <= COLLECT_MAX_OPS:
        calls = expr.atoms(sp.Function)
        result = _cheaper(expr, _collected(expr, list(velocities)), calls)
        if sp.count_ops(result) <= TIDY_MAX_OPS and trigsimp_safe(result):
            simplified = sp.factor_terms(sp.trigsimp(result))
            result = _cheaper(result, simplified, calls)
    if cache is not None:
        cache[expr] = result
    return result


def trigsimp_safe(expr) -> bool:
    """True when expr is built from numbers, symbols, +, * and powers, and calls only
    sin and cos: what trigsimp is meant for (and fast on)."""
    for node in sp.preorder_traversal(expr):
        if node.is_Atom or node.is_Add or node.is_Mul or isinstance(node, TRIGSIMP_FUNCTIONS):
            continue
        if node.is_Pow and node.exp.is_Rational:
            continue
        return False
    return True


def has_high_power(expr) -> bool:
    """(a + b)**1000 counts as small, but expanding or trigsimp-ing it would not be."""
    return any(p.exp.is_Number and abs(p.exp) > MAX_POWER for p in expr.atoms(sp.Pow))


def expandable(expr) -> bool:
    """True when `sympy.expand(expr)` stays small: no high power and at most
    MAX_EXPANDED_TERMS terms by the bound `expanded_terms` (a product of ten sums of
    ten terms is small to write and 10**10 terms expanded)."""
    return not has_high_power(expr) and expanded_terms(expr) <= MAX_EXPANDED_TERMS


def expanded_terms(expr) -> int:
    """An upper bound on the number of terms of expr expanded (function arguments,
    which expand inside their call, count as one term each)."""
    if expr.is_Add:
        return sum(expanded_terms(a) for a in expr.args)
    if expr.is_Mul:
        count = 1
        for factor in expr.args:
            count *= expanded_terms(factor)
            if count > MAX_EXPANDED_TERMS:
                return count
        return count
    if expr.is_Pow and expr.exp.is_Integer and expr.exp > 1:
        return expanded_terms(expr.base) ** min(int(expr.exp), MAX_POWER + 1)
    return 1


def _collected(expr, velocities: list) -> sp.Expr:
    def by_calls(coefficient):
        calls = sorted(coefficient.atoms(sp.Function), key=sp.default_sort_key)
        return sp.factor_terms(sp.collect(coefficient, calls))

    return sp.collect(sp.expand(expr), velocities, func=by_calls)


def _cheaper(current, candidate, calls) -> sp.Expr:
    """candidate when it has fewer operations and calls only known functions among `calls`."""
    found = candidate.atoms(sp.Function)
    if found <= calls and all(isinstance(f, PRINTABLE) for f in found) \
            and sp.count_ops(candidate) < sp.count_ops(current):
        return candidate
    return current
