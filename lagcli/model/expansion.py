"""Polynomials expanded, the same expression `sympy.expand` gives, without its general machinery.

sympy.expand walks the tree once per hint (mul, multinomial, power_exp, power_base, log,
then mul and multinomial again until nothing changes) and multiplies sums out pairwise,
every partial product through `Mul.flatten` and `Add.flatten`: two thirds of tidying a
10-link chain's forcing for generated code (lagcli/render/tidy.py `collected`).

For a *polynomial* expression (rational numbers, symbols, sums, products, positive
integer powers of those, nonzero integer powers of a symbol or of a single term, sin
and cos of polynomials) expand gives the sum of its distinct monomials with their
nonzero rational coefficients, each call's argument expanded too. sympy's Add and Mul
combine like terms and like bases and order their arguments canonically, so that sum
is one expression whichever way it is reached. `expanded` multiplies out over
{monomial: coefficient} dicts, each distinct subexpression once (`memo`: shared parts
such as a chain's velocity sums recur in every entry), and builds the sum with
`sums.total` and `products.product` (sympy's Add and Mul, the same expressions);
anything else goes to `sympy.expand`. tests/test_expansion.py compares both.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.products import product
from lagcli.model.sums import total

CALLS = (sp.sin, sp.cos)      # expand only expands their arguments (no trig hint)


class NotPolynomial(Exception):
    """The expression holds something `expanded` leaves to sympy.expand."""


def expanded(expr, memo: dict | None = None) -> sp.Expr:
    """`sympy.expand(expr)`, the same expression."""
    memo = {} if memo is None else memo
    try:
        terms = _polynomial(expr, memo)
    except NotPolynomial:
        return sp.expand(expr)
    return _sum_of(terms)


def _sum_of(terms: dict) -> sp.Expr:
    """The canonical sum of {monomial: coefficient}, a monomial a frozenset of (base, exponent)."""
    return total([product(coefficient, *(base if e == 1 else sp.Pow(base, e) for base, e in monomial))
                  for monomial, coefficient in terms.items()])


_ONE = frozenset()


def _polynomial(expr, memo: dict) -> dict:
    """expr expanded as {monomial: nonzero rational coefficient}."""
    found = memo.get(expr)
    if found is None:
        found = memo[expr] = _expand_node(expr, memo)
    return found


def _expand_node(expr, memo: dict) -> dict:
    if expr.is_Rational:
        return {_ONE: expr} if expr != 0 else {}
    if expr.is_Symbol:
        if expr.is_commutative is not True:
            raise NotPolynomial(expr)
        return {frozenset({(expr, 1)}): sp.S.One}
    if expr.is_Add:
        result: dict = {}
        for term in expr.args:
            _add_into(result, _polynomial(term, memo))
        return result
    if expr.is_Mul:
        result = {_ONE: sp.S.One}
        for factor in expr.args:
            result = _times(result, _polynomial(factor, memo))
        return result
    if expr.is_Pow:
        return _power(expr, memo)
    if type(expr) in CALLS:
        argument = expanded(expr.args[0], memo)
        call = expr.func(argument)
        if type(call) is type(expr) and call.args[0] == argument:
            return {frozenset({(call, 1)}): sp.S.One}
        return _polynomial(call, memo)        # sin(-x) -> -sin(x), sin(0) -> 0
    raise NotPolynomial(expr)


def _power(expr, memo: dict) -> dict:
    exponent = expr.exp
    if not exponent.is_Integer:
        raise NotPolynomial(expr)
    base = _polynomial(expr.base, memo)
    n = int(exponent)
    if len(base) == 1:              # c*m: c**n * m**n, any integer n
        (monomial, coefficient), = base.items()
        raised = frozenset((b, e * n) for b, e in monomial)
        return {raised: coefficient ** n}
    if n < 0:                       # 1/(a + b): expand keeps the sum in a denominator
        raise NotPolynomial(expr)
    result = {_ONE: sp.S.One}
    for _ in range(n):
        result = _times(result, base)
    return result


def _add_into(result: dict, terms: dict) -> None:
    for monomial, coefficient in terms.items():
        c = result.get(monomial)
        c = coefficient if c is None else c + coefficient
        if c == 0:
            result.pop(monomial, None)
        else:
            result[monomial] = c


def _times(a: dict, b: dict) -> dict:
    result: dict = {}
    for ma, ca in a.items():
        for mb, cb in b.items():
            _add_into(result, {_monomial_product(ma, mb): ca * cb})
    return result


def _monomial_product(a: frozenset, b: frozenset) -> frozenset:
    if not a:
        return b
    if not b:
        return a
    powers = dict(a)
    for base, e in b:
        powers[base] = powers.get(base, 0) + e
    return frozenset((base, e) for base, e in powers.items() if e != 0)
