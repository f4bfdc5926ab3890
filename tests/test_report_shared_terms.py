"""The report's shortcuts give what the direct path gives, node for node (`srepr`) or byte
for byte: a term remembered for one section and reused in another (`signed_sum`'s
pieces, `ordered_terms`' bucket terms) is what that section computes afresh, and a sum of
symbols is one `display_form`'s steps keep. The oracle is the direct computation on a
fresh object (no memo shared), on chain-like expressions whose names sort in every order
("q10" < "q2" as names) and with mixed assumptions."""
from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from lagcli.render.spec_printer import remembering_spec_str, spec_str
from lagcli.render.tidy import display_form, display_steps, sum_of_symbols
from lagcli.report.display import Display, ordered_terms, signed_sum

q = [sp.Symbol(f"q{k}", real=True) for k in range(1, 13)]
qd = [sp.Symbol(f"q{k}_dot", real=True) for k in range(1, 13)]
m = [sp.Symbol(f"m{k}", positive=True) for k in range(1, 13)]
c = [sp.Symbol(f"c{k}") for k in range(1, 13)]          # no assumptions: compared by them too
symbols = st.sampled_from([*q, *m, *c])


@settings(max_examples=60, deadline=None)
@given(chosen=st.lists(symbols, min_size=2, max_size=12, unique=True))
def test_a_sum_of_symbols_is_what_display_forms_steps_give(chosen):
    add = sp.Add(*chosen)
    assert sum_of_symbols(add)
    assert sp.srepr(display_form(add)) == sp.srepr(display_steps(add))


def _terms(draw_indices) -> list[sp.Expr]:
    i, j, k = draw_indices
    mass = m[k] + m[j] + m[i]
    return [c[i] * mass * qd[i] * qd[j] * sp.cos(q[i] - q[j]), -c[j] * mass * qd[j] ** 2 * sp.sin(q[i] - q[j]) / 2,
            -(c[i] - c[j]) * qd[k], c[k] * sp.sin(q[k]), -m[i] * (c[j] + c[k])]


indices = st.lists(st.integers(0, 11), min_size=3, max_size=3, unique=True)


@settings(max_examples=40, deadline=None)
@given(index_sets=st.lists(indices, min_size=2, max_size=4), order=st.randoms(use_true_random=False))
def test_signed_sum_with_remembered_pieces_is_the_direct_sum(index_sets, order):
    pieces: dict = {}
    printer = remembering_spec_str()
    sums = [_terms(s) for s in index_sets] + [sum((_terms(s) for s in index_sets), [])]
    for terms in sums:
        order.shuffle(terms)
        assert signed_sum(terms, printer, pieces) == signed_sum(terms, spec_str)


@settings(max_examples=40, deadline=None)
@given(index_sets=st.lists(indices, min_size=2, max_size=4))
def test_ordered_terms_with_remembered_buckets_are_the_direct_terms(index_sets):
    made: dict = {}
    places: dict = {}
    tidy = display_form
    for index_set in index_sets:
        i, j, k = index_set
        buckets = {qd[i] ** 2: _terms(index_set)[1], qd[i] * qd[j]: _terms(index_set)[0],
                   qd[k]: c[k] * m[i] - c[j] * m[i], sp.S.One: _terms(index_set)[4] + c[i] * sp.sin(q[j])}
        for sign in (1, -1):
            shared = ordered_terms(buckets, qd, tidy, sign=sign, made=made, places=places)
            direct = ordered_terms(buckets, qd, tidy, sign=sign)
            assert [sp.srepr(t) for t in shared] == [sp.srepr(t) for t in direct]


def test_display_sections_sharing_terms_are_the_sections_made_alone(tmp_path):
    """A 6-link chain's equations, F and explicit-form parts, made by one Display (sharing
    bucket terms) in report order, are those made by a fresh Display each."""
    import lagcli

    from conftest import nlink_spec

    d = lagcli.load(str(nlink_spec(tmp_path, 6))).derivation
    shown = Display(d)
    sections = [("equation", ()), ("forcing", ()), ("part_terms", (["velocity"],)), ("part_terms", (["position"],))]
    for i in range(len(d.model.q)):
        for name, extra in sections:
            shared = getattr(shown, name)(i, *extra)
            alone = getattr(Display(d), name)(i, *extra)
            assert [sp.srepr(t) for t in shared] == [sp.srepr(t) for t in alone], (name, i)


@settings(max_examples=60, deadline=None)
@given(chosen=st.lists(symbols, min_size=2, max_size=12, unique=True))
def test_a_sum_of_symbols_has_no_common_factor(chosen):
    from lagcli.render.tidy import common_factor

    add = sp.Add(*chosen)
    assert sp.srepr(common_factor(add)) == sp.srepr(sp.factor_terms(add))


