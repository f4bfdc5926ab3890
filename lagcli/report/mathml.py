"""MathML for the shared page (`lagcli report -o page.html`): sympy's presentation printer,
with the report's conventions.

    velocities, accelerations   q̇, q̈ as an accent over the coordinate (<mover>), like the
                                LaTeX report's \\dot{q}
    multipliers                 lambda_rod -> λ with the subscript "rod"
    sums                        the report's term order (q'' terms first), signs pulled out
                                (`mathml_terms`), as `lagcli.report.display.signed_sum` does

Browsers render MathML natively (MathML Core): the page needs no JavaScript for its
equations. A spec's `latex:` name is used when it is a plain symbol (a letter, a Greek
letter or \\ell, with a one-group subscript or superscript: `m_c`, `\\theta_1`,
`\\ell`: `latex_symbol`); any other symbol is printed by sympy from its name
(theta1 -> θ₁), so the page shows the same letters as the LaTeX report for the
common cases.
"""
from __future__ import annotations

import re
import unicodedata
from collections.abc import Sequence
from html import escape

import sympy as sp
from sympy.printing.mathml import MathMLPresentationPrinter

from lagcli.model.symbols import Acceleration, Velocity

ACCENTS = {Velocity: "\u02d9", Acceleration: "\u00a8"}       # ˙ and ¨ over the letter


_LATEX_SYMBOL = re.compile(r"(\\[A-Za-z]+|[A-Za-z])(?:([_^])(\{[A-Za-z0-9]+\}|[A-Za-z0-9]))?")


def latex_symbol(latex: str) -> str | None:
    """A spec's `latex:` name as MathML when it is a plain symbol (`m_c`, `\\theta_1`,
    `\\ell`, `x^{*}` is not), else None."""
    match = _LATEX_SYMBOL.fullmatch(latex.strip())
    if not match:
        return None
    base, kind, script = match.groups()
    letter = _letter(base)
    if letter is None:
        return None
    out = f"<mi>{escape(letter)}</mi>"
    if kind:
        script = script.strip("{}")
        tag = "mn" if script.isdigit() else "mi"
        element = "msub" if kind == "_" else "msup"
        out = f"<{element}>{out}<{tag}>{escape(script)}</{tag}></{element}>"
    return out


def _letter(base: str) -> str | None:
    if not base.startswith("\\"):
        return base
    name = base[1:]
    if name == "ell":
        return "\u2113"
    case = "CAPITAL" if name[0].isupper() else "SMALL"
    try:
        return unicodedata.lookup(f"GREEK {case} LETTER {name.upper().removeprefix('VAR')}")
    except KeyError:
        return None


def model_names(model) -> dict:
    """{symbol: MathML} of the model's symbols whose `latex:` name is a plain symbol."""
    given = [*model.coordinate_latex.items(), *((p.symbol, p.latex) for p in model.parameters),
             *((u.symbol, u.latex) for u in model.inputs)]
    names = {symbol: latex_symbol(latex) for symbol, latex in given if latex}
    return {symbol: shown for symbol, shown in names.items() if shown}


class MathMLPrinter(MathMLPresentationPrinter):
    """sympy's MathML presentation printer with accents for q̇ and q̈ and the spec's names."""

    def __init__(self, names: dict | None = None):
        super().__init__({"mul_symbol": None, "fold_short_frac": False})
        self.names = {symbol.name: shown for symbol, shown in (names or {}).items()}

    def _named(self, name: str):
        from xml.dom.minidom import parseString

        shown = self.names.get(name)
        return None if shown is None else parseString(shown).documentElement

    def _print_Symbol(self, sym, style="plain"):
        for kind, accent in ACCENTS.items():
            if isinstance(sym, kind):
                base = self._named(sym.coordinate) or super()._print_Symbol(sp.Symbol(sym.coordinate), style)
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
        return self._named(sym.name) or super()._print_Symbol(sym, style)

    _print_Dummy = _print_Symbol


def mathml(expr, names: dict | None = None) -> str:
    """One expression as a MathML fragment (without the <math> element); `names`:
    `model_names(model)`."""
    return MathMLPrinter(names).doprint(sp.sympify(expr))


def mathml_terms(terms: Sequence[sp.Expr], names: dict | None = None) -> str:
    """An ordered sum, each term printed with its sign pulled out (the report's order)."""
    if not terms:
        return "<mn>0</mn>"
    out = []
    for i, term in enumerate(terms):
        negative = term.could_extract_minus_sign()
        body = -term if negative else term
        shown = mathml(body, names)
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
