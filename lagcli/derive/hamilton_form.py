"""Hamilton's form of the equations (unconstrained systems).

With T = 1/2 q'^T M q' + a^T q' + T0 the momenta are p = dL/dq' = M q' + a, and

    H(q, p, t) = 1/2 (p - a)^T M^-1 (p - a) - T0 + V       (printed in this split)
    q' =  dH/dp = M^-1 (p - a)
    p' = -dH/dq + Q'  =  dL/dq (q, q', t) + Q'        (q' = M^-1 (p - a))

H is written out symbolically when M is diagonal or at most 2 x 2 (`SYMBOLIC_SIZE`);
otherwise H and q'(p) stay in the solved form above, and the numeric right-hand
side (`HamiltonRhs`) solves M q' = p - a at each call — never a symbolic inverse
of a large matrix (lagcli/analysis/hamiltonian.py).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagcli.errors import UsageError
from lagcli.render.tidy import display_form, fewest_squares

SYMBOLIC_SIZE = 2


@dataclass(frozen=True)
class HamiltonForm:
    momenta: tuple[sp.Symbol, ...]           # p_<q>
    momentum_exprs: tuple[sp.Expr, ...]      # p = M q' + a
    H: sp.Expr | None                        # H(q, p, t), None when M is large and full
    qdot: tuple[sp.Expr, ...] | None         # dH/dp
    pdot: tuple[sp.Expr, ...] | None         # -dH/dq + Q'


def hamilton_form(d) -> HamiltonForm:
    model = d.model
    if d.constraints:
        raise UsageError(f"{model.source}: Hamilton's form here is for unconstrained systems "
                         "(use independent coordinates)")
    # M, a, V - T0 as the reports print them (sin^2 + cos^2 = 1, angle sums folded), so the
    # solved forms below start from the tidy entries
    M, a = sp.Matrix(d.mass_matrix).applyfunc(display_form), sp.Matrix(d.t1_coefficients).applyfunc(display_form)
    qd = sp.Matrix(model.qd)
    p = sp.Matrix([sp.Symbol(f"p_{q.name}", real=True) for q in model.q])
    momentum = (M * qd + a).applyfunc(display_form)        # p = M q' + a, tidied as the reports do
    if not (M.is_diagonal() or M.rows <= SYMBOLIC_SIZE):
        return HamiltonForm(tuple(p), tuple(momentum), None, None, None)
    velocity = M.LUsolve(p - a).applyfunc(tidy_fraction)               # q' = dH/dp = M^-1 (p - a)
    # written as a textbook does: the kinetic part over its one denominator, then - T0 + V
    # (one fraction of both would hide V inside the kinetic part's denominator)
    H = tidy_fraction(((p - a).T * velocity)[0] / 2) + tidy_fraction(display_form(d.V - d.T0))
    Q = sp.Matrix(d.nonconservative_forces).xreplace(dict(zip(model.qd, velocity)))
    moving = {model.t, *model.q, *p}
    pdot = tuple(tidy_split(-H.diff(q) + Q[k], moving) for k, q in enumerate(model.q))
    return HamiltonForm(tuple(p), tuple(momentum), H, tuple(velocity), pdot)


TRIGSIMP_BUDGET = 150    # count_ops up to which sympy's trigsimp is also tried


def tidy_fraction(expr):
    """One solved expression as the reports would print it (Hamilton's form here, the
    Routhian in lagcli/analysis/routh.py). The shorter of: trigsimp of the cancelled form (small expressions), and the
    cancelled fraction with numerator and denominator in the reports' `display_form`."""
    cancelled = sp.cancel(sp.together(expr))
    numerator, denominator = sp.fraction(cancelled)
    if denominator.could_extract_minus_sign():
        numerator, denominator = -numerator, -denominator
    if denominator.is_Add and sp.count_ops(denominator) <= TRIGSIMP_BUDGET:
        denominator = min(display_form(sp.factor(denominator)), display_form(denominator), key=sp.count_ops)
    else:
        denominator = display_form(denominator)
    denominator = denominator.replace(lambda e: e.is_Add, fewest_squares)
    candidates = [_tidy_sign(display_form(numerator)) / denominator]
    if sp.count_ops(cancelled) <= TRIGSIMP_BUDGET:
        candidates.append(sp.trigsimp(cancelled))
    return min(candidates, key=sp.count_ops)


def tidy_split(expr, moving: set) -> sp.Expr:
    """A solved expression as a textbook writes it: the terms whose denominator is free of
    the `moving` symbols (coordinates, velocities or momenta, t) tidied as the reports do
    (`display_form`: m g L sin(theta), a multiplier), the others as one fraction
    (`tidy_fraction`), so that a potential's force does not disappear inside the kinetic
    part's fraction over its squared denominator. Hamilton's p' here, the Routh reduction's
    equations (lagcli/analysis/routh.py)."""
    polynomial, fractional = [], []
    for term in sp.Add.make_args(sp.sympify(expr)):
        denominator = sp.fraction(sp.together(term))[1]
        (fractional if denominator.free_symbols & moving else polynomial).append(term)
    return display_form(sp.Add(*polynomial)) + (tidy_fraction(sp.Add(*fractional)) if fractional else 0)


def _tidy_sign(expr):
    """-(-a - b + c) -> a + b - c: a sum with most terms negative is not printed under a minus."""
    if expr.is_Mul and expr.args[0] == -1 and len(expr.args) == 2 and expr.args[1].is_Add:
        return sp.expand(expr) if sp.count_ops(sp.expand(expr)) <= sp.count_ops(expr) else expr
    return expr
