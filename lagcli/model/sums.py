"""Sums of terms, built as sympy's `Add` builds them, its terms sorted by `ordering.sort_key`.

`Add(*terms)` collects like terms (c*s + d*s -> (c + d)*s) and sorts the result with
`Basic.compare`, a Python call per comparison: sorting the entries of the 100-link
chain's mass matrix (~5 000 sums of up to 100 terms) that way took seconds.
`total(terms)` does what `Add.flatten` does for the terms a derivation makes (symbols,
calls, products, powers, rational numbers and sums of them, commutative) and sorts with
the key; anything else (floats, infinities, orders, matrices, a number to a power...)
goes to `sympy.Add`. tests/test_sums.py compares both.
"""
from __future__ import annotations

import functools

import sympy as sp
from sympy.core.basic import Basic
from sympy.core.mul import _keep_coeff
from sympy.core.parameters import global_parameters
from sympy.core.sympify import _sympify

from lagcli.model.ordering import sort_args
from lagcli.model.products import product

_ZERO, _ONE = sp.S.Zero, sp.S.One


def total(terms) -> sp.Expr:
    """`sympy.Add(*terms)`, the same expression."""
    terms = [t if isinstance(t, Basic) else _sympify(t) for t in terms]
    if not global_parameters.evaluate:       # inside `with sympy.evaluate(False)`
        return sp.Add(*terms)
    args = [t for t in terms if t is not _ZERO]
    if len(args) < 2:
        return args[0] if args else _ZERO
    if len(args) == 2 and _two_products(*args):      # a chain's dot products: l1*l2*(c1*c2 + s1*s2)
        a, b = args
        order = b.compare(a)       # 0 for equal ones (2*a); different hashes: not equal
        if order and hash(a) != hash(b):
            return sp.Add._from_args((b, a) if order < 0 else (a, b), True)
    collected = _collect(args)
    if collected is None:
        return sp.Add(*terms)
    constant, coefficients = collected
    result = []
    for s, c in coefficients.items():
        if c is _ONE:
            result.append(s)
        elif c.is_zero:
            continue
        elif s.is_Mul:
            result.append(s._new_rawargs(*((c,) + s.args)))     # as flatten: c in front
        elif s.is_Add:
            result.append(sp.Mul(c, s, evaluate=False))     # from an unevaluated c*(x + y)
        else:
            result.append(sp.Mul(c, s))
    sort_args(result)
    if constant is not _ZERO:
        result.insert(0, constant)
    if not result:
        return _ZERO
    if len(result) == 1:
        return result[0]
    return sp.Add._from_args(result, True)   # no constructor postprocessor: those are MatrixExpr's


def _two_products(a, b) -> bool:
    """Two commutative products without a number: flatten keeps both when they differ (no
    like terms, nothing to add) and sorts them by `Basic.compare`."""
    return (type(a) is sp.Mul and type(b) is sp.Mul and not a.args[0].is_Number and not b.args[0].is_Number
            and a.is_commutative is True and b.is_commutative is True)


def dot(u, w) -> sp.Expr:
    """`Matrix(u).dot(Matrix(w))`, the same expression, of two vectors of plain terms: the
    sum of the nonzero products. (sympy's matrix product asked each term of the chain's
    positions whether it is zero, through the assumptions: most of the time of V.)"""
    return total([product(a, b) for a, b in zip(u, w) if a != 0 and b != 0])


def negative(expr: sp.Expr, negated: dict | None = None) -> sp.Expr:
    """`-expr`, the same expression: a sum's terms negated one by one (as `Mul(-1, sum)`
    distributes) and summed by `total`. When every term is a product without a number
    (l1*cos(q1): a chain's positions, its dV), each negated term is -1 times it, and
    compare orders those as it ordered the terms (one more factor each, the same first
    one): the sum keeps its order, not sorted again. `negated` (term -> -term), when
    given, makes -term of a term met before the object made then (a chain's positions
    repeat the terms of the one before: the memos of their parts then find them by
    identity, not by comparing equal copies)."""
    if expr.is_Add and expr.is_commutative and global_parameters.distribute:
        if all(term.is_Mul and not term.args[0].is_Number for term in expr.args):
            if negated is None:
                return sp.Add._from_args([_keep_coeff(sp.S.NegativeOne, term) for term in expr.args], True)
            terms = []
            for term in expr.args:
                found = negated.get(term)
                if found is None:
                    found = negated[term] = _keep_coeff(sp.S.NegativeOne, term)
                terms.append(found)
            return sp.Add._from_args(terms, True)
        return total(negated_terms(expr))
    return -expr


def scaled(number: sp.Rational, expr: sp.Expr) -> sp.Expr:
    """`number * expr` for a rational number, the same expression: a sum (without a number
    of its own) has its terms scaled one by one, as `Mul` distributes them, and summed by
    `total` (sympy's `Add`, whose first call imports sympy.tensor: 0.04 s of a command)."""
    if number.is_Rational and number is not _ONE and not number.is_zero and expr.is_Add \
            and expr.is_commutative and global_parameters.distribute and global_parameters.evaluate:
        terms = [_keep_coeff(number, term) for term in expr.args]
        if all(type(term) is sp.Mul and not term.args[0].is_Number for term in expr.args):
            # number * each product: compare orders those as it ordered the products (one more
            # factor each, the same first one), as in `negative`: not sorted again (T2's 1/2)
            return sp.Add._from_args(terms, True)
        return total(terms)
    return number * expr


def negated_terms(expr: sp.Expr) -> list:
    """Terms whose `total` is `negative(expr)`: a sum's terms negated one by one, not
    sorted (a caller adding them to other terms sorts once: `total([a, *negated_terms(b)])`
    is `total([a, negative(b)])`, each sum flattened into the other's terms anyway)."""
    if expr.is_Add and expr.is_commutative and global_parameters.distribute:
        return [_keep_coeff(sp.S.NegativeOne, term) for term in expr.args]
    return [-expr]


def _collect(args: list):
    """(the rational constant, {term without its number: its number}) in the order
    `Add.flatten` meets them (a sum's terms appended at the end); None for anything
    `total` leaves to sympy."""
    constant, coefficients = _ZERO, {}
    seq = list(args)
    for o in seq:          # seq grows while it is walked, as in flatten
        if o.is_Add:
            seq.extend(o.args)
            continue
        if o.is_Rational:
            constant += o
            continue
        if type(o) is sp.Mul and not o.args[0].is_Number and o.is_commutative is True:
            c, s = _ONE, o         # `_split` of a product without a number: itself, nothing to remember
        else:
            split = _split(o)
            if split is None:
                return None
            c, s = split
        found = coefficients.get(s)
        coefficients[s] = c if found is None else found + c
    return constant, coefficients


@functools.lru_cache(maxsize=1 << 16)
def _split(o) -> tuple | None:
    """(its rational number, the rest) of a plain term (`_plain_term`), as `Add.flatten`
    splits it (`as_coeff_Mul`); None for any other term. Remembered: a chain's sums share
    their terms (the k-th point's velocity holds the terms of the one before), and the rest
    of a term with a number is a new product, hashed anew at every sum."""
    if not _plain_term(o):
        return None
    c, s = o.as_coeff_Mul() if o.is_Mul else (_ONE, o)
    return (c, s) if c.is_Rational else None


def _plain_term(o) -> bool:
    """A commutative symbol, call, product or power whose base is not a number."""
    if o.is_commutative is not True or o.is_Number or o.is_Order:
        return False
    if o.is_Pow:
        return not o.base.is_Number
    return o.is_Symbol or o.is_Mul or isinstance(o, sp.Function)
