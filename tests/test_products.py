"""`product` (lagcli/model/products.py) builds the very expression sympy's Mul does."""
import random

import sympy as sp

from lagcli.model.products import product


def _factors(rng, pool):
    kind = rng.random()
    if kind < 0.35:
        return rng.choice(pool)
    if kind < 0.5:
        return rng.choice([sp.Integer(2), sp.Integer(-1), sp.Rational(1, 2), sp.Rational(-3, 4), sp.S.One,
                           sp.S.Zero, sp.Float(0.5), sp.pi, sp.sqrt(2), sp.I])
    if kind < 0.65:
        return rng.choice([sp.sin, sp.cos, sp.exp, sp.Abs])(rng.choice(pool))
    if kind < 0.75:
        return rng.choice(pool) ** rng.choice([2, 3, -1, -2, sp.Rational(1, 2)])
    if kind < 0.85:
        return sp.Add(*rng.sample(pool, 2)) * rng.choice([1, 2, -1])
    return sp.Mul(*rng.sample(pool, 2)) * rng.choice([1, 3, -1, sp.Rational(1, 3)])


def test_product_is_sympys_mul():
    rng = random.Random(20261127)
    x, y, z = sp.symbols("x y z", real=True)
    q1, q10, q9 = sp.symbols("q1 q10 q9")
    a, b = sp.symbols("a b", commutative=False)
    pool = [x, y, z, q1, q10, q9, sp.cos(x), sp.sin(x - y)]
    for k in range(3000):
        factors = [_factors(rng, pool + ([a, b] if k % 10 == 0 else [])) for _ in range(rng.randint(1, 4))]
        ours, theirs = product(*factors), sp.Mul(*factors)
        assert product(1, factors[0]) == sp.Mul(1, factors[0])
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), factors


def test_products_of_small_calls_are_sympys_mul():
    """Factors that are small but not made of leaves (cos(q1 - q2), sin(2*q3 - q10)**2: keyed
    whole by `leaf_key`), several of one class in a product, are ordered as sympy's Mul orders them."""
    rng = random.Random(20261128)
    qs = sp.symbols("q1 q2 q3 q10 q11 q20", real=True)
    others = list(sp.symbols("l1 l2 l10 m2 q1_dot q2_ddot", real=True)) + [sp.Add(*sp.symbols("m2 m3 m10"))]

    def call():
        x, y = rng.sample(qs, 2)
        angle = rng.choice([x - y, x + y, 2 * x - y, x, -x + 3 * y])
        found = rng.choice([sp.sin, sp.cos])(angle)
        return found ** rng.choice([1, 1, 2, -1]) if rng.random() < 0.3 else found
    for _ in range(2000):
        factors = [call() for _ in range(rng.randint(1, 4))] + rng.sample(others, rng.randint(0, 4))
        if rng.random() < 0.3:
            factors.append(rng.choice([sp.Integer(-1), sp.Rational(1, 2), sp.Integer(3)]))
        rng.shuffle(factors)
        ours, theirs = product(*factors), sp.Mul(*factors)
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), factors


def test_products_of_two_sums_are_sympys_mul():
    """A dot product times a sum of masses (a chain's M_ij: `product`'s two-sum path) is
    sympy's Mul, equal sums (a square) and sums with numbers among them."""
    rng = random.Random(20261128)
    m = sp.symbols("m1:6", real=True)
    l1, l2, q1, q2 = sp.symbols("l1 l2 q1 q2", real=True)
    x = sp.Symbol("x")
    sums = [sp.Add(*m[k:]) for k in range(4)] + [
        l1 * l2 * sp.cos(q1) * sp.cos(q2) + l1 * l2 * sp.sin(q1) * sp.sin(q2),
        l1**2 * sp.cos(q1)**2 + l1**2 * sp.sin(q1)**2, x + 1, 2 * x + sp.Rational(1, 2), sp.cos(q1) - x,
        sp.Float(0.5) + x, m[0] + m[1]]
    for _ in range(500):
        a, b = rng.choice(sums), rng.choice(sums)
        if rng.random() < 0.1:
            b = sp.Add(*a.args)      # an equal copy
        ours, theirs = product(a, b), sp.Mul(a, b)
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), (a, b)


def test_repeated_bases_are_combined_as_sympys_mul():
    """A base met more than once (l1*cos(q1) times itself, x * x**-2, Abs(x) * Abs(x) with x
    real, which sympy's Pow turns into x**2) gives sympy's Mul, whichever path takes it."""
    rng = random.Random(20261129)
    x, y = sp.symbols("x y", real=True)
    z, q1 = sp.symbols("z q1")
    bases = [x, y, z, q1, sp.cos(q1), sp.sin(x - y), sp.Abs(x), sp.Abs(z), sp.exp(z), x + y]
    for _ in range(3000):
        chosen = [rng.choice(bases) for _ in range(rng.randint(2, 5))]
        factors = [b ** rng.choice([1, 1, 2, -1, -2, 3]) for b in chosen]
        if rng.random() < 0.3:
            factors.append(rng.choice([sp.Integer(-1), sp.Rational(1, 2), sp.Integer(3)]))
        ours, theirs = product(*factors), sp.Mul(*factors)
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), factors
