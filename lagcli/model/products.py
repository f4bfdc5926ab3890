"""Products of plain factors, built as sympy's `Mul` builds them, without its general flatten.

`Mul.flatten` handles numbers with radicals, infinities, the imaginary unit, powers to be
combined and non-commutative factors, and costs ~60 microseconds for `m3*(x + y)`: a
40-link chain forms tens of thousands of such products (the masses times the dot
products of its mass matrix, the terms of its reports). When the factors, with products
among them opened, are a rational number and *plain* factors (symbols, function calls,
sums, and integer powers of symbols and calls) with distinct bases, flatten only
multiplies the numbers and sorts the rest by `Basic.compare`; `product` does just that.
Whatever else (a number times a sum, which sympy distributes, a repeated base, a
radical, a float...) goes to `sympy.Mul`. tests/test_products.py compares both.
"""
from __future__ import annotations

import functools

import sympy as sp
from sympy.core.basic import Basic
from sympy.core.parameters import global_parameters
from sympy.core.sympify import _sympify
from sympy.functions.elementary.exponential import ExpBase

from lagcli.model.ordering import class_key, leaf_key, sort_keyed

_ONE, _ZERO = sp.S.One, sp.S.Zero


def product(*factors) -> sp.Expr:
    """`sympy.Mul(*factors)`, the same expression."""
    factors = [f if isinstance(f, Basic) else _sympify(f) for f in factors]
    if len(factors) == 2:
        a, b = factors
        if a is _ONE and not b.is_Mul and global_parameters.evaluate:    # Mul drops its identity
            return b
        if b is _ONE and not a.is_Mul and global_parameters.evaluate:
            return a
        if _symbol_and_sum(a, b) or _symbol_and_sum(b, a):     # a mass times a dot product, M_ij q''_j
            return sp.Mul._from_args((b, a) if class_key(type(b)) < class_key(type(a)) else (a, b), True)
        if _two_sums(a, b) and global_parameters.evaluate:     # a chain's M_ij: a dot product times its masses
            order = b.compare(a)       # 0 for equal ones (a**2); different hashes: not equal
            if order and hash(a) != hash(b):
                return sp.Mul._from_args((b, a) if order < 0 else (a, b), True)
        if _distributes(a, b):
            return sp.Mul(*factors)
    number, plain, bases, keys = sp.S.One, [], [], []
    for factor in factors:
        for part in (factor.args if factor.is_Mul else (factor,)):
            if part.is_Rational:
                number *= part
                continue
            found = _factor(part)
            if found is None:
                return sp.Mul(*factors)
            plain.append(part)
            bases.append(found[0])
            keys.append(found[1])
    # a product of rational numbers is sympy's singleton 0 or 1 when it is one: compared by identity
    if number is _ZERO or (len(plain) == 1 and plain[0].is_Add):
        return sp.Mul(*factors)
    if len(set(bases)) != len(bases):      # l1*cos(q1) times itself: a diagonal dot product
        combined = _combined_powers(plain, bases)
        if combined is None:
            return sp.Mul(*factors)
        plain, keys = combined
    sort_keyed(plain, keys)      # `Mul.flatten`'s order
    args = plain if number is _ONE else [number, *plain]
    if len(args) == 1:
        return args[0]
    return sp.Mul._from_args(args, True) if args else sp.S.One


@functools.lru_cache(maxsize=1 << 16)     # a chain's products share their factors (m3, l3, cos(q3))
def _factor(part: Basic) -> tuple | None:
    """(its base, `leaf_key`) of a plain factor (`_plain`); None for any other."""
    if not _plain(part):
        return None
    return (part.base if part.is_Pow else part), leaf_key(part)


def _combined_powers(plain: list, bases: list) -> tuple[list, list] | None:
    """The factors with a repeated base combined as `Mul.flatten` combines them (x * x**2 ->
    x**3), with their `leaf_key`s; None unless every repeated base is a symbol or call whose
    exponents add up to a nonzero integer (a sum's powers, x * x**-1: left to sympy). Adding
    the exponents here also keeps sympy's `Add` (whose first call imports sympy.tensor, 0.04 s)
    out of a chain's derivation."""
    exponents: dict = {}
    for part, base in zip(plain, bases):
        exponent = int(part.exp) if part.is_Pow else 1
        exponents[base] = exponents.get(base, 0) + exponent
    combined = []
    for base, exponent in exponents.items():
        if exponent == 0 or not (base.is_Symbol or isinstance(base, sp.Function)):
            return None
        power = base if exponent == 1 else sp.Pow(base, exponent)
        if power is not base and not (power.is_Pow and power.base == base):    # Abs(x)**2 is x**2, x real
            return None
        combined.append(power)
    return combined, [leaf_key(part) for part in combined]


def _symbol_and_sum(a, b) -> bool:
    """A commutative symbol and sum: plain, with distinct bases (`_plain`)."""
    return a.is_Symbol and b.is_Add and a.is_commutative is True and b.is_commutative is True


def _two_sums(a, b) -> bool:
    """Two commutative sums: flatten keeps each as one factor when they differ (a sum's own
    number is not pulled out) and sorts the two by `Basic.compare`."""
    return type(a) is sp.Add and type(b) is sp.Add and a.is_commutative is True and b.is_commutative is True


def _distributes(a, b) -> bool:
    """Mul's rule for two factors: a rational number times a (number times a) sum."""
    if b.is_Rational:
        a, b = b, a
    return a.is_Rational and b.as_coeff_Mul()[1].is_Add


def _plain(factor) -> bool:
    """A symbol, sum or call (its own base), or a nonzero integer power of a symbol or call;
    commutative; no exp, whose base is E (exp(x)*exp(y) combine)."""
    if factor.is_Pow:
        base = factor.base
        return factor.exp.is_Integer and factor.exp != 0 and _plain(base) and not base.is_Add
    if factor.is_Symbol or factor.is_Add or isinstance(factor, sp.Function):
        return factor.is_commutative is True and not isinstance(factor, ExpBase)
    return False
