"""MathML for the shared page (`lagcli report -o page.html`): sympy's presentation printer,
with the report's conventions.

    velocities, accelerations   q̇, q̈ as an accent over the coordinate (<mover>), like the
                                LaTeX report's \\dot{q}
    multipliers                 lambda_rod -> λ with the subscript "rod"
    sums                        the report's term order (q'' terms first), signs pulled out
                                (`mathml_terms`), as `lagcli.report.display.signed_sum` does

Browsers render MathML natively (MathML Core): the page needs no JavaScript for its
equations. Symbol names are printed by sympy from the spec's names (theta1 -> θ₁); a
spec's `latex:` strings are LaTeX, not MathML, and are not used here.
"""
from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from sympy.printing.mathml import MathMLPresentationPrinter

from lagcli.model.symbols import Acceleration, Velocity

ACCENTS = {Velocity: "\u02d9", Acceleration: "\u00a8"}       # ˙ and ¨ over the letter


class MathMLPrinter(MathMLPresentationPrinter):
    """sympy's MathML presentation printer with accents for q̇ and q̈."""

    def __init__(self):
        super().__init__({"mul_symbol": None, "fold_short_frac": False})

    def _print_Symbol(self, sym, style="plain"):
        for kind, accent in ACCENTS.items():
            if isinstance(sym, kind):
                base = super()._print_Symbol(sp.Symbol(sym.coordinate), style)
                over = self.dom.createElement("mover")
                over.setAttribute("accent", "true")
                mark = self.dom.createElement("mo")
                mark.appendChild(self.dom.createTextNode(accent))
                if base.tagName in ("msub", "msup", "msubsup"):      # the accent over the letter only
                    letter = base.firstChild
                    base.replaceChild(over, letter)
                    over.appendChild(letter)
                    over.appendChild(mark)
                    return base
                over.appendChild(base)
                over.appendChild(mark)
                return over
        return super()._print_Symbol(sym, style)

    _print_Dummy = _print_Symbol


def mathml(expr) -> str:
    """One expression as a MathML fragment (an <mrow>, without the <math> element)."""
    return MathMLPrinter().doprint(sp.sympify(expr))


def mathml_terms(terms: Sequence[sp.Expr]) -> str:
    """An ordered sum, each term printed with its sign pulled out (the report's order)."""
    if not terms:
        return "<mn>0</mn>"
    out = []
    for i, term in enumerate(terms):
        negative = term.could_extract_minus_sign()
        body = -term if negative else term
        shown = mathml(body)
        if body.is_Add:
            shown = f"<mrow><mo>(</mo>{shown}<mo>)</mo></mrow>"
        if i == 0:
            out.append(f"<mo>\u2212</mo>{shown}" if negative else shown)
        else:
            out.append(f"<mo>{chr(0x2212) if negative else '+'}</mo>{shown}")
    return "<mrow>" + "".join(out) + "</mrow>"


def math_block(*pieces: str) -> str:
    """A displayed equation from MathML pieces (e.g. label, <mo>=</mo>, expression)."""
    return '<math display="block"><mrow>' + "".join(pieces) + "</mrow></math>"


def mi(text: str) -> str:
    """A name as MathML (escaped)."""
    from html import escape

    return f"<mi>{escape(text)}</mi>"
