"""Symbols print as array slots, never as their spec names (so a parameter called
`register` or `y0` cannot break the output):

    t                      time
    y[i]                   q_i for i < n, q'_(i-n) for n <= i < 2n
    p[j]                   parameter j in spec order
    u[k]                   input k in spec order (spec `inputs:`)
    x0, x1, ...            CSE temporaries (sympy Dummies, named by position)

`SlotPrinter` is the mixin each language's printer subclass starts from: it prints
a symbol through its slot and raises `EmitError` for a symbol without one;
`check_slots` runs on every expression before anything is printed. Numbers print
as exact decimal literals (17 significant digits for floats, 21 for constants like
pi), small integer powers as products. What differs between languages is a class
attribute of the subclass (`power_format`, `sqrt_function`, `literal`).
"""
from __future__ import annotations

import sympy as sp
from sympy.printing.codeprinter import PrintMethodNotImplementedError

from lagcli.derive.result import Derivation
from lagcli.targets.cse import Reduced
from lagcli.errors import EmitError
from lagcli.render.operator_printing import RememberedPrecedence

CONSTANT_DIGITS = 21          # pi, E, ... as literals: 3.14159265358979323846
MAX_PRODUCT_POWER = 4         # x**k, 2 <= |k| <= 4, prints as x*x*...; larger via pow


def slots(d: Derivation, reduced: Reduced, printer_class=None) -> dict:
    """symbol -> code: t, y[i] for q and q', p[j] for parameters, u[k] for inputs,
    x<k> for temporaries;
    the subscripts as `printer_class` writes them (`index_base`, `subscript`)."""
    printer_class = printer_class or SlotPrinter
    base, subscript = printer_class.index_base, printer_class.subscript
    model = d.model
    table = {model.t: "t"}
    for i, symbol in enumerate(model.q + model.qd):
        table[symbol] = subscript.format(array="y", index=i + base)
    for j, symbol in enumerate(model.parameter_symbols):
        table[symbol] = subscript.format(array="p", index=j + base)
    for k, symbol in enumerate(model.input_symbols):
        table[symbol] = subscript.format(array="u", index=k + base)
    for k, (symbol, _) in enumerate(reduced.temporaries):
        table[symbol] = f"x{k}"
    return table


def check_slots(exprs, table: dict, free_symbols=lambda expr: sp.sympify(expr).free_symbols) -> None:
    """Raise EmitError when an expression has a symbol that has no slot (`free_symbols`:
    how to find an expression's symbols; `Reduced.free_symbols` remembers them)."""
    missing = set()
    for expr in exprs:
        missing |= {s for s in free_symbols(expr) if s not in table}
    if missing:
        names = ", ".join(sorted(str(s) for s in missing))
        raise EmitError(f"cannot generate code: no array slot for symbol(s) {names} "
                        "(only t, coordinates, velocities, parameters and inputs may appear)")


class SlotPrinter(RememberedPrecedence):
    """Mixin for a sympy code printer: symbols print as their slot, strictly.

    Sums and products print as sympy prints them, each precedence found once
    (`operator_printing.RememberedPrecedence`).
    A subclass sets `sqrt_function`, `power_format` and `literal`, overrides `imports`
    when the language imports functions by name, and lists this mixin first; a language
    whose arrays start at 1 or are subscripted otherwise sets `index_base` and
    `subscript` (`slots` reads them).
    """

    index_base = 0
    subscript = "{array}[{index}]"
    sqrt_function = "sqrt"
    power_format = "{base}**{exp}"

    @staticmethod
    def literal(value) -> str:
        """A literal of the language for a number of the interface."""
        raise NotImplementedError

    def imports(self) -> tuple:
        """(module, names) pairs the printed code needs, after printing; none by default."""
        return ()

    def __init__(self, table: dict, settings: dict | None = None):
        super().__init__({"strict": True, **(settings or {})})
        self.slots = table
        self._printed: dict = {}       # expression -> code: the blocks share temporaries

    def in_given_order(self) -> "SlotPrinter":
        """Print sums and products in the order of their arguments, unsorted: the code of
        `cse.linear_cse`, whose order is deterministic already (sorting the terms of its
        megabyte of code by sympy's sort keys took a fifth of `generate`)."""
        self._settings["order"] = "none"
        return self

    def code(self, expr) -> str:
        """`expr` as code; each distinct expression printed once (a temporary is in the
        mass matrix's, the system's and the invariants' bodies: printing was a sixth of
        `generate` of the 40-link chain)."""
        expr = sp.sympify(expr)
        text = self._printed.get(expr)
        if text is None:
            try:
                text = self._printed[expr] = self._print(expr)
            except PrintMethodNotImplementedError as exc:
                raise EmitError(f"cannot generate code for {expr}: {exc}") from exc
        return text

    def _print_Symbol(self, expr):
        try:
            return self.slots[expr]
        except KeyError:
            raise EmitError(f"cannot generate code: no array slot for symbol {expr}") from None

    _print_Dummy = _print_Symbol

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_NumberSymbol(self, expr):
        return str(sp.Float(expr.evalf(CONSTANT_DIGITS), CONSTANT_DIGITS))

    _print_Pi = _print_Exp1 = _print_EulerGamma = _print_GoldenRatio = _print_NumberSymbol
    _print_Catalan = _print_TribonacciConstant = _print_NumberSymbol

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.base, expr.exp
        if exp.is_Integer and 2 <= abs(int(exp)) <= MAX_PRODUCT_POWER:
            factor = self._power_operand(base)
            product = "*".join([factor] * abs(int(exp)))
            return f"({product})" if exp > 0 else f"(1.0/({product}))"
        if exp == -1:
            return f"(1.0/{self._power_operand(base)})"
        if exp == sp.S.Half:
            return self._print_sqrt(base)
        if exp == -sp.S.Half:
            return f"(1.0/{self._print_sqrt(base)})"
        return self.power_format.format(
            base=self._power_operand(base), exp=self._power_operand(exp))

    def sqrt_name(self) -> str:
        return self.sqrt_function

    def nested_call(self, function: str, args) -> str:
        """`function(a, function(b, c))` for args (a, b, c): min/max of several arguments
        in a language whose function takes two (`function` a module path: `casadi.fmin`)."""
        first, *rest = args
        if not rest:
            return self._print(first)
        return f"{self._module_format(function)}({self._print(first)}, {self.nested_call(function, rest)})"

    def _print_sqrt(self, base) -> str:
        """sqrt(base) as a call of `sqrt_name()`; a language with methods overrides it."""
        return f"{self.sqrt_name()}({self._print(base)})"

    def _power_operand(self, expr) -> str:
        """`expr` printed as an operand of * or pow: bare when it is a symbol, a
        non-negative number or a function call; parenthesised otherwise."""
        text = self._print(expr)
        bare = (expr.is_Symbol or isinstance(expr, sp.Function) or isinstance(expr, sp.NumberSymbol)
                or ((expr.is_Integer or expr.is_Float) and expr.is_nonnegative))
        return text if bare else f"({text})"
