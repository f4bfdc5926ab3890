"""`display_form` of a weighted sum m_1 X + m_2 X + ... + m_n X without building it.

A chain's mass matrix entry is such a sum, one term per mass beyond the joint, with X
the tidied dot product of two Jacobian columns (l1*l2*cos(q1 - q2)): a 40-link chain
has 820 entries and ~11 000 terms, and building every term only for `display_form` to
pull X out again was half of its report. When X is a monomial (a rational number
times symbols, their powers and plain function calls) and the weights are distinct
symbols that X does not contain, each of display_form's steps is known in advance:
the sum is expanded; no power of sin or cos repeats (`pythagorean` finds nothing);
no two terms share a rest (`fold_angle_sums` folds nothing); all terms share X's
calls (`group_by_calls` makes one group) and X's number and powers are the common
factor (`common_factor`). So the result is computed from X and the sum of the weights
alone, with the same final steps and the same operation-count comparison;
tests/test_fast_sympy_rules.py compares it with display_form on every shape. The sums are
recognised as written by the derivation (`weighted_sum`: m_k times X) or flat (`flat_weighted_sum`:
-g*l4*m7*sin(q4), the terms of a chain's dV/dq_4; tests/test_report_shared_terms.py).
"""
from __future__ import annotations

import sympy as sp
from sympy.core.mul import _keep_coeff

from lagcli.model.products import product
from lagcli.model.sums import total
from lagcli.render.operations import count_ops
from lagcli.render.tidy import (DISPLAY_MAX_NODES, MAX_POWER, _square_arguments, common_factor,
                                is_expanded, pull_signs)


def weighted_display_form(weights, shared, signs=pull_signs) -> sp.Expr | None:
    """display_form(sum(w * shared for w in weights)), or None when the shortcut does not
    apply (the caller then builds the sum). `signs`: pull_signs, or one remembering its
    results (a chain's entries of one column share their sum of masses)."""
    split = _monomial(shared)
    if split is None or len(weights) < 2 or len(set(weights)) != len(weights) \
            or not all(w.is_Symbol for w in weights) or not shared.free_symbols.isdisjoint(weights):
        return None
    number, powers, calls = split
    first = product(weights[0], shared)                            # every term counts as this one
    grouped = product(_keep_coeff(number, product(*powers, total(weights)), clear=True, sign=True), product(*calls))
    result = signs(common_factor(grouped))
    negative = number.is_negative
    whole = len(weights) * count_ops(-first if negative else first) + len(weights) - 1 + negative
    return result if count_ops(result) <= whole else None


def weighted_sum(expr) -> tuple[list, sp.Expr] | None:
    """([m_1, ..., m_n], X) when expr = m_1 X + ... + m_n X (symbols m_k, one X)."""
    if not expr.is_Add:
        return None
    weights, shared = [], None
    for term in expr.args:
        if not (term.is_Mul and len(term.args) == 2):
            return None
        first, second = term.args
        weight, rest = (first, second) if first.is_Symbol else (second, first)
        if not weight.is_Symbol or rest.is_Symbol or (shared is not None and rest != shared):
            return None
        weights.append(weight)
        shared = rest
    return weights, shared


def flat_weighted_sum(expr) -> tuple[list, sp.Expr] | None:
    """([w_1, ..., w_n], X) when each term of the sum expr is the product X w_k written flat
    (-g*l4*m7*sin(q4): X = -g*l4*sin(q4)), w_k symbols, X free of sums: the canonical factors
    of each term are X's with w_k among them, so sum(w_k * X) is expr itself."""
    if not expr.is_Add or not all(term.is_Mul for term in expr.args):
        return None
    first, second = expr.args[0].args, expr.args[1].args
    differing = [a for a in first if a not in second]
    if len(differing) != 1 or not differing[0].is_Symbol:
        return None
    shared_args = tuple(a for a in first if a is not differing[0])
    if not shared_args or any(a.is_Add for a in shared_args):
        return None
    weights, shared_set = [], set(shared_args)    # looked up by hash: sympy's == per pair was most of it
    for term in expr.args:
        weight = [a for a in term.args if a not in shared_set]
        if len(weight) != 1 or not weight[0].is_Symbol \
                or tuple(a for a in term.args if a is not weight[0]) != shared_args:
            return None
        weights.append(weight[0])
    shared = shared_args[0] if len(shared_args) == 1 else sp.Mul._from_args(shared_args, True)
    return weights, shared


def _monomial(shared):
    """(number, [symbols and their powers], [calls]) of a plain monomial, else None."""
    if not (shared.is_Mul or shared.is_Symbol or shared.is_Pow or shared.is_Function):
        return None
    if not is_expanded(shared) or _square_arguments(shared):
        return None
    number, factors = shared.as_coeff_mul()
    if not number.is_Rational or number == 0:
        return None
    powers, calls = [], []
    for factor in factors:
        if factor.is_Pow and abs(factor.exp) > MAX_POWER:
            return None
        if factor.has(sp.Function):
            if factor.is_Pow or common_factor(factor) != factor:
                return None
            calls.append(factor)
        elif factor.is_Symbol or (factor.is_Pow and factor.exp.is_Integer and factor.exp > 0):
            powers.append(factor)
        else:
            return None
    return number, powers, calls


def _nodes(expr) -> int:
    return sum(1 for _ in sp.preorder_traversal(expr))
