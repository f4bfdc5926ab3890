"""`lagcli.render.shapes.Shapes` (a result remembered for an expression's shape, renamed
back for the next expression of that shape) gives what computing it afresh gives, node
for node (`srepr`: the same arguments in the same order, so the same printed bytes).
The oracle is the function itself, called directly on each expression: the report's
tidying (`display_form`, `pull_signs`, `Display.tidy`) on chain-like expressions whose
symbols' names sort in every order ("q10" < "q2" as names), with mixed assumptions."""
from __future__ import annotations

import functools

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from lagcli.render.shapes import Shapes, renamed, renamings
from lagcli.render.tidy import display_form, pull_signs

q = [sp.Symbol(f"q{k}", real=True) for k in range(1, 13)]
l = [sp.Symbol(f"l{k}", positive=True) for k in range(1, 13)]
m = [sp.Symbol(f"m{k}", positive=True) for k in range(1, 13)]
c = [sp.Symbol(f"c{k}") for k in range(1, 13)]          # no assumptions: compared by them too
indices = st.lists(st.integers(0, 11), min_size=4, max_size=4, unique=True)


def dot(i: int, j: int, number=1) -> sp.Expr:
    """A planar chain's dot product of two Jacobian columns, as the derivation writes it."""
    return number * (l[i] * l[j] * sp.sin(q[i]) * sp.sin(q[j]) + l[i] * l[j] * sp.cos(q[i]) * sp.cos(q[j]))


def shapes_of(draw_indices) -> list[sp.Expr]:
    i, j, k, h = draw_indices
    return [
        dot(i, j), dot(i, j, -2), dot(i, i),
        sp.Add(*(w * dot(i, j) for w in (m[k], m[h], m[j]))),          # a mass matrix entry
        sp.Add(*(w * dot(i, i) for w in (m[k], m[h]))),
        dot(i, j) * (m[k] + m[h] + m[j]), dot(i, i) * (m[k] + m[h]), m[k] * dot(i, j),   # entries as products
        c[i] * sp.sin(q[i] - q[j]) * (m[k] + m[h]) - c[j] * sp.cos(q[j]) ** 2 + c[j] * sp.sin(q[j]) ** 2,
        l[i] * (m[k] - m[h]) * sp.cos(q[i] + q[j]) + l[j] * m[k] * sp.sin(q[h]) ** 2 * sp.Rational(3, 2),
        -q[i] - q[j] + 2 * q[k], (q[j] - q[i]) * (-c[k] - c[h]) * l[i],
    ]


@pytest.mark.parametrize("tidy", [display_form, pull_signs], ids=["display_form", "pull_signs"])
@settings(max_examples=45, deadline=None)
@given(index_sets=st.lists(indices, min_size=2, max_size=4))
def test_remembered_by_shape_is_the_direct_result(tidy, index_sets):
    remembered = Shapes(tidy)
    for index_set in index_sets:
        for expr in shapes_of(index_set):
            assert sp.srepr(remembered(expr)) == sp.srepr(tidy(expr)), expr


def test_display_tidy_by_shape_is_the_tree_tidied_directly(tmp_path, monkeypatch):
    """Every entry of a 12-link chain's mass matrix, X (m_k + ... + m_n) (its dot product X
    tidied by shape, from an entry before of that shape), is the entry tidied by a Display
    made without shapes (so no tidied part is shared with the first)."""
    import lagcli
    from lagcli.report import display

    from conftest import nlink_spec

    d = lagcli.load(str(nlink_spec(tmp_path, 12))).derivation
    shown = display.Display(d)
    monkeypatch.setattr(display, "Shapes", lambda function: function)     # every sum tidied directly
    direct = display.Display(d)
    n = len(d.model.q)
    for i in range(n):
        for j in range(i, n):
            assert sp.srepr(shown.M[i][j]) == sp.srepr(direct.M[i][j]), (i, j)
            assert sp.srepr(shown.M[i][j]) == sp.srepr(display_form(d.mass_matrix[i, j])), (i, j)


