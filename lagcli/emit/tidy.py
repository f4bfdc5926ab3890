"""Tidying one expression before CSE: the cheapest of a few equivalent forms.

Only an optimisation of generated code (fewer operations at run time); every step
is bounded in size and time, and an expression no step improves stays as it was.
"""
from __future__ import annotations

import sympy as sp

from lagcli.calculus import TooSlow, time_limit

TIDY_MAX_OPS = 80             # trigsimp only expressions this small (bench/codegen.py: cost vs gain)
COLLECT_MAX_OPS = 5000        # expand + collect only expressions this small
TIDY_SECONDS = 2.0            # per tidy step; past it the expression stays as it was
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
    multiplications it saves. Each step gets TIDY_SECONDS (`lagcli.calculus.time_limit`);
    one that runs out leaves the expression as it was (tidying is only an optimisation:
    sympy's trigsimp can grind for minutes on tanh, Max or sign terms)."""
    expr = sp.sympify(expr)
    if cache is not None and expr in cache:
        return cache[expr]
    result = expr
    if not expr.is_Atom and sp.count_ops(expr) <= COLLECT_MAX_OPS:
        calls = expr.atoms(sp.Function)
        result = _cheaper(expr, _limited(_collected, expr, list(velocities)), calls)
        if sp.count_ops(result) <= TIDY_MAX_OPS and trigsimp_safe(result):
            simplified = _limited(lambda e: sp.factor_terms(sp.trigsimp(e)), result)
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


def _limited(step, expr, *args):
    """step(expr, *args) within TIDY_SECONDS, else expr unchanged."""
    try:
        with time_limit(TIDY_SECONDS):
            return step(expr, *args)
    except TooSlow:
        return expr


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
