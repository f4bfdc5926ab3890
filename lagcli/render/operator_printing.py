"""sympy's printing of sums and products, each expression's precedence found once.

sympy's printers ask `precedence(x)` of a product up to three times (its own
`_print_Mul`, the parent's `parenthesize`, the parent sum's `_print_Add`), and each
answer builds `-x` (`Mul.could_extract_minus_sign`): half of the printing of the 40-link
chain's code (bench/README.md, issue 24). `RememberedPrecedence` is a mixin placed before
sympy's printer class (the code targets' `slots.SlotPrinter` and the reports' spec-language
`spec_printer.SpecPrinter` start from it): its `parenthesize`, `_print_Add` and
`_print_Mul` are sympy's (`StrPrinter.parenthesize`, `StrPrinter._print_Add`,
`CodePrinter._print_Mul`, sympy 1.14) with `precedence` replaced by `precedence_of`, which
remembers the answer per expression (unless the printer sets `_precedences` to None: a
printer kept for the whole process) and gives the answer of a product without a leading
number directly (it cannot be negative). A printer whose sympy class prints sums or
products its own way (Octave's `_print_Mul`, Rust's both, StrPrinter's `_print_Mul`) keeps
that: the mixin defers to it (`_generic`). The spec language's product of factors that
are neither numbers nor powers with a negative exponent or an integer base (a report's
term) is its factors' texts joined by '*' at once: StrPrinter's sign, number and
denominator walk does nothing else with them. tests/test_operator_printing.py compares the
text with sympy's printers on random expressions.
"""
from __future__ import annotations

from functools import cache

from sympy import Mul, Number, Pow, Rational, S
from sympy.core.mul import _keep_coeff
from sympy.printing.precedence import PRECEDENCE, precedence
from sympy.printing.str import StrPrinter

# sympy's generic methods, by name (module.qualname) rather than imported: the C printers'
# module (sympy.printing.c, and sympy.codegen.ast with it: ~30 ms of import) is loaded by
# the code targets that print C, never by a report.
GENERIC = {
    "parenthesize": ("sympy.printing.str.StrPrinter.parenthesize",),
    "_print_Add": ("sympy.printing.str.StrPrinter._print_Add",),
    "_print_Mul": ("sympy.printing.codeprinter.CodePrinter._print_Mul",
                   "sympy.printing.c.C89CodePrinter._print_Mul",        # C89's: math macros first
                   "sympy.printing.str.StrPrinter._print_Mul"),         # the reports' (`_print_str_Mul`)
}
MUL = PRECEDENCE["Mul"]


class RememberedPrecedence:
    """Mixin for a sympy code printer: sympy's sum and product printing, each precedence once."""

    def __init__(self, settings=None):
        super().__init__(settings)
        self._precedences: dict = {}

    def precedence_of(self, item) -> int:
        """`sympy.printing.precedence.precedence(item)`, remembered (with a memo)."""
        memo = self._precedences
        if memo is None:
            return _precedence(item)
        found = memo.get(item)
        if found is None:
            found = memo[item] = _precedence(item)
        return found

    def parenthesize(self, item, level, strict=False):
        if not _generic(type(self), "parenthesize"):
            return super().parenthesize(item, level, strict)
        known = self.precedence_of(item)
        if known < level or (not strict and known <= level):
            return "(%s)" % self._print(item)
        return self._print(item)

    def _print_Add(self, expr, order=None):
        if not _generic(type(self), "_print_Add"):
            return super()._print_Add(expr, order=order)
        terms = self._as_ordered_terms(expr, order=order)
        prec = self.precedence_of(expr)
        words = []
        for term in terms:
            text = self._print(term)
            if text.startswith('-') and not term.is_Add:
                sign, text = "-", text[1:]
            else:
                sign = "+"
            if self.precedence_of(term) < prec or term.is_Add:
                words.extend([sign, "(%s)" % text])
            else:
                words.extend([sign, text])
        sign = words.pop(0)
        return ("" if sign == "+" else sign) + ' '.join(words)

    def _print_Mul(self, expr, **kwargs):
        if _sympys(type(self), "_print_Mul") is StrPrinter._print_Mul:
            return self._print_str_Mul(expr)
        if not _generic(type(self), "_print_Mul") or getattr(self, "math_macros", None):
            return super()._print_Mul(expr, **kwargs)
        prec = self.precedence_of(expr)
        c, e = expr.as_coeff_Mul()
        if c < 0:
            expr, sign = _keep_coeff(-c, e), "-"
        else:
            sign = ""
        a, b, pow_paren = [], [], []      # numerator, denominator, 1/(x*y) kept in parentheses
        args = expr.as_ordered_factors() if self.order not in ('old', 'none') else Mul.make_args(expr)
        for item in args:
            if item.is_commutative and item.is_Pow and item.exp.is_Rational and item.exp.is_negative:
                if item.exp != -1:
                    b.append(Pow(item.base, -item.exp, evaluate=False))
                else:
                    if len(item.args[0].args) != 1 and isinstance(item.base, Mul):
                        pow_paren.append(item)
                    b.append(Pow(item.base, -item.exp))
            else:
                a.append(item)
        a = a or [S.One]
        if len(a) == 1 and sign == "-":
            a_str = [self.parenthesize(a[0], 0.5 * (PRECEDENCE["Pow"] + PRECEDENCE["Mul"]))]
        else:
            a_str = [self.parenthesize(x, prec) for x in a]
        b_str = [self.parenthesize(x, prec) for x in b]
        return _quotient(sign, a_str, b, b_str, pow_paren)

    def _print_str_Mul(self, expr) -> str:
        """`StrPrinter._print_Mul` (the reports' spec language), with `precedence_of` and the
        sign of the common coefficients 1 and -1 known without comparing numbers."""
        prec = self.precedence_of(expr)
        args = expr.args
        if self.order in ('old', 'none') and all(numerator_factor(a) for a in args):
            return '*'.join([self.parenthesize(x, prec, strict=False) for x in args])   # a report's term
        if args[0] is S.One or any(isinstance(a, Number) or a.is_Pow and all(ai.is_Integer for ai in a.args)
                                   for a in args[1:]):
            return StrPrinter._print_Mul(self, expr)     # unevaluated: every factor shown as it is
        c, e = expr.as_coeff_Mul()
        if c is S.NegativeOne or (c is not S.One and c < 0):
            expr, sign = _keep_coeff(-c, e), "-"
        else:
            sign = ""
        a, b, pow_paren = [], [], []      # numerator, denominator, 1/(x*y) kept in parentheses
        for item in (expr.as_ordered_factors() if self.order not in ('old', 'none') else Mul.make_args(expr)):
            if item.is_commutative and isinstance(item, Pow) and _negative_exponent(item.exp):
                if item.exp is not S.NegativeOne:
                    b.append(_inverted(item))
                else:
                    if len(item.args[0].args) != 1 and isinstance(item.base, (Mul, Pow)):
                        pow_paren.append(item)
                    b.append(item.base)
            elif item.is_Rational and item is not S.Infinity:
                if item.p != 1:
                    a.append(Rational(item.p))
                if item.q != 1:
                    b.append(Rational(item.q))
            else:
                a.append(item)
        a = a or [S.One]
        a_str = [self.parenthesize(x, prec, strict=False) for x in a]
        b_str = [self.parenthesize(x, prec, strict=False) for x in b]
        return _quotient(sign, a_str, b, b_str, pow_paren)


