"""The numeric value of a constant sympy expression, computed with bounded work.

sympy keeps `exp(exp(exp(100)))` or `acos(2)` as exact symbolic objects, and
asking for their value (`float()`, `evalf`, a comparison inside `Min`, the
argument reduction of `tan` of a number with a million digits) can overflow,
come out complex, or grind for minutes. Here every node is evaluated bottom-up
in IEEE double precision (Python floats and `math`), so the cost is one float
operation per node, whatever the numbers, and every intermediate value must be
a finite real double of magnitude at most `LARGEST` and, unless zero, at least
`SMALLEST` (the C and NumPy code lagcli generates computes in doubles too: a
constant outside that range would be inf or 0 there).

`constant_value(expr)` returns the float or raises `ConstantError` saying what
went wrong in words a spec author understands. `value_at(expr, point)` evaluates
an expression at numeric values of its symbols the same way (for the numeric
identity tests of `lagcli.model.calculus`: sympy's `evalf` at a random point can grind
on `sin(exp(exp(exp(exp(x)))))` or run out of memory on a taller exp tower).
"""
from __future__ import annotations

import math
from collections.abc import Callable

import sympy as sp

LARGEST = 1e300
SMALLEST = 1e-300


class ConstantError(ValueError):
    """A constant is not a finite real number within the double range (message says why)."""


def _sign(x: float) -> float:
    return float((x > 0) - (x < 0))


_FUNCTIONS: dict[type, Callable[..., float]] = {
    sp.sin: math.sin, sp.cos: math.cos, sp.tan: math.tan,
    sp.asin: math.asin, sp.acos: math.acos, sp.atan: math.atan, sp.atan2: math.atan2,
    sp.sinh: math.sinh, sp.cosh: math.cosh, sp.tanh: math.tanh,
    sp.exp: math.exp, sp.log: math.log, sp.Abs: abs, sp.sign: _sign,
    sp.Min: min, sp.Max: max,
    # in derivatives: of real values (all values here are real), and almost everywhere
    sp.re: lambda x: x, sp.im: lambda x: 0.0,
    sp.Heaviside: lambda x, *half: 0.5 + _sign(x) / 2, sp.DiracDelta: lambda x, *order: _not_at_zero(x),
}


def _not_at_zero(x: float) -> float:
    if x == 0:
        raise ZeroDivisionError
    return 0.0


def constant_value(expr: sp.Expr, memo: dict | None = None) -> float:
    """The value of the constant `expr` as a float (see the module docstring).

    `memo` (expression -> value) lets a caller that evaluates growing expressions
    reuse the values of their parts."""
    return _value(expr, {} if memo is None else memo, None)


def value_at(expr: sp.Expr, point: dict, memo: dict | None = None) -> float:
    """The value of `expr` with each symbol replaced by its float in `point`: a finite
    real, without the range limits of constants (an underflow to 0 is fine here)."""
    return _value(expr, {} if memo is None else memo, point)


def _value(expr: sp.Expr, memo: dict, point: dict | None) -> float:
    found = memo.get(expr)
    if found is None:
        found = _checked(_node_value(expr, memo, point), strict=point is None)
        memo[expr] = found
    return found


def _node_value(expr: sp.Expr, memo: dict, point: dict | None) -> float:
    args = expr.args
    if args:        # an operation (every number, symbol and special value below is a leaf)
        return _operation(expr, [_value(arg, memo, point) for arg in args])
    if expr is sp.nan:
        raise ConstantError("is undefined (NaN)")
    if expr is sp.zoo or expr is sp.oo or expr is sp.S.NegativeInfinity:    # singletons (`in` called __eq__)
        raise ConstantError("is infinite")
    if expr is sp.I:
        raise ConstantError("is complex")
    if expr.is_Rational:
        return _rational(expr)
    if expr.is_Float or expr.is_NumberSymbol:
        return float(expr)
    if expr.is_Symbol:
        if point is not None and expr in point:
            return float(point[expr])
        raise ConstantError(f"is not a constant (uses {expr})")
    return _operation(expr, [])


def value_from_arguments(expr: sp.Expr, args: list[float]) -> float:
    """The value of the node `expr` (not a leaf) whose arguments have the values `args`, as
    `value_at` finds it (raises ConstantError): for a caller that knows the arguments'
    values (`calculus.DependenceProbe`, after one argument changed)."""
    return _checked(_operation(expr, args), strict=False)


def _operation(expr: sp.Expr, args: list[float]) -> float:
    try:
        if expr.is_Add:
            return math.fsum(args)
        if expr.is_Mul:
            return math.prod(args)
        if expr.is_Pow:
            return _power(*args)
        function = _FUNCTIONS.get(type(expr))
        if function is None:
            raise ConstantError(f"cannot be evaluated ({type(expr).__name__} is not supported)")
        return function(*args)
    except ZeroDivisionError:
        raise ConstantError("divides by zero") from None
    except OverflowError:
        raise ConstantError(f"is too large (beyond {LARGEST:g})") from None
    except ValueError:
        raise ConstantError("is not a real number (a function is used outside its domain)") from None


def _rational(number: sp.Rational) -> float:
    try:
        value = int(number.p) / int(number.q)
    except OverflowError:
        raise ConstantError(f"is too large (beyond {LARGEST:g})") from None
    if value == 0 and number != 0:
        raise ConstantError(f"is too small (below {SMALLEST:g}; it would be 0 in double precision)")
    return value


def _power(base: float, exponent: float) -> float:
    if base == 0 and exponent < 0:
        raise ZeroDivisionError
    value = base ** exponent
    if isinstance(value, complex):
        raise ValueError
    return value


def _checked(value: float, strict: bool) -> float:
    if isinstance(value, complex) or math.isnan(value):
        raise ConstantError("is not a real number")
    if not math.isfinite(value) or (strict and abs(value) > LARGEST):
        raise ConstantError(f"is too large (beyond {LARGEST:g})")
    if strict and value != 0 and abs(value) < SMALLEST:
        raise ConstantError(f"is too small (below {SMALLEST:g}; it would be 0 in double precision)")
    return value
