"""`angle_entry_rates` (the report's derivatives of a chain's mass-matrix entry, built at
once) gives the derivation's derivative (`calculus.derivative`) and sympy's own
(`sympy.diff`), node for node, on entries of that shape and near it; where it declines,
the report takes the general path."""
from __future__ import annotations

import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from lagcli.model import calculus
from lagcli.model.products import product
from lagcli.report.derivatives import angle_entry_rates

q = [sp.Symbol(f"q{k}", real=True) for k in range(1, 13)]
m = [sp.Symbol(f"m{k}", positive=True) for k in range(1, 13)]
c = [sp.Symbol(f"c{k}") for k in range(1, 13)]          # no assumptions: compared by them too
x = sp.Symbol("x")                                      # not known real: not a plain angle

angles = st.one_of(
    st.tuples(st.integers(0, 11), st.integers(0, 11)).filter(lambda ij: ij[0] != ij[1])
    .map(lambda ij: q[ij[0]] - q[ij[1]]),
    st.sampled_from(q),
    st.tuples(st.lists(st.sampled_from(q), min_size=1, max_size=3, unique=True),
              st.lists(st.sampled_from([1, -1, 2, -3]), min_size=3, max_size=3))
    .map(lambda sc: sp.Add(*(k * s for k, s in zip(sc[1], sc[0])))),
    st.just(q[0] + x))
factors = st.one_of(
    st.sampled_from([*m, *c]),
    st.lists(st.sampled_from(m), min_size=2, max_size=5, unique=True).map(lambda ms: sp.Add(*ms)),
    st.tuples(st.sampled_from(c + q[:2]), st.sampled_from([2, 3, -1])).map(lambda be: be[0] ** be[1]),
    st.sampled_from([q[0], q[1] + m[0], sp.sin(q[2]), sp.Rational(1, 2), sp.Integer(-2), sp.Integer(3)]))


@settings(max_examples=300, deadline=None)
@given(others=st.lists(factors, max_size=4), angle=angles, call=st.sampled_from([sp.sin, sp.cos]))
def test_angle_entry_rates_are_the_derivations_derivatives(others, angle, call):
    entry = sp.Mul(*others, call(angle))
    rates = angle_entry_rates(entry, {}, {})
    for var, found in rates.items():
        assert sp.srepr(found) == sp.srepr(calculus.derivative(entry, var, {})), (entry, var)
        assert sp.srepr(found) == sp.srepr(sp.diff(entry, var)), (entry, var)


def test_angle_entry_rates_of_chain_entries_are_found():
    """The chain's shape, l_i l_j (m_j + ... + m_n) cos(q_i - q_j), with and without a number."""
    for i, j in [(0, 1), (3, 10), (9, 2)]:
        mass = sp.Add(*m[j:])
        for entry in (c[i] * c[j] * mass * sp.cos(q[i] - q[j]), c[i] ** 2 * mass * sp.sin(q[i]),
                      sp.Rational(1, 2) * c[i] * mass * sp.cos(q[i] - q[j]), 2 * sp.cos(q[i] + 2 * q[j])):
            rates = angle_entry_rates(entry, {}, {})
            assert rates, entry
            for var, found in rates.items():
                assert sp.srepr(found) == sp.srepr(sp.diff(entry, var)), (entry, var)


def test_angle_entry_rates_decline_other_shapes():
    mass = m[0] + m[1]
    for entry in (product(2, mass, sp.cos(q[0] - q[1])),   # a number times a sum: distributed
                  q[0] * sp.cos(q[0] - q[1]),              # another factor varies
                  sp.sin(q[2]) * sp.cos(q[0] - q[1]),      # two calls
                  sp.cos(q[0] - q[1]) ** 2,                # a power of the call
                  c[0] * sp.cos(q[0] + x),                 # not a plain angle
                  c[0] * sp.cos(q[0]) + c[1]):             # not a product
        assert angle_entry_rates(entry, {}, {}) == {}, entry


def test_chain_reports_take_the_direct_rates(tmp_path):
    """A 7-link chain's derivatives of M, as the report takes them, are the derivation's."""
    import lagcli
    from lagcli.report.display import Display

    from conftest import nlink_spec

    d = lagcli.load(str(nlink_spec(tmp_path, 7))).derivation
    shown = Display(d)
    n = len(d.model.q)
    for i in range(n):
        for j in range(n):
            for k in range(n):
                expected = calculus.derivative(shown.M[i][j], d.model.q[k], {})
                assert sp.srepr(shown._dM(i, j, k)) == sp.srepr(expected), (i, j, k)
    assert any(shown._angle_rates.values())
