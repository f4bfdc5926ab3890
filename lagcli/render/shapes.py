"""Results remembered for an expression's *shape*: the expression with its symbols renamed in order.

A chain's report tidies hundreds of expressions that differ only in their symbols: the
mass matrix entry l3*l6*(m6 + ... + m40)*cos(q3 - q6) and l4*l7*(m7 + ... + m40)*cos(q4 - q7)
go through the same steps. sympy orders the arguments of a sum or product by comparing
symbols by their names (`Basic.compare`, `default_sort_key`: name strings, after the
assumptions' count), and lagcli's tidying steps compare them the same way (`trig_call`'s
leading symbol, `pull_signs`' leading term), never look at a name otherwise, and do not
depend on the hash seed (same spec -> same bytes). So renaming the symbols of an
expression to placeholders in the same name order, with the same assumptions, renames
every step's result the same way: f(rename(x)) = rename(f(x)). `Shapes` keeps f's result
for each renamed expression and renames it back for the next expression of that shape.

Only *plain* expressions have a shape: numbers, symbols with distinct names, sums,
products, powers, sin and cos. Anything else is computed as it is. Renaming rebuilds each
node with the arguments in their order (no re-sorting, no evaluation): the order is that
of the renamed expression built afresh, since the renaming keeps every comparison.
tests/test_shapes.py compares remembered results with direct ones.
"""
from __future__ import annotations

import functools
from collections.abc import Callable

import sympy as sp

from lagcli.model.angle_calls import TRIG, trig_node


class Shapes:
    """f's results (one pure, renaming-equivariant function f) by the shape of the argument.

    `marked`: symbols f treats apart (generated code's tidying collects over the
    velocities): which placeholders stand for one of them is part of the shape, so an
    expression is renamed only onto one with its marked symbols in the same places."""

    def __init__(self, function: Callable[[sp.Expr], sp.Expr], marked=frozenset()):
        self._function = function
        self._marked = frozenset(marked)
        self._results: dict = {}
        self._nodes: dict = {}      # every node renamed, itself: equal nodes are one object

    def __call__(self, expr: sp.Expr) -> sp.Expr:
        renaming = renamings(expr)
        if renaming is None:
            return self._function(expr)
        forward, back = renaming
        key = shape_key(expr, forward, {})
        if self._marked:
            key = (key, tuple(sorted(forward[s].name for s in forward.keys() & self._marked)))
        found = self._results.get(key)
        if found is not None:
            return renamed(found, back, self._nodes)
        result = self._function(expr)
        if _symbols_within(result, forward):
            self._results[key] = renamed(result, forward, self._nodes)
        return result


def shape_key(expr, rule: dict, memo: dict):
    """The renamed expr (`renamed(expr, rule, ...)`) as nested tuples (class, arguments'
    keys), symbols as their placeholders: equal exactly when the renamed expressions are
    (same classes, same arguments in the same order), without building the renamed nodes."""
    if expr.is_Symbol:
        return rule[expr]
    if expr.is_Number:
        return expr
    found = memo.get(expr)
    if found is None:
        found = memo[expr] = (expr.func, *(shape_key(a, rule, memo) for a in expr.args))
    return found


def renamings(expr: sp.Expr) -> tuple[dict, dict] | None:
    """({symbol: placeholder}, {placeholder: symbol}) with placeholders in the order of the
    symbols' names, each with its symbol's assumptions; None when expr is not plain."""
    symbols: set = set()
    if not _plain(expr, symbols, set()):
        return None
    ordered = sorted(symbols, key=lambda s: s.name)
    if len({s.name for s in ordered}) != len(ordered):
        return None          # one name with two sets of assumptions: compared by assumptions
    width = len(str(len(ordered)))
    forward = {s: _placeholder(f"${k:0{width}d}", s._assumptions0) for k, s in enumerate(ordered)}
    return forward, {placeholder: s for s, placeholder in forward.items()}


@functools.lru_cache(maxsize=None)
def _placeholder(name: str, assumptions: tuple) -> sp.Symbol:
    """The symbol `name` with these assumptions (a symbol's `_assumptions0`, the ones
    its comparisons use)."""
    return sp.Symbol(name, **dict(assumptions))


def renamed(expr: sp.Expr, rule: dict, nodes: dict, memo: dict | None = None) -> sp.Expr:
    """expr with its symbols replaced by `rule`, every node rebuilt with its arguments in
    their order (a plain expr: see the module docstring). `nodes` holds the nodes built
    so far, each returned again for an equal one: expressions that share parts are
    compared and looked up fast (an equal copy is compared node by node)."""
    if expr.is_Symbol:
        return rule[expr]
    if expr.is_Number:
        return expr
    memo = {} if memo is None else memo      # this renaming's results (parts repeat)
    found = memo.get(expr)
    if found is None:
        args = tuple(renamed(a, rule, nodes, memo) for a in expr.args)
        if expr.is_Add or expr.is_Mul:
            found = expr.func._from_args(args, expr.is_commutative)
        elif type(expr) in TRIG:
            found = trig_node(expr.func, args[0])
        else:
            found = expr.func(*args, evaluate=False)
        found = memo[expr] = nodes.setdefault(found, found)
    return found


def _plain(expr, symbols: set, seen: set) -> bool:
    if expr in seen:
        return True
    if type(expr) is sp.Symbol:
        symbols.add(expr)
    elif expr.is_Number:
        if not expr.is_Rational:
            return False
    elif expr.is_Add or expr.is_Mul or expr.is_Pow or type(expr) in TRIG:
        if not all(_plain(a, symbols, seen) for a in expr.args):
            return False
    else:
        return False
    seen.add(expr)
    return True


def _symbols_within(expr, rule: dict) -> bool:
    """expr is plain and every symbol in it is one `rule` renames."""
    symbols: set = set()
    return _plain(expr, symbols, set()) and symbols <= rule.keys()
