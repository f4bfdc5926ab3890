"""Discrete mechanics (Marsden and West 2001): what the variational integrator of
`simulate --method variational` evaluates, as sympy expressions of (t, q, q').

The discrete Lagrangian is the midpoint rule (second order, symmetric):

    L_d(q0, q1) = h L(qm, v, tm),   qm = (q0 + q1)/2,  v = (q1 - q0)/h,  tm = t0 + h/2

and the discrete Lagrange-d'Alembert principle with the midpoint forces
f- = f+ = (h/2) Q'(qm, v, tm) gives, in position-momentum form, with the
constraint forces A^T lambda of lagcli's convention (RATTLE-type: the position
constraint at the new point, the velocity-level one for the new momentum):

    p0 = g(m) - (h/2) f(m) - (h/2) A(q0, t0)^T mu     phi(q1, t1) = 0        (solved for q1, mu)
    p1 = g(m) + (h/2) f(m) + (h/2) A(q1, t1)^T nu     A(q1, t1) q1' + d(q1, t1) = 0   (linear)

where g = dL/dq' = M q' + a (the momenta), f = dL/dq + Q' and (m) means at (tm, qm, v).
The first line is solved by Newton with its Jacobian

    d/dq1 = 1/2 (dg/dq - h/2 df/dq) + 1/h (dg/dq' - h/2 df/dq'),   d/dmu = -(h/2) A0^T

from the second derivatives below (symbolic, generated as code; no finite differences).
The new velocity q1' comes from p1 = M(q1, t1) q1' + a(q1, t1), with a = g at q' = 0.

    DiscreteGroups   the expressions, grouped as the generated functions return them
    discrete_groups  from a Derivation
    refusal          why a system cannot be integrated this way (nonholonomic rows), or None
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import sympy as sp

from lagcli.derive.result import Derivation
from lagcli.model.calculus import derivative

METHOD = "variational"


@dataclass(frozen=True)
class DiscreteGroups:
    """Flat, row-major groups of expressions in (t, q, q') (and the inputs).

    momentum        n      g = dL/dq' = M q' + a
    momentum_rate   n      f = dL/dq + Q'
    momentum_q      n*n    dg_i/dq_j
    momentum_v      n*n    dg_i/dq'_j = M (mirrored: exactly symmetric)
    rate_q          n*n    df_i/dq_j
    rate_v          n*n    df_i/dq'_j
    position        d      phi_j (holonomic rows, in order)
    gradient        d*n    dphi_j/dq_k = a_jk
    position_rate   d      dphi_j/dt = d_j
    """

    momentum: tuple
    momentum_rate: tuple
    momentum_q: tuple
    momentum_v: tuple
    rate_q: tuple
    rate_v: tuple
    position: tuple
    gradient: tuple
    position_rate: tuple

    def groups(self) -> dict[str, tuple]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


MOMENTA = ("momentum", "momentum_rate")
JACOBIAN = ("momentum_q", "momentum_v", "rate_q", "rate_v")
HOLONOMIC = ("position", "gradient", "position_rate")


def discrete_groups(d: Derivation) -> DiscreteGroups:
    """The expressions of `DiscreteGroups` for `d` (holonomically constrained or not)."""
    q, qd, n = d.model.q, d.model.qd, d.n
    M = d.mass_matrix
    memo: dict = {}      # free symbols of shared subtrees, found once (calculus.derivative)
    # sums built at once (Add of all terms), derivatives by lagcli's calculus.derivative:
    # the same expressions as sum() and sympy's diff, without their quadratic and per-node costs
    g = [sp.Add(*(M[i, k] * qd[k] for k in range(n))) + d.t1_coefficients[i] for i in range(n)]
    f = [derivative(d.L, q[i], memo) + d.nonconservative_forces[i] for i in range(n)]
    rows = [r for r in d.constraints if r.kind == "holonomic"]
    return DiscreteGroups(
        momentum=tuple(g),
        momentum_rate=tuple(f),
        momentum_q=tuple(_derivative(g[i], q[j], memo) for i in range(n) for j in range(n)),
        momentum_v=tuple(M[min(i, j), max(i, j)] for i in range(n) for j in range(n)),
        rate_q=tuple(_derivative(f[i], q[j], memo) for i in range(n) for j in range(n)),
        rate_v=tuple(_derivative(f[i], qd[j], memo) for i in range(n) for j in range(n)),
        position=tuple(r.expr for r in rows),
        gradient=tuple(a for r in rows for a in r.a),
        position_rate=tuple(r.d for r in rows),
    )


def _derivative(expr: sp.Expr, symbol: sp.Symbol, memo: dict) -> sp.Expr:
    """d expr / d symbol for Newton's Jacobian, with the derivatives of the kinks of
    sign, abs, min and max taken where they exist: DiracDelta -> 0 (sign is flat on both
    sides), Heaviside(z) -> (1 + sign(z))/2 (the side of min/max that is chosen)."""
    result = derivative(expr, symbol, memo)
    if result.has(sp.DiracDelta, sp.Heaviside):
        result = result.replace(sp.DiracDelta, lambda *args: sp.S.Zero)
        result = result.replace(sp.Heaviside, lambda z, *rest: (1 + sp.sign(z)) / 2)
    return result


def refusal(d: Derivation) -> str | None:
    """Why `--method variational` cannot integrate `d`, naming the constraint; None when it can.
    The discrete scheme here enforces holonomic constraints; velocity constraints would
    need a discrete nonholonomic scheme (Cortes and Martinez 2001), which lagcli does not have."""
    for j, row in enumerate(d.constraints, start=1):
        if row.kind != "holonomic":
            label = f"'{row.label}'" if row.label else f"{j}"
            disguise = (" (it is integrable: written as a position constraint phi(q, t) = 0 it "
                        "would be holonomic)" if row.integrable else "")
            return (f"--method {METHOD}: constraint {label} ({row.expr} = 0) is nonholonomic{disguise}; "
                    f"the variational integrator enforces holonomic constraints only\n"
                    "  hint: use --method DOP853 (or Radau) for this system")
    return None
