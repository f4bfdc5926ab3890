"""The LaTeX printer of lagcli: sympy's `LatexPrinter` with the model's symbol names.

Symbols are typeset from the symbol objects of the model, never by rewriting
printed text:

    q          the coordinate's `latex:` from the spec, else sympy's name (theta1 -> \\theta_{1})
    q_dot      \\dot{<q>}    (sympy's split: theta1 -> \\dot{\\theta}_{1}; a user latex: \\dot{<latex>})
    q_ddot     \\ddot{<q>}
    parameter  its `latex:` from the spec, else sympy's name
    lambda_j   \\lambda_{j};  lambda_<name> -> \\lambda_{\\mathrm{<name>}}

`LatexPrinter.tex(expr)` returns a `Tex`: the one-line LaTeX (a `str`) that
also carries `lines`, the same expression broken at top-level sums so that no
line is wider than `CONTENT_WIDTH` (see `tex_width`), for display in `align*`.
A wide product with a long sum as a factor is broken inside a pair of fixed-size
parentheses (`\\biggl( ... \\biggr)`, which need no pairing per line).
"""
from __future__ import annotations

import functools
import re

import sympy as sp
from sympy.core.function import _coeff_isneg
from sympy.printing.latex import LatexPrinter as SympyLatexPrinter

from lagcli.render.escape import latex_text

# Widths are in units of the estimate below (`tex_width`), meant as 6 pt at 10 pt type;
# measured with pdflatex on every line of the bundled specs' documents, a unit is 5.0 to
# 6.4 pt (median 5.65). The standalone document's text is 16 cm (455 pt) wide.
LINE_WIDTH = 76.0
LABEL_WIDTH = 9.0                     # the label column of `align*` (e.g. "Q'_{\theta_{1}}" or "\ddot x\colon")
CONTENT_WIDTH = LINE_WIDTH - LABEL_WIDTH - 4.0   # minus "= " and the "\quad" of continuation lines

THIN_SPACE = r"\,"                    # between the factors of a product: m\,l\,\dot\theta, never "ml"
MIN_ROOM = 12.0                       # do not start a long term on a line with less room left
_DELIMITERS = (r"\biggl(", r"\biggr)"), (r"\Bigl(", r"\Bigr)"), (r"\bigl(", r"\bigr)")


class Tex(str):
    """One-line LaTeX of an expression, with `lines` (broken form) and `width` (estimate)."""

    lines: tuple[str, ...]
    width: float

    def __new__(cls, flat: str, lines: tuple[str, ...] | None = None) -> "Tex":
        tex = super().__new__(cls, flat)
        tex.lines = tuple(lines) if lines else (flat,)
        tex.width = tex_width(flat)
        return tex


