"""The report's derivatives of its tidied parts: d M_ij / d q_k for the velocity terms,
dV/dq_i for the forces, da_i/dq_j for the gyroscopic matrix (`Display.differentiate`
takes each once).

They are the derivation's derivatives (`lagcli.model.calculus.derivative`, taken almost
everywhere as the derivation takes them), with shortcuts that give the same
expressions: a product in which one factor varies is the other factors times that
factor's derivative, formed as one product (`one_factor_derivative`: a chain's M_ij), that
product shared by the variables whose derivatives differ only in sign (d/dq_i and d/dq_j
of cos(q_i - q_j)), as is f'(u) of sin(u) and cos(u) (`_outer_rate`); and the derivative of
every sum and product met is remembered for the report (`rate`): a chain's potential
holds g m_k (-l_1 cos(q_1) - ... - l_k cos(q_k)) for every k, all sharing the terms
-l_i cos(q_i), whose derivative for q_i was formed again for each k.
tests/test_report_shared_terms.py compares them with `calculus.derivative`.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model import calculus
from lagcli.model.angle_calls import TRIG, plain_sign, trig_call
from lagcli.model.calculus import almost_everywhere
from lagcli.model.products import product
from lagcli.model.sums import total


def derivative(expr: sp.Expr, var, memo: dict, rates: dict | None = None) -> sp.Expr:
    """d expr/d var, taken almost everywhere as the derivation does (no Heaviside, DiracDelta);
    `memo`: free symbols of the subexpressions seen (`lagcli.model.calculus.free_symbols`);
    `rates`: the derivatives of the sums and products seen (`rate`)."""
    return almost_everywhere(rate(expr, var, memo, {} if rates is None else rates))


def rate(expr, var, memo: dict, rates: dict) -> sp.Expr:
    """`calculus.derivative(expr, var, memo)`, the same expression, each sum's and product's
    remembered in `rates` under (expr, var): a sum is the total of its terms' derivatives
    (the terms that mention var, in order, as calculus.derivative takes them), a product
    with one varying factor `one_factor_derivative`'s; anything else is calculus.derivative's."""
    if not isinstance(expr, sp.Basic) or var not in calculus.free_symbols(expr, memo):
        return sp.S.Zero
    if isinstance(expr, TRIG):       # calculus.derivative's rule, f'(u) formed once for every variable
        return _times_rate(_outer_rate(expr, rates), rate(expr.args[0], var, memo, rates))
    if not (expr.is_Add or expr.is_Mul):
        return calculus.derivative(expr, var, memo)
    key = (expr, var)
    found = rates.get(key)
    if found is None:
        if expr.is_Add:
            found = total([rate(a, var, memo, rates) for a in calculus._terms_mentioning(expr, var, memo)])
        else:
            found = one_factor_derivative(expr, var, memo, rates)
            if found is None:
                found = calculus.derivative(expr, var, memo)
        rates[key] = found
    return found


def _outer_rate(call, rates: dict) -> sp.Expr:
    """cos(u) for sin(u), -sin(u) for cos(u), as calculus.derivative forms them (`trig_call`),
    remembered in `rates` under (call,): d/dq_i and d/dq_j of cos(q_i - q_j) share it."""
    key = (call,)
    found = rates.get(key)
    if found is None:
        arg = call.args[0]
        found = rates[key] = trig_call(sp.cos, arg) if isinstance(call, sp.sin) else -trig_call(sp.sin, arg)
    return found


def _times_rate(outer, inner) -> sp.Expr:
    """product(outer, inner) for f'(u) (`_outer_rate`), at once for the inner rates 1 and -1
    of an angle q_i - q_j: outer itself (sympy's, so already in its canonical form), or a
    call c or -c negated as sympy negates it (-(-sin(u)) is sin(u), -cos(u) is -1 times
    cos(u), as product builds them)."""
    if inner is sp.S.One:
        return outer
    if inner is sp.S.NegativeOne and (isinstance(outer, TRIG) or _negated_call(outer)):
        return -outer
    return product(outer, inner)


def _negated_call(expr) -> bool:
    """expr is -1 times a sin or cos call."""
    return expr.is_Mul and len(expr.args) == 2 and expr.args[0] is sp.S.NegativeOne and isinstance(expr.args[1], TRIG)


def one_factor_derivative(expr, var, memo: dict, rates: dict | None = None) -> sp.Expr | None:
    """`calculus.derivative` of a product in which one factor f varies (l3 l6 (m6 + ... + m40)
    cos(q3 - q6), an entry of a chain's M): the other factors times f' (by `rate`), one
    product of them all, where calculus.derivative forms it factor by factor (each product
    sorting the sum of masses again). The same expression when f' is not a rational number
    and no factor but a leading one is, unless the first two factors are a rational number
    and a sum (distributed in the factor-by-factor product); None otherwise. When f' is s * r
    with s = 1 or -1 and an earlier variable's f' was -s * r, the result is that variable's
    derivative negated (remembered in `rates`): d/dq_i and d/dq_j of a chain's
    M_ij = l_i l_j (m_j + ... + m_n) cos(q_i - q_j) are -P and P, P = l_i l_j (...) sin(q_i - q_j)."""
    if not expr.is_Mul or any(a.is_Rational for a in expr.args[1:]):
        return None
    moving = [k for k, a in enumerate(expr.args) if var in calculus.free_symbols(a, memo)]
    if len(moving) != 1:
        return None
    k = moving[0]
    rates = {} if rates is None else rates
    factor_rate = rate(expr.args[k], var, memo, rates)
    if factor_rate.is_Rational or (expr.args[0].is_Rational and _distributed(factor_rate if k == 1 else expr.args[1])):
        return None
    sign, rest = factor_rate.as_coeff_Mul()
    key = (expr, k, rest)      # a triple: the rates' own keys are pairs (expr, var)
    earlier = rates.get(key)   # (sign, derivative) for an earlier variable whose f' is +-rest too
    if earlier is not None and (sign is sp.S.One or sign is sp.S.NegativeOne):
        earlier_sign, found = earlier
        if earlier_sign is sign:
            return found
        if found.is_Mul and (found.args[0].is_Rational or not found.args[0].is_Number):
            return -found      # Mul.__neg__: the coefficient negated, as the product with -f' has it
    found = product(*expr.args[:k], factor_rate, *expr.args[k + 1:])
    if sign is sp.S.One or sign is sp.S.NegativeOne:
        rates[key] = (sign, found)
    return found


def _distributed(second) -> bool:
    """A rational number times `second` is a sum distributed (sympy's Mul of two factors): the
    first step of calculus.derivative's factor-by-factor product of c * second * ..."""
    return second.as_coeff_Mul()[1].is_Add


def angle_entry_rates(expr, memo: dict, rates: dict) -> dict:
    """{q: d expr/dq} for each symbol q of the angle u of a product r * F_1 ... F_m * f(u)
    (a chain's M_ij = l_i l_j (m_j + ... + m_n) cos(q_i - q_j)), built at once; {} for any
    other expr. r is an optional rational number, f is sin or cos, u is a plain angle
    (`angle_calls`: integer multiples of real symbols) from which sympy pulls no sign, and
    the F_k are commutative symbols, sums and integer powers of symbols, none mentioning
    a symbol of u. Then `rate`'s product of the F_k with f'(u) du/dq = s c g(u) (s c the
    number: s = -1 for d cos = -sin, c the integer coefficient of q in u) is a product of
    plain factors, sorted with g(u) last as f(u) was (a sin or cos sorts after symbols,
    sums and powers): the number r s c, then the F_k in their order, then g(u).
    tests/test_report_angle_rates.py compares it with `calculus.derivative`."""
    call = expr.args[-1] if type(expr) is sp.Mul else None
    if type(call) not in TRIG or plain_sign(call.args[0]) != 1:
        return {}
    number, others = expr.args[0], expr.args[:-1]
    if number.is_Rational:
        others = others[1:]
        if others and others[0].is_Add:      # rate distributes r over that sum (`_distributed`)
            return {}
    else:
        number = sp.S.One
    coefficients = _angle_coefficients(call.args[0])
    if not all(_plain_constant(f) for f in others) \
            or any(not calculus.free_symbols(f, memo).isdisjoint(coefficients) for f in others):
        return {}
    outer = _outer_rate(call, rates)          # cos(u), or -sin(u): the Mul (-1, sin(u))
    sign, rated = outer.as_coeff_Mul()
    out = {}
    for symbol, c in coefficients.items():
        factor = number * sign * c
        args = others + (rated,) if factor is sp.S.One else (factor, *others, rated)
        out[symbol] = args[0] if len(args) == 1 else sp.Mul._from_args(args, True)
    return out


def _angle_coefficients(angle) -> dict:
    """{symbol: its integer coefficient} of a plain angle (`plain_sign` accepted it)."""
    if type(angle) is sp.Symbol:
        return {angle: sp.S.One}
    out = {}
    for term in angle.args:
        if type(term) is sp.Symbol:
            out[term] = sp.S.One
        else:
            out[term.args[1]] = term.args[0]
    return out


def _plain_constant(factor) -> bool:
    """A factor `products.product` keeps as it is and sorts before a sin or cos: a commutative
    symbol or sum, or a nonzero integer power of a commutative symbol."""
    if factor.is_Pow:
        base, exponent = factor.args
        return type(base) is sp.Symbol and base.is_commutative is True and exponent.is_Integer \
            and exponent is not sp.S.Zero
    return (type(factor) is sp.Symbol or type(factor) is sp.Add) and factor.is_commutative is True