def _quotient(sign: str, a_str: list, b: list, b_str: list, pow_paren: list) -> str:
    """The printers' common end of a product: sign, numerator and denominator joined, a base
    of 1/(x*y) kept in parentheses (as sympy's C and str printers write it)."""
    for item in pow_paren:
        if item.base in b:
            b_str[b.index(item.base)] = "(%s)" % b_str[b.index(item.base)]
    if not b:
        return sign + '*'.join(a_str)
    if len(b) == 1:
        return sign + '*'.join(a_str) + "/" + b_str[0]
    return sign + '*'.join(a_str) + "/(%s)" % '*'.join(b_str)


def numerator_factor(factor) -> bool:
    """A factor `_print_str_Mul` prints as it is in the numerator: no number (no sign or
    denominator to pull out), no power with an integer base or a negative exponent; a
    product of such factors prints as its factors, in order, joined by '*'."""
    if isinstance(factor, Number):
        return False
    if isinstance(factor, Pow) or factor.is_Pow:
        exponent = factor.exp
        return exponent.is_Rational and exponent.p > 0 and not factor.base.is_Integer
    return True


def _negative_exponent(exponent) -> bool:
    """StrPrinter's test `exponent.as_coeff_Mul()[0] < 0`, a rational exponent's sign read directly."""
    if exponent.is_Rational:
        return exponent.p < 0
    return bool(exponent.as_coeff_Mul()[0] < 0)


def _inverted(power):
    """StrPrinter's `apow`: base**(-exponent), the exponent's leading number negated."""
    base, exponent = power.as_base_exp()
    factors = list(Mul.make_args(exponent))
    if factors[0] is S.NegativeOne:
        factors = factors[1:]
    else:
        factors[0] = -factors[0]
    exponent = Mul._from_args(factors)
    if isinstance(power, Pow):
        return power.func(base, exponent, evaluate=False)
    return power.func(exponent, evaluate=False)


def _precedence(item) -> int:
    """`precedence(item)`; a product without a leading number is MUL at once (precedence_Mul:
    no function of low precedence, no minus sign to find)."""
    if type(item) is Mul and not item.args[0].is_Number and not any(hasattr(arg, "precedence") for arg in item.args):
        return MUL
    return precedence(item)


@cache
def _sympys(cls, name: str):
    """The sympy method `name` of the printer under the mixin in `cls` (None: none)."""
    after = cls.__mro__[cls.__mro__.index(RememberedPrecedence) + 1:]
    for klass in after:
        if name in vars(klass):
            return vars(klass)[name]
    return None


@cache
def _generic(cls, name: str) -> bool:
    """True when the sympy printer under the mixin in `cls` prints `name` the generic way."""
    method = _sympys(cls, name)
    return method is not None and f"{method.__module__}.{method.__qualname__}" in GENERIC[name]