class LatexPrinter(SympyLatexPrinter):
    """sympy's LaTeX printer with the model's symbols; see the module docstring."""

    paren = (r"\left(", r"\right)")        # around a sum that fits on one line
    delimiters = _DELIMITERS                # around a broken sum, by nesting depth
    times = r"\times"                       # a product continued on the next line

    def __init__(self, model, settings: dict | None = None, multipliers=()):
        super().__init__({"symbol_names": {}, "mul_symbol": THIN_SPACE, **(settings or {})})
        names = self._settings["symbol_names"] = dict(self._settings["symbol_names"])
        for q, qd, qdd in zip(model.q, model.qd, model.qdd):
            user = model.coordinate_latex.get(q)
            names[q] = user if user else self._name(q.name)
            names[qd] = self._accented(r"\dot", q, user)
            names[qdd] = self._accented(r"\ddot", q, user)
        for info in (*model.parameters, *model.inputs):
            names[info.symbol] = info.latex or self._name(info.symbol.name)     # the user's names win
        for multiplier, label in multipliers:
            names[multiplier] = multiplier_latex(multiplier, label)
        # Printed LaTeX and term order per subexpression: the line breaking measures a
        # sum, then its terms, then their factors, so without these each subexpression
        # would be printed (and its terms sorted) once per level above it.
        self._printed: dict = {}
        self._ordered: dict = {}

    def _print(self, expr, **kwargs) -> str:
        if kwargs or not isinstance(expr, sp.Basic):
            return super()._print(expr, **kwargs)
        tex = self._printed.get(expr)
        if tex is None:
            tex = self._printed[expr] = super()._print(expr)
        return tex

    def _as_ordered_terms(self, expr, order=None):
        if order is not None:
            return super()._as_ordered_terms(expr, order)
        terms = self._ordered.get(expr)
        if terms is None:
            terms = self._ordered[expr] = super()._as_ordered_terms(expr)
        return list(terms)

    def _accented(self, accent: str, q: sp.Symbol, user: str | None) -> str:
        if user:
            base, underscore, sub = user.partition("_")
            simple = base.lstrip("\\").isalpha() and base.count("\\") <= 1 and "^" not in user
            return f"{accent}{{{base}}}_{sub}" if underscore and sub and simple else f"{accent}{{{user}}}"
        base, supers, subs = self._split_super_sub(q.name)
        tex = f"{accent}{{{base}}}"
        if supers:
            tex += "^{%s}" % " ".join(supers)
        if subs:
            tex += "_{%s}" % " ".join(subs)
        return tex

    def tex(self, expr, width: float = CONTENT_WIDTH) -> Tex:
        expr = sp.sympify(expr)
        flat = self.doprint(expr)
        if tex_width(flat) <= width:
            return Tex(flat)
        return Tex(flat, self.lines(expr, width, 0))

    def tex_terms(self, terms, width: float = CONTENT_WIDTH) -> Tex:
        """An ordered sum (the report's term lists: q'' terms first), signs pulled out."""
        if not terms:
            return self.tex(sp.S.Zero, width)
        flat = self._join_terms(terms)
        if tex_width(flat) <= width:
            return Tex(flat)
        return Tex(flat, self._terms_lines(list(terms), width, 0, width))

    def _join_terms(self, terms) -> str:
        out = [self._print(terms[0])]
        for term in terms[1:]:
            sign, term = ("-", -term) if term.could_extract_minus_sign() else ("+", term)
            body = self._print(term)
            out.append(f"{sign} {self.paren[0]}{body}{self.paren[1]}" if self._needs_add_brackets(term)
                       else f"{sign} {body}")
        return " ".join(out)

    def _name(self, string: str) -> str:
        """sympy's name -> LaTeX (theta1 -> \\theta_{1}), with a multi-letter name set as
        one word (\\mathit{Lam}) rather than a product of letters."""
        tex = self._deal_with_super_sub(string)
        word = re.match(r"[A-Za-z]{2,}", tex)
        return rf"\mathit{{{word.group()}}}{tex[word.end():]}" if word else tex

    def symbol(self, name: str) -> str:
        """LaTeX of a name that is not in the model (a known function, a particle)."""
        return self._name(name)

    # -- breaking long expressions -------------------------------------------------
    #
    # `lines(expr, width, depth, first)` breaks `expr` into lines no wider than
    # `width`, except the first, which has `first` (the room left on a line that
    # something else has started). Joined with spaces, the lines are `expr` again.

    def lines(self, expr: sp.Expr, width: float, depth: int = 0, first: float | None = None) -> list[str]:
        first = width if first is None else first
        tex = self._print(expr)
        if tex_width(tex) <= first:
            return [tex]
        if _coeff_isneg(expr):
            return self._signed("-", -expr, width, depth, first)
        if expr.is_Add:
            return self._add_lines(expr, width, depth, first)
        if expr.is_Mul and any(f.is_Add for f in expr.args):
            return self._mul_lines(expr, width, depth, first)
        return [tex]                      # a power or function of a long sum: left whole

    def _signed(self, sign: str, expr: sp.Expr, width: float, depth: int, first: float) -> list[str]:
        if expr.is_Add:
            body = self._parenthesized(expr, width, depth, first - 2)
        else:
            body = self.lines(expr, width, depth, first - 2)
        return [f"{sign} {body[0]}", *body[1:]]

    def _add_lines(self, expr: sp.Add, width: float, depth: int, first: float) -> list[str]:
        return self._terms_lines(self._as_ordered_terms(expr), width, depth, first)

    def _terms_lines(self, terms, width: float, depth: int, first: float) -> list[str]:
        out: list[str] = []
        for i, term in enumerate(terms):
            if i == 0:
                out.extend(self.lines(term, width, depth, first))
                continue
            sign, term = ("-", -term) if term.could_extract_minus_sign() else ("+", term)
            body = self._print(term)
            flat = f"{sign} {self.paren[0]}{body}{self.paren[1]}" if self._needs_add_brackets(term) else f"{sign} {body}"
            room = _room(out, width, first)
            if tex_width(flat) <= room:
                out[-1] = f"{out[-1]} {flat}"
            elif tex_width(flat) <= width or room < MIN_ROOM:
                out.extend(self._signed(sign, term, width, depth, width))
            else:
                piece = self._signed(sign, term, width, depth, room)
                out[-1] = f"{out[-1]} {piece[0]}"
                out.extend(piece[1:])
        return out

    def _mul_lines(self, expr: sp.Mul, width: float, depth: int, first: float) -> list[str]:
        sums = [f for f in expr.args if f.is_Add]
        widest = max(sums, key=lambda f: (tex_width(self._print(f)), sp.default_sort_key(f)))
        rest = sp.Mul(*[f for f in expr.args if f is not widest])
        if rest == 1:
            return self._parenthesized(widest, width, depth, first)
        if rest.is_Add:
            out = self._parenthesized(rest, width, depth, first)
        else:
            out = self.lines(rest, width, depth, first)
        room = _room(out, width, first)
        if room < MIN_ROOM:
            piece = self._parenthesized(widest, width, depth, width - 3)
            return [*out, f"{self.times} {piece[0]}", *piece[1:]]
        piece = self._parenthesized(widest, width, depth, room)
        return [*out[:-1], f"{out[-1]} {piece[0]}", *piece[1:]]

    def _parenthesized(self, expr: sp.Expr, width: float, depth: int, first: float) -> list[str]:
        left, right = self.delimiters[min(depth, len(self.delimiters) - 1)]
        inner = self.lines(expr, width - 1.5, depth + 1, first - 1.5)
        if len(inner) == 1:
            return [f"{self.paren[0]}{inner[0]}{self.paren[1]}"]
        return [f"{left}{inner[0]}", *inner[1:-1], f"{inner[-1]}{right}"]


