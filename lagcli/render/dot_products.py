"""`display_form` of a planar dot product c R sin(x) sin(y) + c R cos(x) cos(y), found directly.

Every off-diagonal entry of a planar chain's mass matrix is such a sum times a sum of
masses: the dot product of two links' directions, l_i l_j (sin q_i sin q_j + cos q_i cos q_j)
expanded. display_form folds it into c R cos(x - y) (`fold_angle_sums`), and the report
found that result by the sum's shape (`lagcli.render.shapes`: renaming each of a 40-link
chain's 780 entries to placeholders and back cost more than this recognition). When the
two terms have the same rational number c, the same other factors R (symbols and positive
integer powers of symbols) and call sin and cos of the same two distinct symbols x, y, each
of display_form's steps is known in advance: the sum is expanded; no sin or cos is squared
(`pythagorean` finds nothing); the pair folds into c R cos(x - y), x the symbol first in
sympy's order (`trig_call` pulls no sign out of a cosine); that one term is its own group of
calls with nothing to pull out (`group_by_calls`, `common_factor`), holds no sum to flip
(`pull_signs`), and has fewer operations than the sum. tests/test_dot_products.py compares
`folded_dot_product` with display_form on random sums of this shape and near it.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.angle_calls import trig_call
from lagcli.model.products import product


def folded_dot_product(expr) -> sp.Expr | None:
    """c R cos(x - y) for expr = c R sin(x) sin(y) + c R cos(x) cos(y) (see the module
    docstring), the expression display_form gives; None for any other expr."""
    if not expr.is_Add or len(expr.args) != 2 or not expr.is_commutative:
        return None
    first, second = (_split(term) for term in expr.args)
    if first is None or second is None or first[1:] != second[1:] or {first[0], second[0]} != {sp.sin, sp.cos}:
        return None
    _, number, rest, (x, y) = first
    return product(number, *rest, trig_call(sp.cos, _difference(x, y)))


def _difference(x, y) -> sp.Add:
    """x - y of two symbols, the sum sympy builds (x, then the product -1*y: sympy sorts a symbol
    before a product), without its general flatten (most of the time of the recognition)."""
    return sp.Add._from_args((x, sp.Mul._from_args((sp.S.NegativeOne, y))))


def _split(term) -> tuple | None:
    """(f, c, R, (x, y)) of a term c R f(x) f(y), f sin or cos, x and y symbols, x's name
    first; R a tuple of symbols and their positive integer powers. None for any other term."""
    if not term.is_Mul:
        return None
    number, factors = term.as_coeff_mul()
    if not number.is_Rational:     # not 0 either: a product with the factor 0 is 0, no Mul
        return None
    calls = [f for f in factors if type(f) in (sp.sin, sp.cos)]
    if len(calls) != 2 or type(calls[0]) is not type(calls[1]):
        return None
    x, y = sorted((call.args[0] for call in calls), key=_name)
    if type(x) is not sp.Symbol or type(y) is not sp.Symbol or x.name == y.name:
        return None
    rest = tuple(f for f in factors if f is not calls[0] and f is not calls[1])    # by identity: no __eq__
    if not all(f.is_Symbol or (f.is_Pow and f.base.is_Symbol and f.exp.is_Integer and f.exp > 0) for f in rest):
        return None
    return type(calls[0]), number, rest, (x, y)


def _name(arg) -> str:
    """A symbol's name: the order of sympy's sort key among symbols (`default_sort_key`)."""
    return arg.name if type(arg) is sp.Symbol else ""