def _expressions():
    leaves = st.sampled_from([*q[:4], *m[:4], *c[:4], sp.Rational(1, 2), sp.Integer(-3), sp.Integer(2)])

    def grow(children):
        pair = st.tuples(children, children)
        return st.one_of(pair.map(lambda ab: ab[0] + ab[1]), pair.map(lambda ab: ab[0] * ab[1]),
                         pair.map(lambda ab: ab[0] - ab[1]), children.map(sp.sin), children.map(sp.cos),
                         st.tuples(children, st.integers(-3, 3)).map(lambda be: be[0] ** be[1]),
                         pair.map(lambda ab: ab[0] / ab[1] if ab[1] != 0 else ab[0]))

    return st.recursive(leaves, grow, max_leaves=12)


@settings(max_examples=60, deadline=None)
@given(exprs=st.lists(_expressions(), min_size=2, max_size=8))
def test_remembering_printer_prints_what_the_plain_printer_prints(exprs):
    """The remembering spec printer (printed parts and parenthesized factors kept) on
    expressions sharing parts, each printed again in products and powers."""
    printer = remembering_spec_str()
    for expr in exprs + [sp.Mul(*exprs), -sp.Add(*exprs)] + [e ** 2 for e in exprs]:
        assert printer(expr) == spec_str(expr)


@settings(max_examples=60, deadline=None)
@given(chosen=st.lists(symbols, min_size=2, max_size=8, unique=True), signs=st.lists(st.booleans(), min_size=8, max_size=8))
def test_a_sum_of_signed_symbols_has_the_common_factor_of_factor_terms(chosen, signs):
    from lagcli.render.tidy import common_factor

    add = sp.Add(*(-s if negative else s for s, negative in zip(chosen, signs)))
    assert sp.srepr(common_factor(add)) == sp.srepr(sp.factor_terms(add))


@settings(max_examples=60, deadline=None)
@given(index_sets=indices, weights=st.lists(st.sampled_from(m + c), min_size=2, max_size=6, unique=True),
       number=st.sampled_from([1, -1, 2, sp.Rational(-1, 2)]), power=st.integers(1, 3))
def test_a_flat_weighted_sum_is_shown_as_display_form_shows_it(index_sets, weights, number, power):
    """dV/dq_i of a chain, -g l_i m_i sin(q_i) - g l_i m_(i+1) sin(q_i) - ...: the sum rebuilt
    from the weights and X is the sum itself, and the weighted form of it is display_form's."""
    from lagcli.render.weighted import flat_weighted_sum, weighted_display_form

    i, j, k = index_sets
    for shared in (number * c[i] * q[j] ** power * sp.sin(q[k]), number * c[i] * sp.cos(q[i] - q[j]),
                   number * q[k] ** power):
        add = sp.Add(*(w * shared for w in weights))
        found = flat_weighted_sum(add)
        if found is None:
            continue
        assert sp.srepr(sp.Add(*(w * found[1] for w in found[0]))) == sp.srepr(add)
        shown = weighted_display_form(*found)
        if shown is not None:
            assert sp.srepr(shown) == sp.srepr(display_form(add)), add


@settings(max_examples=80, deadline=None)
@given(factors=st.lists(_expressions(), min_size=2, max_size=5), var=st.sampled_from(q[:4]))
def test_one_factor_derivative_is_calculus_derivative(factors, var):
    """The report's derivative of a product with one varying factor is the derivation's."""
    from lagcli.model import calculus
    from lagcli.report.derivatives import one_factor_derivative

    expr = sp.Mul(*factors)
    found = one_factor_derivative(expr, var, {})
    if found is not None:
        assert sp.srepr(found) == sp.srepr(calculus.derivative(expr, var, {})), expr


def test_one_factor_derivative_of_chain_entries():
    from lagcli.model import calculus
    from lagcli.report.derivatives import one_factor_derivative

    for i, j, k in [(0, 3, 5), (2, 7, 1), (9, 10, 11)]:
        mass = sp.Add(*m[k:])
        for entry in (c[i] * c[j] * mass * sp.cos(q[i] - q[j]), -c[i] * mass * sp.sin(q[j]) * qd[i],
                      c[i] * c[j] * mass * sp.cos(q[j] - q[i] + q[k])):
            for var in (q[i], q[j], q[k]):
                found = one_factor_derivative(entry, var, {})
                direct = calculus.derivative(entry, var, {})
                assert found is None or sp.srepr(found) == sp.srepr(direct), (entry, var)