def _room(out: list[str], width: float, first: float) -> float:
    """Room left on the last line of `out` (whose first line has `first`)."""
    if not out:
        return first
    return (first if len(out) == 1 else width) - tex_width(out[-1]) - 1


def multiplier_latex(multiplier: sp.Symbol, label: str | None) -> str:
    """lambda_1 -> \\lambda_{1}; lambda_rolling -> \\lambda_{\\mathrm{rolling}}."""
    suffix = multiplier.name[len("lambda_"):]
    if label is None and suffix.isdigit():
        return rf"\lambda_{{{suffix}}}"
    return rf"\lambda_{{\mathrm{{{latex_text(label or suffix)}}}}}"



# -- width estimate ----------------------------------------------------------------

_TOKEN = re.compile(r"\\[A-Za-z]+|\\.|[{}^_]|[^\s\\{}^_]")
_FUNCTIONS = {"sin", "cos", "tan", "sinh", "cosh", "tanh", "asin", "acos", "atan", "log", "exp",
              "operatorname", "min", "max", "arcsin", "arccos", "arctan", "sign", "ln"}
_INVISIBLE = {r"\left", r"\right", r"\bigl", r"\bigr", r"\Bigl", r"\Bigr", r"\biggl", r"\biggr",
              r"\mathrm", r"\dot", r"\ddot", r"\mathit", r"\mathbf", r"\mathcal", r"\operatorname",
              r"\displaystyle"}
_SPACES = {r"\quad": 2.0, r"\qquad": 4.0, r"\,": 0.3, r"\;": 0.5, r"\:": 0.4, r"\!": -0.3, r"\ ": 0.5}
# Widths of math italic letters and digits at 10 pt (Computer Modern), in units of 6 pt;
# any other single character or command (a Greek letter) counts 1.
_GLYPHS = {**dict.fromkeys("abcdeghkopqrsuvxyz", 0.85), **dict.fromkeys("fijlt", 0.65),
           "m": 1.5, "n": 1.0, "w": 1.2,
           **dict.fromkeys("ABCDEGHKNOQRUXZ", 1.35), **dict.fromkeys("FLPSTVY", 1.1),
           "I": 0.75, "J": 0.95, "M": 1.65, "W": 1.6,
           **dict.fromkeys("0123456789", 0.85), "(": 0.65, ")": 0.65}
_BINARY = {"+": 2.2, "-": 2.2, "=": 2.4, r"\cdot": 1.4, r"\times": 2.2, ",": 0.8, r"\colon": 1.0}


@functools.lru_cache(maxsize=65536)
def tex_width(tex: str) -> float:
    """An estimate of the width of LaTeX math, in units of about 6 pt (see LINE_WIDTH)."""
    width, _ = _group_width(_TOKEN.findall(tex), 0)
    return width


def _group_width(tokens: list[str], i: int) -> tuple[float, int]:
    """Width of tokens[i:] up to the closing brace of the current group; returns (width, next index)."""
    width = 0.0
    while i < len(tokens):
        tok = tokens[i]
        i += 1
        if tok == "}":
            return width, i
        if tok in ("^", "_"):
            part, i = _argument(tokens, i)
            width += 0.7 * part
        elif tok == r"\frac":
            num, i = _argument(tokens, i)
            den, i = _argument(tokens, i)
            width += max(num, den) + 0.6
        elif tok == "{":
            part, i = _group_width(tokens, i)
            width += part
        elif tok in _INVISIBLE:
            if tok in (r"\left", r"\right", r"\bigl", r"\bigr", r"\Bigl", r"\Bigr", r"\biggl", r"\biggr"):
                delim, i = (tokens[i], i + 1) if i < len(tokens) else ("", i)
                width += 0.0 if delim == "." else 0.8
        elif tok in _SPACES:
            width += _SPACES[tok]
        elif tok in _BINARY:
            width += _BINARY[tok]
        elif tok.startswith("\\") and tok[1:] in _FUNCTIONS:
            width += 0.8 * (len(tok) - 1) + 0.3      # upright letters, then the operator's space
        else:
            width += _GLYPHS.get(tok, 1.0)
    return width, i


def _argument(tokens: list[str], i: int) -> tuple[float, int]:
    if i >= len(tokens):
        return 0.0, i
    if tokens[i] == "{":
        return _group_width(tokens, i + 1)
    return _group_width([tokens[i], "}"], 0)[0], i + 1
