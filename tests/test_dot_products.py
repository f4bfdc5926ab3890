"""`folded_dot_product` (lagcli/render/dot_products.py) gives display_form's own result.

The oracle is `display_form` itself, which folds the sum by its general steps
(expand, pythagorean, fold_angle_sums, group_by_calls, common_factor, pull_signs), on
seeded random sums of the recognised shape c R sin(x) sin(y) + c R cos(x) cos(y) and of
shapes near it (a sign, a factor, a call or an argument changed), which must be left to
display_form (None) or folded to the very same expression."""
from __future__ import annotations

import random

import sympy as sp

from lagcli.render.dot_products import folded_dot_product
from lagcli.render.tidy import display_form

NAMES = ["q1", "q2", "q10", "q39", "theta", "phi", "a", "Z", "x_b", "l1", "l2", "l10", "m", "g"]


def _symbols(rng: random.Random, k: int) -> list[sp.Symbol]:
    kinds = [dict(real=True), dict(real=True), dict(positive=True), {}]
    return [sp.Symbol(name, **rng.choice(kinds)) for name in rng.sample(NAMES, k)]


def _dot_product(rng: random.Random) -> sp.Expr:
    x, y, *rest = _symbols(rng, rng.randint(2, 6))
    number = rng.choice([1, 1, -1, 2, -3, sp.Rational(1, 2), -sp.Rational(3, 4)])
    common = sp.Mul(number, *(s ** rng.choice([1, 1, 2, 3]) for s in rest))
    return common * sp.sin(x) * sp.sin(y) + common * sp.cos(x) * sp.cos(y)


def _near(rng: random.Random, expr: sp.Expr) -> sp.Expr:
    """expr with one of its parts changed: still a sum of two terms, mostly not foldable."""
    first, second = expr.args
    x, y = sorted(first.atoms(sp.Symbol) & second.atoms(sp.Symbol), key=str)[:2]
    z = sp.Symbol("w", real=True)
    change = rng.choice([
        lambda: (-first, second),
        lambda: (2 * first, second),
        lambda: (first * z, second),
        lambda: (first.subs(sp.sin(x), sp.cos(x)), second),
        lambda: (first.subs(x, 2 * x), second.subs(x, 2 * x)),
        lambda: (first.subs(x, x + z), second.subs(x, x + z)),
        lambda: (first.subs(x, y), second.subs(x, y)),
        lambda: (first * sp.sin(z), second * sp.sin(z)),
        lambda: (first * sp.sqrt(z), second * sp.sqrt(z)),
        lambda: (first * (z + 1), second * (z + 1)),
        lambda: (first.subs(y, sp.Dummy("d", real=True)), second),
    ])
    return sp.Add(*change())


def test_folded_dot_product_is_display_form():
    rng = random.Random(20261128)
    folded = 0
    for _ in range(300):
        expr = _dot_product(rng)
        if not expr.is_Add or len(expr.args) != 2:
            continue
        found = folded_dot_product(expr)
        assert found is not None, expr
        assert sp.srepr(found) == sp.srepr(display_form(expr)), expr
        folded += 1
    assert folded > 250


def test_near_shapes_are_left_alone_or_folded_the_same():
    rng = random.Random(11)
    for _ in range(300):
        expr = _near(rng, _dot_product(rng))
        found = folded_dot_product(expr)
        if found is not None:
            assert sp.srepr(found) == sp.srepr(display_form(expr)), expr


def test_other_expressions_are_not_recognised():
    x, y, l = sp.symbols("x y l", real=True)
    for expr in (x + y, l * sp.sin(x) * sp.sin(y) - l * sp.cos(x) * sp.cos(y),
                 l * sp.sin(x) * sp.cos(y) + l * sp.cos(x) * sp.sin(y), sp.sin(x) ** 2 + sp.cos(x) ** 2,
                 l * sp.sin(x) * sp.sin(y) + 2 * l * sp.cos(x) * sp.cos(y), sp.sin(x) * sp.sin(y) * l + x):
        assert folded_dot_product(expr) is None, expr
