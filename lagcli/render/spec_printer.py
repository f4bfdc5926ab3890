"""Print sympy expressions back in the spec's own expression language.

Every expression lagcli reports (text and JSON) parses back with
`lagcli.model.expr.parse`: velocities are `q_dot`, accelerations `q_ddot`, and the
function names are the contract's (`abs`, `min`, `max`, `exp(1)` for e).
"""
from __future__ import annotations

from collections.abc import Callable

import sympy as sp
from sympy.printing.str import StrPrinter

from lagcli.errors import EmitError
from lagcli.render.operator_printing import MUL, RememberedPrecedence, numerator_factor


class SpecPrinter(RememberedPrecedence, StrPrinter):
    """`remember`: keep the string of every subexpression printed and every precedence
    found (`RememberedPrecedence`), for a printer that prints many expressions sharing
    parts (a report of a 40-link chain prints the same sums of masses thousands of times,
    and its products' factors recur in thousands of terms), and every factor's text in its
    parent's parentheses (`parenthesize`). A subexpression prints the same wherever it
    stands (the parentheses around it are its parent's), so the bytes do not change.
    Without `remember` (the printer `spec_str` keeps for the process) nothing is kept."""
    _default_settings = {**StrPrinter._default_settings, "order": "none"}

    def __init__(self, settings=None, remember: bool = False):
        super().__init__(settings)
        self._memo: dict | None = {} if remember else None
        self._parenthesized: dict | None = {} if remember else None     # (item, level, strict) -> text
        self._factor_texts: dict | None = {} if remember else None      # factor -> its text in a term, or ""
        if not remember:
            self._precedences = None

    def parenthesize(self, item, level, strict=False) -> str:
        """sympy's `parenthesize` (`RememberedPrecedence`'s), each answer remembered with
        `remember`: a product's factors are printed inside thousands of products (one call
        here instead of three, each with its own lookup)."""
        memo = self._parenthesized
        if memo is None:
            return super().parenthesize(item, level, strict)
        key = (item, level, strict)
        found = memo.get(key)
        if found is None:
            found = memo[key] = super().parenthesize(item, level, strict)
        return found

    def _print_str_Mul(self, expr) -> str:
        """A report's term, a product of factors printed as they are (`numerator_factor`) at
        the precedence of a product: its factors' texts in their parentheses joined by '*'
        (`RememberedPrecedence._print_str_Mul`), each factor's text found by one look-up
        with `remember` (a 40-link chain's report prints ~6 000 such terms, from ~1 000
        distinct factors); anything else as there."""
        texts = self._factor_texts
        if texts is not None and self.order in ('old', 'none') and self.precedence_of(expr) == MUL:
            out = []
            for factor in expr.args:
                text = texts.get(factor)
                if text is None:
                    text = texts[factor] = self.parenthesize(factor, MUL, strict=False) if numerator_factor(factor) else ""
                if not text:
                    break
                out.append(text)
            else:
                return '*'.join(out)
        return super()._print_str_Mul(expr)

    def _print(self, expr, **kwargs) -> str:
        memo = self._memo
        if memo is None or kwargs or not isinstance(expr, sp.Basic):
            return super()._print(expr, **kwargs)
        found = memo.get(expr)
        if found is None:
            found = memo[expr] = self._dispatched(expr)
        return found

    def _dispatched(self, expr) -> str:
        """sympy's `Printer._print` of expr: for a sum, product, power, symbol, sin or cos the method
        its own class names (the first one Printer._print's walk up the classes finds), at
        once; anything else through that walk."""
        name = _DIRECT.get(type(expr))
        if name is None:
            return super()._print(expr)
        self._print_level += 1
        try:
            return getattr(self, name)(expr)
        finally:
            self._print_level -= 1

    def _print_Abs(self, expr):
        return f"abs({self._print(expr.args[0])})"

    def _print_Min(self, expr):
        return f"min({', '.join(self._print(a) for a in expr.args)})"

    def _print_Max(self, expr):
        return f"max({', '.join(self._print(a) for a in expr.args)})"

    def _print_Exp1(self, expr):
        return "exp(1)"

    def _print_exp(self, expr):
        return f"exp({self._print(expr.args[0])})"

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_ImaginaryUnit(self, expr):
        raise EmitError("an expression became complex; it cannot be written in the spec language")

    def _print_Infinity(self, expr):
        raise EmitError("an expression became infinite")

    _print_NegativeInfinity = _print_ComplexInfinity = _print_NaN = _print_Infinity


_DIRECT = {sp.Add: "_print_Add", sp.Mul: "_print_Mul", sp.Pow: "_print_Pow", sp.Symbol: "_print_Symbol",
           sp.sin: "_print_Function", sp.cos: "_print_Function"}    # neither has a method of its own

_PRINTER = SpecPrinter()


def spec_str(expr) -> str:
    return _PRINTER.doprint(sp.sympify(expr))


def remembering_spec_str() -> Callable[[sp.Expr], str]:
    """`spec_str` remembering what it printed (`SpecPrinter`'s `remember`): for one report."""
    printer = SpecPrinter(remember=True)
    return lambda expr: printer.doprint(sp.sympify(expr))


def output_names(model, multipliers=()) -> dict:
    """Names an output expression may use: inputs plus q_ddot and the multipliers."""
    names = {s.name: s for s in (*model.q, *model.qd, *model.qdd, *model.parameter_symbols,
                                 *model.input_symbols, *multipliers)}
    return {"pi": sp.pi, **names}


def parse_output(text: str, model, multipliers=()) -> sp.Expr:
    """Parse an expression lagcli printed (JSON/text) back into sympy, with lagcli's own parser."""
    from lagcli.errors import Loc
    from lagcli.model.expr import OUTPUT_LIMITS, Scope, parse

    return parse(text, Scope(output_names(model, multipliers), model.t), Loc("<output>"), limits=OUTPUT_LIMITS)
