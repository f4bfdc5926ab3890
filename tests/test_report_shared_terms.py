"""The report's shortcuts give what the direct path gives, node for node (`srepr`) or byte
for byte: a term remembered for one section and reused in another (`signed_sum`'s
pieces, `ordered_terms`' bucket terms) is what that section computes afresh, and a sum of
symbols is one `display_form`'s steps keep. The oracle is the direct computation on a
fresh object (no memo shared), on chain-like expressions whose names sort in every order
("q10" < "q2" as names) and with mixed assumptions."""
from __future__ import annotations

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
    tidy = display_form
    for index_set in index_sets:
        i, j, k = index_set
        buckets = {qd[i] ** 2: _terms(index_set)[1], qd[i] * qd[j]: _terms(index_set)[0],
                   qd[k]: c[k] * m[i] - c[j] * m[i], sp.S.One: _terms(index_set)[4] + c[i] * sp.sin(q[j])}
        for sign in (1, -1):
            shared = ordered_terms(buckets, qd, tidy, sign=sign, made=made)
            direct = ordered_terms(buckets, qd, tidy, sign=sign)
            assert [sp.srepr(t) for t in shared] == [sp.srepr(t) for t in direct]


def test_display_sections_sharing_terms_are_the_sections_made_alone(tmp_path):
    """A 6-link chain's equations, F and explicit-form parts, made by one Display (sharing
    bucket terms) in report order, are those made by a fresh Display each."""
    import lagcli

    links = range(1, 7)
    lines = ["name: chain6", f"coordinates: [{', '.join(f'q{k}' for k in links)}]", "parameters:"]
    lines += [f"  {p}{k}: 1.0" for k in links for p in "ml"] + ["  g: 9.81", "gravity: [0, -g]", "particles:"]
    for k in links:
        x = " + ".join(f"l{j}*sin(q{j})" for j in range(1, k + 1))
        y = " + ".join(f"l{j}*cos(q{j})" for j in range(1, k + 1))
        lines.append(f"  P{k}: {{mass: m{k}, position: [{x}, -({y})]}}")
    path = tmp_path / "chain6.yaml"
    path.write_text("\n".join(lines) + "\n")
    d = lagcli.load(str(path)).derivation
    shown = Display(d)
    sections = [("equation", ()), ("forcing", ()), ("part_terms", (["velocity"],)), ("part_terms", (["position"],))]
    for i in range(len(d.model.q)):
        for name, extra in sections:
            shared = getattr(shown, name)(i, *extra)
            alone = getattr(Display(d), name)(i, *extra)
            assert [sp.srepr(t) for t in shared] == [sp.srepr(t) for t in alone], (name, i)
