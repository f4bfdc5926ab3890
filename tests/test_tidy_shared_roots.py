"""The Pythagorean step of the reports' tidying on expressions that share a big root
(the frames bicycle's front wheel: 1/sqrt(S), S a sum of hundreds of terms, in many
terms). Its shortcuts give what sympy gives: `_expanded_term` equals
`sympy.expand(term.xreplace(table))` and `powers_in` equals `atoms(sympy.Pow)`, on
made-up terms and on the frames bicycle's own constraint rows."""
from __future__ import annotations

import pytest
import sympy as sp

from lagcli.render.tidy import _expanded_term, pythagorean, powers_in

a, b, c, r = sp.symbols("a b c r", real=True)
S = (sp.sin(a) ** 2 * sp.cos(b) ** 2 + sp.cos(a) ** 2 * sp.sin(c) ** 2 - 2 * sp.sin(a) * sp.cos(a) * sp.sin(b)
     + r * sp.cos(a) ** 4 + 1)
TERMS = [
    2 * r * sp.sin(a) ** 3 * sp.cos(b) / sp.sqrt(S),
    -r * sp.sin(a) ** 2 * sp.sqrt(S),
    r * sp.sin(a) ** 2 * sp.cos(b) ** 2 / (-2 * sp.sqrt(S) + sp.sin(a) ** 2 * r),
    sp.sin(a) ** 4 * sp.cos(c) * (r + sp.sin(a) ** 2) / S,
    sp.sin(a) ** 2 * S ** sp.Rational(-3, 2),
    sp.sin(a) ** 2 * sp.cos(a) ** 3 * (1 + sp.sin(a) ** 2) ** 2,
]


@pytest.mark.parametrize("drop, keep", [(sp.sin(a), sp.cos(a)), (sp.cos(a), sp.sin(a))])
def test_expanded_term_is_sympys_expand(drop, keep):
    nested: dict = {}
    for term in TERMS:
        powers = {p for p in powers_in(term) if p.base == drop and p.exp.is_Integer and p.exp >= 2}
        table = {p: drop ** (int(p.exp) % 2) * (1 - keep ** 2) ** (int(p.exp) // 2) for p in powers}
        assert _expanded_term(term, table, nested) == sp.expand(term.xreplace(table)), term


def test_powers_in_is_atoms():
    expr = sp.Add(*TERMS)
    assert powers_in(expr) == expr.atoms(sp.Pow)


@pytest.mark.slow
def test_frames_bicycle_rows_keep_their_tidy_form():
    """The frames bicycle's constraint rows tidied with the shortcuts equal those tidied
    with sympy's own expand and atoms (the same bytes in the report)."""
    import lagcli
    import lagcli.render.tidy as tidy

    d = lagcli.load("specs/benchmark_bicycle_frames.yaml").derivation
    def has_root(e) -> bool:
        return any(p.base.is_Add and not p.exp.is_Integer for p in e.atoms(sp.Pow))

    entries = [sp.expand(e) for row in d.constraints for e in row.a if has_root(e)]
    assert entries
    fast = [pythagorean(e) for e in entries[:6]]
    saved = tidy._expanded_term, tidy.powers_in
    try:
        tidy._expanded_term = lambda term, table, nested: sp.expand(term.xreplace(table))
        tidy.powers_in = lambda expr: expr.atoms(sp.Pow)
        slow = [pythagorean(e) for e in entries[:6]]
    finally:
        tidy._expanded_term, tidy.powers_in = saved
    assert fast == slow
