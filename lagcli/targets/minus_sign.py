"""sympy's `Add.could_extract_minus_sign`, with its tie-break found from the sum's leading term.

sympy pulls a minus sign out of a sum with more negative than positive terms; on a tie it
compares the sort keys of the sum and of its negative, which computes the sort key of every
subexpression: 0.7 s of CPU for the energy of the 40-link chain, a fifth of its `generate`
(bench/README.md). Those two keys differ first at the leading term of sympy's term order
(`as_ordered_terms`: the largest monomial, lexicographically over the sorted bases), whose
coefficient is c in the sum and -c in its negative: the answer is `c < 0`. The leading term
is found by walking the bases in sympy's order only as far as needed; the sort keys of big
bases are computed only when the cheap ones (symbols) do not single it out. Wherever a sum
steps outside what this argument covers (a number term, numeric factors, equal monomials,
bases with equal keys, non-commutative factors), sympy's own method decides.
"""
from __future__ import annotations

import sympy as sp
from sympy.core.exprtools import decompose_power
from sympy.core.sorting import default_sort_key


class _Undecided(Exception):
    """The leading term is not found by the shortcut: sympy decides."""


def could_extract_minus_sign(add) -> bool:
    """`add.could_extract_minus_sign()` for a sympy Add, the same answer."""
    negative = sum(1 for arg in add.args if _term_extracts(arg))
    positive = len(add.args) - negative
    if positive != negative:
        return negative > positive
    try:
        return bool(_leading_coefficient(add) < 0)
    except _Undecided:
        return add.could_extract_minus_sign()


def _term_extracts(term) -> bool:
    """`term.could_extract_minus_sign()` without building -term for its `self == -self`
    test (Mul.could_extract_minus_sign): a product not led by a number answers False
    whatever the test finds; one led by a nonzero rational c and then a factor that is
    not a number (zoo is one) differs from its negative (Mul.__neg__ writes -c or drops
    c = -1, and keeps c when zoo follows it) and answers c < 0."""
    if type(term) is sp.Mul:
        lead = term.args[0]
        if not lead.is_Number:
            return False
        second = term.args[1]
        if lead.is_Rational and lead.p != 0 and not second.is_Number and second is not sp.zoo:
            return lead.p < 0
    return term.could_extract_minus_sign()


def _leading_coefficient(add):
    """The numeric coefficient of the first term of `add.as_ordered_terms()`."""
    negated = [-term for term in add.args]
    if set(sp.Add.make_args(-add)) != set(negated):
        raise _Undecided           # -add is not the sum of the negated terms (z - 1*(x - y))
    terms = [_monomial(term, minus) for term, minus in zip(add.args, negated)]
    candidates = list(range(len(terms)))
    for base in _ordered_bases({base for _, powers in terms for base in powers}):
        best = max(terms[k][1].get(base, 0) for k in candidates)
        candidates = [k for k in candidates if terms[k][1].get(base, 0) == best]
        if len(candidates) == 1:
            return terms[candidates[0]][0]
    raise _Undecided


def _monomial(term, negated) -> tuple:
    """(coefficient, {base: exponent}) of a term as sympy's `Expr.as_terms` splits it."""
    if term.is_Number:
        raise _Undecided           # as_ordered_terms special-cases a number and a product
    coefficient, rest = term.as_coeff_Mul()
    if negated.as_coeff_Mul() != (-coefficient, rest):
        raise _Undecided           # the negative's sort key would differ elsewhere
    powers: dict = {}
    for factor in sp.Mul.make_args(rest):
        if factor.is_number or not factor.is_commutative:
            raise _Undecided       # sympy folds numbers into the coefficient
        base, exponent = decompose_power(factor)
        powers[base] = exponent
    return coefficient, powers


def _ordered_bases(bases):
    """The bases in the order of their sort keys (sympy's `gens` order), computing the
    keys of a group of bases only when the walk reaches it: bases are grouped by the
    first element of their sort key, the class key of their head."""
    groups: dict = {}
    for base in bases:
        groups.setdefault(_head(base), []).append(base)
    for head in sorted(groups):
        members = groups[head]
        keys = [_key(base) for base in members]
        if len(set(keys)) < len(keys):
            raise _Undecided       # sympy's order of equal keys follows set iteration
        yield from (members[k] for k in sorted(range(len(members)), key=keys.__getitem__))


def _head(base) -> tuple:
    """The first element of `base.sort_key()` (Expr.sort_key: the class key of the
    expression, or of the base of a power)."""
    if base.is_Symbol:
        return base.class_key()
    if not isinstance(base, (sp.Add, sp.Mul, sp.Pow, sp.Function)):
        raise _Undecided
    coefficient, rest = base.as_coeff_Mul()
    if rest.is_Pow:
        if rest.base is sp.S.Exp1:
            raise _Undecided
        rest = rest.base
    return rest.class_key()


def _key(base) -> tuple:
    """`base.sort_key()`, cheaply for a symbol."""
    if type(base) is sp.Symbol:
        return base.class_key(), (1, (base.name,)), sp.S.One.sort_key(), sp.S.One
    if type(base) is sp.Dummy:
        return base.class_key(), (2, (base.name, base.dummy_index)), sp.S.One.sort_key(), sp.S.One
    return default_sort_key(base)
