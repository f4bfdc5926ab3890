"""Hamilton's form of the equations (unconstrained systems).

With T = 1/2 q'^T M q' + a^T q' + T0 the momenta are p = dL/dq' = M q' + a, and

    H(q, p, t) = 1/2 (p - a)^T M^-1 (p - a) - T0 + V
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
from lagcli.render.tidy import display_form

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
    M, a = sp.Matrix(d.mass_matrix), sp.Matrix(d.t1_coefficients)
    qd = sp.Matrix(model.qd)
    p = sp.Matrix([sp.Symbol(f"p_{q.name}", real=True) for q in model.q])
    momentum = (M * qd + a).applyfunc(display_form)        # p = M q' + a, tidied as the reports do
    if not (M.is_diagonal() or M.rows <= SYMBOLIC_SIZE):
        return HamiltonForm(tuple(p), tuple(momentum), None, None, None)
    velocity = M.LUsolve(p - a).applyfunc(sp.cancel)
    H = _tidy(((p - a).T * velocity)[0] / 2 - d.T0 + d.V)
    Q = sp.Matrix(d.nonconservative_forces).xreplace(dict(zip(model.qd, velocity)))
    qdot = tuple(_tidy(H.diff(pi)) for pi in p)
    pdot = tuple(_tidy(-H.diff(q) + Q[k]) for k, q in enumerate(model.q))
    return HamiltonForm(tuple(p), tuple(momentum), H, qdot, pdot)


def _tidy(expr):
    return sp.trigsimp(sp.cancel(expr)) if sp.count_ops(expr) <= 150 else expr
