"""The linear-time rewritings of code generation (lagcli/render/tidy.py, code half) against
sympy itself: `factored` is sympy's factor_terms on the sums a mechanical system has,
and gives an equal expression on anything else; `collected` is an equal expression
with one term per velocity monomial. Seeded random expressions of the shapes the
derivation produces (polynomials in parameters and velocities times sin/cos of angle
sums, quotients, square roots)."""
from __future__ import annotations

import random

import pytest
import sympy as sp
from sympy.simplify.cse_opts import sub_pre

from lagcli.render.tidy import collected, factored

x, y, z, m1, m2, l1, l2 = sp.symbols("x y z m1 m2 l1 l2", real=True)
u1, u2 = sp.symbols("u1 u2", real=True)      # velocities
ATOMS = [x, y, z, m1, m2, l1, l2, sp.cos(x), sp.sin(x - y), sp.cos(y), sp.cos(2 * x - y)]
NUMBERS = [1, -1, 2, -2, 3, sp.Rational(1, 2), -sp.Rational(3, 2), sp.Rational(3, 4)]


def _random_sum(rng: random.Random, atoms=ATOMS) -> sp.Expr:
    terms = []
    for _ in range(rng.randint(2, 6)):
        term = sp.S(rng.choice(NUMBERS))
        for atom in rng.sample(atoms, rng.randint(1, min(4, len(atoms)))):
            term *= atom ** rng.randint(1, 2)
        terms.append(term)
    return sp.Add(*terms)


def _nested(rng: random.Random) -> sp.Expr:
    """Products, quotients and roots of random sums, with shared parts (no root or
    quotient of a value near 0: rounding there would not be the rewriting's fault)."""
    a, b, c, d = (_random_sum(rng) for _ in range(4))
    return rng.choice([a * b / (c ** 2 + 1) + sp.sqrt(d ** 2 + 1) * a, a / m1 + b / (m1 * l1), -(a - b) * c * l2,
                       a * (b - c) ** 2 - a * d, sp.sin(a) * b + sp.cos(a) * b * c])


def _equal(a: sp.Expr, b: sp.Expr, rng: random.Random) -> bool:
    symbols = sorted(a.free_symbols | b.free_symbols, key=str)
    fa, fb = (sp.lambdify(symbols, e, "cmath") for e in (a, b))
    for _ in range(3):
        values = [rng.uniform(0.5, 2.0) for _ in symbols]
        va, vb = fa(*values), fb(*values)
        if abs(va - vb) > 1e-9 * (1 + abs(va)):
            return False
    return True


def test_factored_is_sympys_factor_terms_on_sums_of_products():
    rng = random.Random(1)
    sums = [_random_sum(rng) for _ in range(150)] + [_random_sum(rng) * l1 * sp.cos(x) for _ in range(20)]
    sums += [m1 * (x + y), 2 * l1 * (x + y) + 2 * l1 * z, sp.sqrt(x) + x / 2, x / y + z / y]
    for expr in sums:
        assert factored(expr) == sp.factor_terms(expr), expr


def test_factored_keeps_the_value_and_sign_normalised_forms():
    rng = random.Random(2)
    for _ in range(40):
        expr = _nested(rng)
        assert _equal(factored(expr), expr, rng), expr
        marked = sub_pre(expr)          # sympy.cse's 1*-1*(...) forms, as eliminate passes them
        assert _equal(factored(marked), expr, rng), expr
    # a number times one sum is multiplied into it first, as factor_terms does
    assert factored(sub_pre(-(l1 * x * m2 - m2 * y))) == sp.factor_terms(sub_pre(-(l1 * x * m2 - m2 * y)))


def test_collected_is_equal_with_one_term_per_velocity_monomial():
    rng = random.Random(3)
    velocities = (u1, u2)
    monomials = [sp.S.One, u1, u2, u1 ** 2, u1 * u2, u2 ** 2]
    for _ in range(25):
        expr = sum(rng.choice([1, -2, sp.Rational(1, 2)]) * _random_sum(rng) * rng.choice(monomials)
                   for _ in range(rng.randint(2, 5)))
        expr = expr * _random_sum(rng, [l1, m1, sp.cos(x)])     # not expanded
        result = collected(expr, velocities)
        assert _equal(result, expr, rng), expr
        keys = [term.as_independent(*velocities, as_Add=False)[1] for term in sp.Add.make_args(result)]
        keys = [key for key in keys if key != 1]      # the velocity-free part may be a sum itself
        assert len(keys) == len(set(keys)), result


@pytest.mark.parametrize("velocities", [(), (u1,)])
def test_collected_of_a_number_or_symbol_is_itself(velocities):
    for expr in (sp.S.Zero, sp.S(3), x, u1):
        assert collected(expr, velocities) == expr


def test_signs_normalised_is_sympys_sub_pre():
    """cse.signs_normalised (one memo over many expressions, no sort) gives exactly the
    expressions of sympy's own sub_pre, sums of sums and shared sums included."""
    from lagcli.targets.cse import signs_normalised

    rng = random.Random(5)
    normalise = signs_normalised({})
    exprs = [_nested(rng) for _ in range(40)]
    exprs += [-(x - y) * (y - x) + (z - x) ** 2, (l1 - l2) / (m2 - m1) - (x - y - z)]
    for expr in exprs:
        assert sp.srepr(normalise(expr)) == sp.srepr(sub_pre(expr)), expr


def test_calls_in_is_sympys_atoms():
    """`tidy.calls_in` (each distinct subexpression visited once) finds sympy's atoms(Function)."""
    from lagcli.render.tidy import calls_in

    x, y = sp.symbols("x y", real=True)
    f = sp.Function("f")
    for expr in [x, sp.sin(x) * sp.cos(x - y) + sp.sin(x) ** 2, sp.exp(sp.sin(f(x, sp.cos(y)))) + sp.Abs(x),
                 sp.sin(x) * (sp.sin(x) + sp.cos(x) * sp.sin(x)), sp.Integer(3)]:
        assert calls_in(expr) == expr.atoms(sp.Function), expr
