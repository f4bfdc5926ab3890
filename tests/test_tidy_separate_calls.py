"""`separate_calls` (lagcli/render/tidy.py): a sum it recognises is one that display_form's
first steps give back unchanged, so `display_steps` skips them.

The oracle is those steps themselves, run with sympy's own `expand` (expand, the
Pythagorean identity, angle sums folded, terms grouped by their calls), on seeded random
sums of the recognised shape (rational numbers times symbols, their powers and one sin or
cos of a symbol, a different call in each term: the sums of a chain's potential) and of
shapes near it (a call repeated or squared, two calls in a term, a call of a sum, a sum
as a factor), which must not be recognised unless the steps leave them unchanged too;
and `display_steps`' result is compared with sympy's `factor_terms`, signs pulled out."""
from __future__ import annotations

import random

import pytest
import sympy as sp

from lagcli.render.operations import count_ops
from lagcli.render.tidy import (display_steps, fold_angle_sums, group_by_calls, pull_signs, pythagorean,
                                separate_calls)

NAMES = ["q1", "q2", "q10", "q39", "theta", "phi", "a", "Z", "x_b", "l1", "l2", "l10", "m", "g"]
NUMBERS = [1, 1, 1, -1, -1, 2, -3, sp.Rational(1, 2), -sp.Rational(3, 4)]


def _symbols(rng: random.Random, k: int) -> list[sp.Symbol]:
    kinds = [dict(real=True), dict(real=True), dict(positive=True), {}]
    return [sp.Symbol(name, **rng.choice(kinds)) for name in rng.sample(NAMES, k)]


def _term(rng: random.Random, call, pool: list) -> sp.Expr:
    factors = rng.sample(pool, rng.randint(1, min(3, len(pool))))
    return sp.Mul(rng.choice(NUMBERS), *(s ** rng.choice([1, 1, 2]) for s in factors), call)


def _separate(rng: random.Random) -> sp.Expr:
    symbols = _symbols(rng, 8)
    angles, pool = symbols[:4], symbols[4:]
    calls = rng.sample([f(x) for x in angles for f in (sp.sin, sp.cos)], rng.randint(2, 6))
    return sp.Add(*(_term(rng, call, pool) for call in calls))


def _near(rng: random.Random, expr: sp.Expr) -> sp.Expr:
    """expr with one term changed so that it is no longer of the recognised shape (mostly)."""
    x, y = sp.Symbol("u", real=True), sp.Symbol("v", real=True)
    term = expr.args[0]
    call = next(f for f in term.args if isinstance(f, (sp.sin, sp.cos)))
    other = expr.args[1]
    change = rng.choice([
        lambda: term * call,                                   # a squared call
        lambda: term * sp.cos(x),                              # two calls in a term
        lambda: term.subs(call, call.func(x + y)),             # a call of a sum
        lambda: term * (x + y),                                # a sum as a factor
        lambda: 3 * term / 2 + other,                          # a repeated call (like terms stay apart)
        lambda: term.subs(call, sp.tan(x)),                    # another function
        lambda: term / call,                                   # no call
    ])
    return sp.Add(change(), *expr.args[1:])


def _first_steps(expr) -> sp.Expr:
    """display_form's steps before the common factors, with sympy's own expand."""
    result = sp.expand(expr)
    if result.has(sp.sin, sp.cos):
        result = fold_angle_sums(pythagorean(result))
    return group_by_calls(result)


@pytest.mark.parametrize("seed", range(300))
def test_separate_calls_are_left_as_they_are(seed):
    rng = random.Random(seed)
    expr = _separate(rng)
    if not expr.is_Add:
        return
    assert separate_calls(expr) == (len({f for f in expr.atoms(sp.sin, sp.cos)}) == len(expr.args))
    if separate_calls(expr):
        assert sp.srepr(_first_steps(expr)) == sp.srepr(expr)
    pulled = pull_signs(sp.factor_terms(expr))
    expected = pulled if count_ops(pulled) <= count_ops(expr) else pull_signs(expr)
    assert sp.srepr(display_steps(expr)) == sp.srepr(expected)


@pytest.mark.parametrize("seed", range(300))
def test_near_shapes_are_recognised_only_when_left_as_they_are(seed):
    rng = random.Random(seed)
    expr = _separate(rng)
    if not expr.is_Add or len(expr.args) < 2:
        return
    near = _near(rng, expr)
    if separate_calls(near):
        assert sp.srepr(_first_steps(near)) == sp.srepr(near)
