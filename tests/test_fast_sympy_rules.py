"""lagcli's faster versions of sympy operations give sympy's own results, structurally
(==, not only numerically): `calculus.derivative` (sympy's diff), `tidy.common_factor`
(sympy's factor_terms), `tidy.is_expanded` (sympy's expand leaves the expression alone) and
`operations.count_ops` (sympy's count_ops).
The oracle each time is sympy itself, on seeded random expressions of the shapes the
derivation and the reports meet (polynomials in parameters times sin/cos of angle sums,
powers, square roots, non-smooth functions)."""
from __future__ import annotations

import random

import pytest
import sympy as sp

from lagcli.model.calculus import derivative
from lagcli.render.operations import count_ops
from lagcli.render.tidy import common_factor, is_expanded

x, y, z, m1, m2, l1, l2 = sp.symbols("x y z m1 m2 l1 l2", real=True)
t = sp.Symbol("t", real=True)
f = sp.Function("f")

SPECIAL = [x, 3 * x ** 2 * sp.cos(y * x), sp.sqrt(x ** 2 + y ** 2), (x + y) ** 2 * sp.sin(x - y),
           sp.atan2(y, x), sp.Abs(x - y) * x, sp.sign(x) * x ** 3, sp.exp(x * y) / (1 + x), x ** y,
           sp.log(x) * sp.tan(x), sp.Min(x, y) * x, f(t) * x, sp.Piecewise((x, x > 0), (x ** 2, True)),
           2 * (x + y) * (x - 1), sp.Rational(1, 2) * x ** 2 * (y + z), l1 * l2 * (m1 + m2) * sp.cos(x - y)]


def _random_sums(count: int, seed: int) -> list[sp.Expr]:
    rng = random.Random(seed)
    atoms = [x, y, z, m1, m2, l1, l2, sp.cos(x), sp.sin(x - y), sp.cos(y), sp.cos(2 * x - y)]
    numbers = [1, -1, 2, -2, 3, sp.Rational(1, 2), -sp.Rational(3, 2), sp.Rational(3, 4)]
    sums = []
    for _ in range(count):
        terms = []
        for _ in range(rng.randint(2, 6)):
            term = sp.S(rng.choice(numbers))
            for atom in rng.sample(atoms, rng.randint(1, 4)):
                term *= atom ** rng.randint(1, 2)
            terms.append(term)
        sums.append(sp.Add(*terms))
    return sums


@pytest.mark.parametrize("expr", SPECIAL + _random_sums(40, 1), ids=str)
def test_derivative_is_sympys_diff(expr):
    for var in (x, y, t):
        assert derivative(expr, var) == expr.diff(var)


def _big_sums(count: int, seed: int) -> tuple[list[sp.Expr], list[sp.Symbol]]:
    """Sums of 9 to 30 terms (indexed by symbol in `derivative`), alone and inside products
    and powers, as a chain's potential holds them: g m_k (l_1 cos(q_1) + ... + l_k cos(q_k))."""
    rng = random.Random(seed)
    qs, ls = sp.symbols("q1:31"), sp.symbols("l1:31")
    exprs = []
    for _ in range(count):
        k = rng.randint(9, 30)
        terms = [rng.choice([1, -1, 2, sp.Rational(1, 2)]) * ls[i] * rng.choice([sp.cos, sp.sin])(qs[i])
                 * (x if rng.random() < 0.2 else 1) for i in rng.sample(range(30), k)]
        big = sp.Add(*terms, *(rng.sample(terms, 2)))     # like terms too
        exprs.append(rng.choice([big, m1 * big, m2 * l1 * big ** 2, sp.cos(big) + big * y]))
    return exprs, list(qs[:5]) + [x, y]


@pytest.mark.parametrize("seed", range(20))
def test_derivative_of_big_sums_is_sympys_diff(seed):
    """One memo for every variable, as the derivation shares it: the index of a sum's
    terms, built at the first derivative, serves the next ones."""
    exprs, variables = _big_sums(3, seed)
    memo: dict = {}
    for expr in exprs:
        for var in variables:
            ours, theirs = derivative(expr, var, memo), expr.diff(var)
            assert ours == theirs and ours.args == theirs.args


def test_common_factor_is_sympys_factor_terms():
    exprs = _random_sums(120, 2) + [sum_ * l1 * sp.cos(x) for sum_ in _random_sums(20, 3)]
    exprs += [m1 * (x + y), 2 * l1 * (x + y) + 2 * l1 * z, sp.sqrt(x) + x / 2, x / y + z / y]
    for expr in exprs:
        assert common_factor(expr) == sp.factor_terms(expr), expr


def test_is_expanded_only_when_expand_changes_nothing():
    exprs = _random_sums(100, 4) + [(x + y) ** 2, x * (y + z), sp.cos(2 * (x + y)), sp.exp(x + y),
                                    sp.sqrt(x * y), l1 * sp.cos(x - y) * m1]
    recognised = 0
    for expr in exprs:
        if is_expanded(expr):
            recognised += 1
            assert sp.expand(expr) == expr, expr
    assert recognised >= 70      # the common case is recognised