@settings(max_examples=60, deadline=None)
@given(exprs=st.lists(_expressions(), min_size=2, max_size=6), var=st.sampled_from(q[:4]))
def test_remembered_rates_are_calculus_derivatives(exprs, var):
    """Derivatives of expressions sharing parts, taken with one memo of the sums' and products'
    rates (each expression, sums and products of them, weighted sums of growing sums like a
    chain's potential), are the derivation's, each taken afresh."""
    from lagcli.model import calculus
    from lagcli.report.derivatives import derivative

    memo, rates = {}, {}
    growing = sp.Add(*(m[k] * c[0] * sp.Add(*exprs[:k + 1]) for k in range(len(exprs))))
    for expr in [*exprs, sp.Add(*exprs), sp.Mul(*exprs), *(m[k] * e for k, e in enumerate(exprs)), growing]:
        for v in (var, q[5]):
            assert sp.srepr(derivative(expr, v, memo, rates)) == sp.srepr(calculus.derivative(expr, v, {})), (expr, v)


def test_remembered_rates_of_a_chains_potential(tmp_path):
    """dV/dq_i of a 12-link chain (its sums share their terms), one memo for all i."""
    import lagcli
    from lagcli.model import calculus
    from lagcli.report.derivatives import derivative

    from conftest import nlink_spec

    d = lagcli.load(str(nlink_spec(tmp_path, 12))).derivation
    memo, rates = {}, {}
    for qi in d.model.q:
        assert sp.srepr(derivative(d.V, qi, memo, rates)) == sp.srepr(calculus.derivative(d.V, qi, {}))


@pytest.mark.parametrize("spec", ["chain6", "specs/double_pendulum.yaml", "specs/heavy_symmetric_top.yaml",
                                  "specs/ex20_spinning_disk_double_pendulum.yaml", "specs/cart_pole.yaml"])
def test_velocity_buckets_are_the_christoffel_sums_by_sympy(spec, tmp_path):
    """c_i by monomial (pairs whose terms cancel skipped without sympy arithmetic) is the
    notes' sum of sympy derivatives of the tidied M, over every pair j <= l."""
    import lagcli

    from conftest import ROOT, nlink_spec

    path = nlink_spec(tmp_path, 6) if spec == "chain6" else ROOT / spec
    d = lagcli.load(str(path)).derivation
    shown = Display(d)
    M, q, qd, n = shown.M, shown.q, shown.qd, shown.n
    for i in range(n):
        expected = {}
        for j in range(n):
            for l in range(j, n):
                if j == l:
                    c = sp.diff(M[i][j], q[j]) - sp.diff(M[j][j], q[i]) / 2
                else:
                    c = sp.diff(M[i][j], q[l]) + sp.diff(M[i][l], q[j]) - sp.diff(M[j][l], q[i])
                if c != 0:
                    expected[qd[j] * qd[l]] = c
        assert shown.velocity_buckets(i) == expected, (spec, i)


@settings(max_examples=80, deadline=None)
@given(number=st.sampled_from([sp.Integer(-1), sp.Integer(2), sp.Rational(-1, 2)]),
       factors=st.lists(_expressions(), min_size=1, max_size=4), var=st.sampled_from(q[:4]))
def test_a_product_with_a_leading_number_and_its_shared_rates_are_calculus_derivatives(number, factors, var):
    """A product with a leading number (a chain's -g m_k (l_1 cos(q_1) + ...)), derived for
    two variables with one memo of rates (the product of the other factors shared when the
    two derivatives differ in sign only), is the derivation's derivative, taken afresh."""
    from lagcli.model import calculus
    from lagcli.report.derivatives import derivative, one_factor_derivative

    expr = sp.Mul(number, *factors)
    memo, rates = {}, {}
    for v in (var, q[(q.index(var) + 1) % 4], var):
        direct = calculus.derivative(expr, v, {})
        assert sp.srepr(derivative(expr, v, memo, rates)) == sp.srepr(direct), (expr, v)
        found = one_factor_derivative(expr, v, {})
        assert found is None or sp.srepr(found) == sp.srepr(direct), (expr, v)


def test_angle_differences_derived_for_both_angles_share_their_product():
    from lagcli.model import calculus
    from lagcli.report.derivatives import derivative

    memo, rates = {}, {}
    for i, j, k in [(0, 3, 5), (2, 7, 1), (9, 10, 11)]:
        for entry in (-c[i] * sp.Add(*m[k:]) * sp.cos(q[i] - q[j]), 3 * c[j] * sp.sin(q[j] - q[i] + q[k]) * m[i]):
            for var in (q[i], q[j], q[k], q[i]):
                assert sp.srepr(derivative(entry, var, memo, rates)) == sp.srepr(calculus.derivative(entry, var, {}))