def test_not_plain_has_no_shape():
    x = sp.Symbol("x", real=True)
    assert renamings(sp.exp(x) + x) is None
    assert renamings(sp.Float(1.5) * x) is None
    assert renamings(sp.Symbol("x") + x) is None       # one name, two sets of assumptions


def test_renamed_keeps_argument_order_and_form():
    a, b = sp.symbols("a b", real=True)
    unevaluated = sp.Mul(2, a + b, evaluate=False)       # common_factor's 2*(a + b)
    forward, back = renamings(unevaluated)
    nodes: dict = {}
    there = renamed(unevaluated, forward, nodes)
    assert there.is_Mul and len(there.args) == 2
    assert sp.srepr(renamed(there, back, nodes)) == sp.srepr(unevaluated)


@settings(max_examples=40, deadline=None)
@given(index_sets=st.lists(indices, min_size=2, max_size=3))
def test_shape_keys_are_equal_exactly_when_the_renamed_expressions_are(index_sets):
    from lagcli.render.shapes import shape_key

    exprs = [e for index_set in index_sets for e in shapes_of(index_set)]
    keyed = []
    for expr in exprs:
        forward, _ = renamings(expr)
        keyed.append((shape_key(expr, forward, {}), renamed(expr, forward, {})))
    for key, shape in keyed:
        for other_key, other_shape in keyed:
            assert (key == other_key) == (shape == other_shape)


def test_marked_symbols_are_part_of_the_shape():
    """Generated code's tidying collects over the velocities: two expressions of one shape
    whose velocities sit in different places are tidied each for itself."""
    from lagcli.render.tidy import tidy_expression

    a, b, c, d, k, h = sp.symbols("a b c d k h", real=True)
    velocities = {a, d}
    first = a * b * k + a * b * h + a * k * h + b * k * h     # the velocity a leads
    second = c * d * k + c * d * h + c * k * h + d * k * h    # same shape, the velocity d second
    remembered = Shapes(lambda e: tidy_expression(e, velocities), marked=velocities)
    for expr in (first, second):
        assert sp.srepr(remembered(expr)) == sp.srepr(tidy_expression(expr, velocities))
    unmarked = Shapes(lambda e: tidy_expression(e, velocities))
    unmarked(first)
    assert unmarked(second) != tidy_expression(second, velocities)     # the test would see it


@pytest.mark.parametrize("n", [7, 12])
def test_generated_code_tidied_by_shape_is_each_expression_tidied(tmp_path, n):
    """Every expression of a chain's generated code (M's entries, F, the invariants) tidied
    by shape (`targets.expressions.tidied`) is that expression tidied directly, with no
    cache (12 links: names that sort out of numeric order, q10 < q2)."""
    import lagcli
    from lagcli.render.tidy import tidy_expression
    from lagcli.targets.expressions import collect, tidied

    from conftest import nlink_spec

    system = lagcli.load(nlink_spec(tmp_path, n))
    d = system.derivation
    derived = collect(d, system.layout, tidy=False)
    by_shape = tidied(derived, d.model.qd)
    for name, exprs in derived.groups().items():
        for expr, shaped in zip(exprs, getattr(by_shape, name)):
            assert sp.srepr(shaped) == sp.srepr(tidy_expression(expr, d.model.qd)), (name, expr)


def test_a_renamed_call_is_the_node_sympy_builds():
    from lagcli.model.angle_calls import trig_node

    a, b = sp.symbols("a b", real=True)
    for function in (sp.sin, sp.cos):
        for arg in (a, a - b, b - a, 2 * a + b):
            built, sympys = trig_node(function, arg), function(arg, evaluate=False)
            assert sp.srepr(built) == sp.srepr(sympys) and built == sympys and hash(built) == hash(sympys)
            assert built.nargs == sympys.nargs and built.is_real == sympys.is_real
