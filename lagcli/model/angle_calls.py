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
The call is built as `trig_node` builds it, not by sympy's unevaluated constructor (its
cache lookup and a new FiniteSet for `nargs`: a 40-link chain's report builds 780 cosines
and 780 sines of angle differences), and remembered: a call asked for again is the same
object, as sympy's cache gives it. Any other argument goes to sympy.
"""
from __future__ import annotations

import sympy as sp
from sympy.core.basic import Basic

TRIG = (sp.sin, sp.cos)
_NARGS = {f: f(sp.Symbol("x"), evaluate=False).nargs for f in TRIG}     # FiniteSet(1), immutable
_CALLS: dict = {}        # (function, plain angle) -> its call (`trig_call`), bounded
_CALLS_KEPT = 1 << 16


def trig_call(function, arg) -> sp.Expr:
    """`function(arg)` for function sin or cos, the same expression as sympy's."""
    sign = plain_sign(arg)
    if sign is None:
        return function(arg)
    if sign > 0:
        return _remembered_node(function, arg)
    positive = _remembered_node(function, -arg)
    return positive if function is sp.cos else -positive


def trig_node(function, arg) -> sp.Expr:
    """`function(arg, evaluate=False)` for sin or cos: the node sympy's `Application.__new__`
    builds (its arguments, its `nargs`), without that constructor's cache lookup and its
    new FiniteSet for `nargs`."""
    node = Basic.__new__(function, arg)
    node.nargs = _NARGS[function]
    return node


def _remembered_node(function, arg) -> sp.Expr:
    """`trig_node(function, arg)`, one object for each call."""
    key = (function, arg)
    found = _CALLS.get(key)
    if found is None:
        if len(_CALLS) >= _CALLS_KEPT:
            _CALLS.clear()
        found = _CALLS[key] = trig_node(function, arg)
    return found


def plain_sign(arg) -> int | None:
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
