"""`signed_product` (lagcli/report/display.py): pull_signs of a coefficient times velocities,
without pull_signs' walk when the product is known to be kept.

The oracle is pull_signs of the product built by sympy's own `Mul`, on seeded random
coefficients (sums with more or fewer negative terms, numbers, powers, calls, nested;
some already passed through pull_signs, as the report's tidied coefficients are) times
random symbols and powers of symbols, with pull_signs remembering across the cases (as the
report's `Display.signs`) and without."""
from __future__ import annotations

import functools
import random

import pytest
import sympy as sp

from lagcli.render.tidy import pull_signs
from lagcli.report.display import signed_product

SYMBOLS = sp.symbols("a b c l1 l2 m1 m2 q1 q2", real=True)
VELOCITIES = sp.symbols("q1_dot q2_dot q1_ddot", real=True)


def _expr(rng: random.Random, depth: int) -> sp.Expr:
    if depth == 0 or rng.random() < 0.3:
        return rng.choice([*SYMBOLS, *SYMBOLS, sp.Integer(rng.choice([-2, -1, 2, 3])), sp.Rational(1, 2)])
    kind = rng.choice(["add", "add", "mul", "mul", "pow", "call"])
    parts = [_expr(rng, depth - 1) for _ in range(rng.randint(2, 4))]
    if kind == "add":
        return sp.Add(*(rng.choice([1, -1]) * p for p in parts))
    if kind == "mul":
        return sp.Mul(*parts)
    if kind == "pow":
        return sp.Pow(parts[0], rng.choice([2, 3, -1]))
    return rng.choice([sp.sin, sp.cos])(parts[0])


def _factors(rng: random.Random) -> list:
    return [rng.choice(VELOCITIES) ** rng.choice([1, 1, 2]) for _ in range(rng.randint(1, 2))] \
        + ([sp.S.Half] if rng.random() < 0.2 else [])


@pytest.mark.parametrize("remember", [False, True])
def test_signed_product_is_pull_signs_of_sympys_product(remember):
    memo: dict = {}
    signs = functools.partial(pull_signs, memo=memo) if remember else pull_signs
    kept = 0
    for seed in range(600):
        rng = random.Random(seed)
        coefficient = _expr(rng, 3)
        if rng.random() < 0.6:
            coefficient = pull_signs(coefficient)      # a tidied coefficient, as the report's
        factors = _factors(rng)
        expected = pull_signs(sp.Mul(coefficient, *factors))
        found = signed_product(coefficient, *factors, signs=signs)
        assert sp.srepr(found) == sp.srepr(expected), (coefficient, factors)
        kept += found == sp.Mul(coefficient, *factors)
    assert kept > 120       # the shortcut's case is exercised