@settings(max_examples=80, deadline=None)
@given(weights=st.lists(st.sampled_from(m + c), min_size=2, max_size=6, unique=True),
       shared=st.lists(st.one_of(st.sampled_from([q[0], q[1], c[2], sp.sin(q[3]), sp.cos(q[0] - q[1])]),
                                 st.tuples(st.sampled_from([q[2], c[3], q[0] + c[4], sp.sin(q[1])]),
                                           st.integers(2, 9)).map(lambda be: be[0] ** be[1])),
                       min_size=1, max_size=4, unique=True),
       number=st.sampled_from([1, -1, 3, sp.Rational(-1, 2)]))
def test_a_flat_weighted_sums_expandability_is_its_shared_parts(weights, shared, number):
    """`weighted_expandable` (from X and the number of weights) is `expandable` of the sum
    w_1 X + ... + w_n X itself, high powers and powers of sums in X among them."""
    from lagcli.render.tidy import expandable, weighted_expandable
    from lagcli.render.weighted import flat_weighted_sum

    add = sp.Add(*(w * number * sp.Mul(*shared) for w in weights))
    found = flat_weighted_sum(add)
    if found is not None:
        assert weighted_expandable(len(found[0]), found[1]) == expandable(add), add


@settings(max_examples=80, deadline=None)
@given(exprs=st.lists(_expressions(), min_size=1, max_size=6))
def test_zero_minus_b_is_the_sum_of_bs_negated_terms(exprs):
    """`difference(0, b)` (Q_i = -dV/dq_i) is `total` of b's negated terms, as for any a."""
    from lagcli.model.sums import negated_terms, total
    from lagcli.report.display import difference

    for b in (sp.Add(*exprs), sp.Mul(*exprs), *exprs, sp.Add(*(m[k] * c[0] * sp.sin(q[k]) for k in range(len(exprs))))):
        assert sp.srepr(difference(sp.S.Zero, b)) == sp.srepr(total([sp.S.Zero, *negated_terms(b)])), b


@settings(max_examples=100, deadline=None)
@given(exprs=st.lists(_expressions(), min_size=1, max_size=4))
def test_nonzero_is_sympys_comparison_with_0(exprs):
    from lagcli.report.display import nonzero

    numbers = [sp.S.Zero, sp.Integer(0), sp.Float(0.0), sp.Float(-0.0), sp.Rational(0, 3), sp.Integer(2), sp.nan,
               sp.zoo, sp.oo, sp.S.Half, 0, 0.0, 1]
    for expr in [*exprs, sp.Add(*exprs), sp.Mul(*exprs), *(e - e for e in exprs), *numbers]:
        assert nonzero(expr) == (expr != 0), expr


def test_the_printers_direct_methods_are_those_sympys_walk_finds():
    """`SpecPrinter._dispatched` calls, for the classes it knows, the method Printer._print's
    walk up the classes finds (none of them has its own `_sympystr`)."""
    from lagcli.render.spec_printer import _DIRECT, SpecPrinter

    printer = SpecPrinter(remember=True)
    for cls, name in _DIRECT.items():
        classes = cls.__mro__
        if sp.Function in classes:       # Printer._print's rule for subclasses of known functions
            i = classes.index(sp.Function)
            classes = tuple(k for k in classes[:i] if k.__name__ == classes[0].__name__
                            or k.__name__.endswith("Base")) + classes[i:]
        walked = next(f"_print_{k.__name__}" for k in classes if hasattr(printer, f"_print_{k.__name__}"))
        assert walked == name and not hasattr(cls, printer.printmethod), cls


@settings(max_examples=40, deadline=None)
@given(index_sets=st.lists(indices, min_size=1, max_size=4))
def test_a_term_showing_its_velocity_mentions_one(index_sets):
    """`_shows_velocity` (a term with its monomial's first factor among its factors) is never
    true of a term free of the velocities."""
    from lagcli.report.display import _shows_velocity, signed_product

    moving = set(qd)
    for i, j, k in index_sets:
        for monomial in (qd[i] ** 2, qd[i] * qd[j], qd[k], m[i], sp.S.One):
            for coefficient in (c[i] * m[j] * sp.sin(q[i] - q[j]), -c[k] * (m[i] + m[j]), c[j]):
                term = signed_product(coefficient, monomial)
                if _shows_velocity(term, monomial, moving):
                    assert not term.free_symbols.isdisjoint(moving), term
