"""`lagcli.model.expansion.expanded` gives the very expression sympy.expand gives (the
same arguments in the same order): on random polynomials, and on what it hands to
sympy.expand itself (floats, exp, noncommutative symbols, sums in a denominator)."""
import random

import sympy as sp

from lagcli.model.expansion import expanded


def _random_expr(rng, pool, depth):
    if depth == 0 or rng.random() < 0.25:
        kind = rng.random()
        if kind < 0.75:
            return rng.choice(pool)
        return rng.choice([sp.Integer(2), sp.Integer(-1), sp.Rational(1, 2), sp.Rational(-3, 4), sp.S.Zero])
    kind = rng.random()
    parts = [_random_expr(rng, pool, depth - 1) for _ in range(rng.randint(2, 3))]
    if kind < 0.35:
        return sp.Add(*parts)
    if kind < 0.7:
        return sp.Mul(*parts)
    if kind < 0.85:
        return parts[0] ** rng.choice([2, 3, -1, -2])
    return rng.choice([sp.sin, sp.cos])(parts[0])


def test_expanded_is_sympys_expand_on_polynomials():
    rng = random.Random(20261128)
    q1, q10, q9 = sp.symbols("q1 q10 q9", real=True)
    x, y = sp.symbols("x y", positive=True)
    z = sp.Symbol("z")
    pool = [q1, q10, q9, x, y, z, sp.sin(q1 - q10), sp.cos(q9)]
    for _ in range(1500):
        expr = _random_expr(rng, pool, rng.randint(1, 4))
        ours, theirs = expanded(expr), sp.expand(expr)
        assert ours == theirs and sp.srepr(ours) == sp.srepr(theirs), expr


def test_expanded_is_sympys_expand_on_a_chain_s_forcing_term():
    l1, l2, l3, m2, m3, g = sp.symbols("l1 l2 l3 m2 m3 g", positive=True)
    q1, q2, q3, v1, v2 = sp.symbols("q1 q2 q3 q1_dot q2_dot", real=True)
    term = -m3 * (l3 * (-l1 * v1 ** 2 * sp.sin(q1) - l2 * v2 ** 2 * sp.sin(q2)) * sp.cos(q3)
                  + l3 * (l1 * v1 ** 2 * sp.cos(q1) + l2 * v2 ** 2 * sp.cos(q2)) * sp.sin(q3)) \
        - g * l3 * (m2 + m3) * sp.sin(q3) + (v1 + v2) ** 2 * sp.sin(2 * (q1 - q2)) / l1
    assert sp.srepr(expanded(term)) == sp.srepr(sp.expand(term))


def test_not_polynomial_goes_to_sympy():
    x, y = sp.symbols("x y", real=True)
    a, b = sp.symbols("a b", commutative=False)
    for expr in [sp.Float(1.5) * (x + y) ** 2, sp.exp(x + y) * (x + 1), (x + y) / (x - y) * (x + 2),
                 sp.sqrt(x) * (x + y), a * (b + a), sp.pi * (x + 1) ** 2, sp.Abs(x * (x + 1)) * (y + 1)]:
        assert sp.srepr(expanded(expr)) == sp.srepr(sp.expand(expr)), expr
