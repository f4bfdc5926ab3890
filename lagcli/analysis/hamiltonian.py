"""Hamilton's form of the equations (unconstrained systems).

With T = 1/2 q'^T M q' + a^T q' + T0 the momenta are p = dL/dq' = M q' + a, and

    H(q, p, t) = 1/2 (p - a)^T M^-1 (p - a) - T0 + V
    q' =  dH/dp = M^-1 (p - a)
    p' = -dH/dq + Q'  =  dL/dq (q, q', t) + Q'        (q' = M^-1 (p - a))

H is written out symbolically when M is diagonal or at most 2 x 2 (`SYMBOLIC_SIZE`);
otherwise H and q'(p) stay in the solved form above, and the numeric right-hand
side (`HamiltonRhs`) solves M q' = p - a at each call — never a symbolic inverse
of a large matrix.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagcli.render.tidy import display_form

from lagcli.errors import UsageError

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


class HamiltonRhs:
    """y = [q, p] -> [q', p'] (numeric; sympy's lambdify of lagcli-built expressions)."""

    def __init__(self, d, parameters: dict):
        model = d.model
        values = {p.symbol: sp.Float(parameters.get(p.symbol.name, p.value), 30)
                  for p in (*model.parameters, *model.inputs)}
        M, a = sp.Matrix(d.mass_matrix).xreplace(values), sp.Matrix(d.t1_coefficients).xreplace(values)
        L = d.L.xreplace(values)
        force = sp.Matrix([L.diff(q) for q in model.q]) + sp.Matrix(d.nonconservative_forces).xreplace(values)
        args = [model.t, list(model.q), list(model.qd)]
        self._M = sp.lambdify(args, M, modules="numpy", cse=True)
        self._a = sp.lambdify(args, a, modules="numpy", cse=True)
        self._force = sp.lambdify(args, force, modules="numpy", cse=True)
        self._H = sp.lambdify(args, (d.T2 - d.T0 + d.V).xreplace(values), modules="numpy", cse=True)
        self.n = len(model.q)

    def velocities(self, t, q, p) -> np.ndarray:
        zero = np.zeros(self.n)
        M = np.asarray(self._M(t, q, zero), dtype=float).reshape(self.n, self.n)
        a = np.asarray(self._a(t, q, zero), dtype=float).reshape(self.n)
        return np.linalg.solve(M, p - a)

    def __call__(self, t, y) -> np.ndarray:
        q, p = y[:self.n], y[self.n:]
        qd = self.velocities(t, q, p)
        return np.concatenate([qd, np.asarray(self._force(t, q, qd), dtype=float).reshape(self.n)])

    def hamiltonian(self, t, y) -> float:
        """H = T2 - T0 + V at q' = q'(q, p)."""
        q, p = y[:self.n], y[self.n:]
        return float(self._H(t, q, self.velocities(t, q, p)))
