"""sin and cos of a plain angle (q1 - q2), built without sympy's evaluation.

`sympy.cos(q1 - q2)` runs `cos.eval`: a minus-sign test whose tie-break compares the sort
keys of the sum and of its negative, a search for the imaginary unit and for a multiple of
pi, assumption queries: about 1.5 ms for a new angle difference, and a 40-link chain has
780 of them, met as a cosine in its mass matrix and as a sine in its derivatives. For a
*plain angle* (a real symbol, or a sum of integer multiples of distinct real symbols with
no number term) every one of eval's rules but the minus sign finds nothing, and the minus
sign is decided as sympy decides it: more negative terms than positive ones, or as many
and the leading term negative, the leading term being the one with the first symbol in
sympy's order (its name; `lagcli.targets.minus_sign` makes the same argument for any sum).
So `trig_call(sp.cos, q2 - q1)` is `cos(q1 - q2)` and `trig_call(sp.sin, q2 - q1)` is
`-sin(q1 - q2)`, the very objects sympy returns (tests/test_angle_calls.py compares them).
Any other argument goes to sympy.
"""
from __future__ import annotations

import sympy as sp

TRIG = (sp.sin, sp.cos)


def trig_call(function, arg) -> sp.Expr:
    """`function(arg)` for function sin or cos, the same expression as sympy's."""
    sign = _plain_sign(arg)
    if sign is None:
        return function(arg)
    if sign > 0:
        return function(arg, evaluate=False)
    positive = function(-arg, evaluate=False)
    return positive if function is sp.cos else -positive


def _plain_sign(arg) -> int | None:
    """1 when arg is a plain angle from which sympy pulls no minus sign, -1 when it pulls
    one, None when arg is not a plain angle."""
    if type(arg) is sp.Symbol:
        return 1 if _plain_symbol(arg) else None
    if not arg.is_Add:
        return None
    negative, leading = 0, None
    for term in arg.args:
        if type(term) is sp.Symbol:
            number, symbol = 1, term
        elif term.is_Mul and len(term.args) == 2 and term.args[0].is_Integer and type(term.args[1]) is sp.Symbol:
            number, symbol = int(term.args[0]), term.args[1]
        else:
            return None
        if not _plain_symbol(symbol):
            return None
        negative += number < 0
        if leading is None or symbol.name < leading[1].name:
            leading = (number, symbol)
    positive = len(arg.args) - negative
    if negative != positive:
        return -1 if negative > positive else 1
    return -1 if leading[0] < 0 else 1


def _plain_symbol(symbol) -> bool:
    """A real, finite symbol that may be nonzero: none of eval's rules applies to it."""
    return symbol.is_extended_real is True and symbol.is_finite is True and symbol.is_zero is not True