def test_count_ops_is_sympys_count_ops():
    """Every subexpression of random sums, of the special shapes (divisions, exp, Min,
    Piecewise: handed to sympy), their negations and expansions, and of the equations of
    two bundled specs with rolling and rigid bodies."""
    from pathlib import Path

    from lagcli.derive.pipeline import derive_file

    exprs = SPECIAL + _random_sums(60, 5) + [-e for e in _random_sums(20, 6)]
    exprs += [sp.expand(e) for e in _random_sums(20, 7)] + [x / y - 2.0 * z, -x - y, 1.5 * x - sp.E, -(x + y) ** 2]
    unevaluated = [sp.Mul(n, sp.Add(*terms), evaluate=False) for n in (-1, 2, -2, 1.5)
                   for terms in ((x, y), (x * sp.cos(y), -z), (l1, m1 * sp.sin(x - y)))]      # pull_signs, _keep_coeff
    exprs += unevaluated + [sp.Mul(sp.Integer(-1), e * l2, evaluate=False) for e in unevaluated[:3]]
    for spec in ("rolling_disc", "heavy_symmetric_top"):
        d = derive_file(Path(__file__).resolve().parent.parent / "specs" / f"{spec}.yaml")
        exprs += [d.T, d.V, *d.mass_matrix, *d.forcing]
    for expr in exprs:
        for node in sp.preorder_traversal(expr):
            if isinstance(node, sp.Expr):
                assert count_ops(node) == sp.count_ops(node), node


def test_weighted_display_form_is_display_form(monkeypatch):
    """The shortcut for m_1 X + ... + m_n X gives display_form's result whenever it answers,
    on monomials X of every shape (signs, fractions, powers, one or two calls, calls whose
    arguments have a common factor), also on sums too big for display_form's size budget:
    there it gives what display_form would give without the budget (the shortcut costs
    what X costs, so a 100-link chain's mass matrix is shown grouped at any size)."""
    from lagcli.render import tidy
    from lagcli.render.tidy import display_form
    from lagcli.render.weighted import weighted_display_form

    monkeypatch.setattr(tidy, "small", lambda expr, budget=None: True)    # display_form without its budget

    rng = random.Random(8)
    masses = sp.symbols("m1:60", real=True)
    parts = [x, y ** 2, l1, l2 ** 3, sp.cos(x - y), sp.sin(x), sp.cos(2 * x - 2 * y), sp.sin(y) ** 2, sp.tan(z)]
    numbers = [1, -1, 2, -3, sp.Rational(1, 2), -sp.Rational(3, 4)]
    answered = 0
    for _ in range(150):
        shared = sp.S(rng.choice(numbers)) * sp.Mul(*rng.sample(parts, rng.randint(1, 4)))
        weights = list(rng.sample(masses, rng.choice([2, 3, 7, 20, 59])))
        found = weighted_display_form(weights, shared)
        if found is not None:
            answered += 1
            assert found == display_form(sp.Add(*(w * shared for w in weights))), (weights, shared)
    assert answered >= 60


def test_leading_term_is_the_first_ordered_term():
    """`tidy.leading_term` (which sign a tied sum shows, for pull_signs) is sympy's
    `as_ordered_terms()[0]` on sums of numbers times symbols (names that sort as strings:
    q1, q10, q2) and on anything else it falls back to."""
    from lagcli.render.tidy import leading_term

    rng = random.Random(24)
    symbols = [*sp.symbols("q1:13", real=True), x, y, z, sp.Symbol("th10"), sp.Symbol("th2"), sp.Dummy("d")]
    numbers = [1, -1, 2, -3, sp.Rational(1, 2), -sp.Rational(5, 3), sp.Float(0.5)]
    for _ in range(500):
        add = sp.Add(*(rng.choice(numbers) * s for s in rng.sample(symbols, rng.randint(2, 5))))
        add += rng.choice([0, 0, 1, x * y, sp.cos(x)])
        if add.is_Add:
            assert leading_term(add) == add.as_ordered_terms()[0], add


def test_small_counts_what_preorder_traversal_visits():
    """`tidy.small` (each distinct subexpression sized once, `tree_size`) answers as counting
    `sympy.preorder_traversal` would, at every budget around the true size, alone and for lists."""
    from lagcli.render.tidy import small

    exprs = SPECIAL + _random_sums(30, 9) + [sp.Min(x, y, z), (m1 * x + m1 * x * y) ** 2 * sp.cos(x) * sp.cos(x)]
    for expr in exprs:
        size = sum(1 for _ in sp.preorder_traversal(expr))
        for budget in (0, 1, size // 2, size - 1, size, size + 1):
            assert small(expr, budget) == (size <= budget), (expr, budget)
    together = sum(1 for e in exprs[:5] for _ in sp.preorder_traversal(e))
    assert small(exprs[:5], together) and not small(exprs[:5], together - 1)
