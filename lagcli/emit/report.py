"""What `derive` reports, as pre-printed strings, shared by text, JSON and LaTeX.

`report_content(derivation, printer)` returns a plain dict (the JSON keys of
CONTRACT §3 plus a few extensions) whose expressions are strings made by
`printer`. Small expressions are tidied (trigsimp) for readability when
`simplify` is on; big ones are printed as derived (simplifying them can take
minutes and changes nothing in the physics).
"""
from __future__ import annotations

from collections.abc import Callable

import sympy as sp
from sympy.simplify.fu import TR10i

from lagcli.derive.result import Derivation
from lagcli.emit.tidy import expandable, trigsimp_safe

TIDY_MAX_OPS = 300      # beyond this, print as derived
TRIGSIMP_MAX_OPS = 60   # trigsimp is thorough but slow: only for what is already small


def tidy(expr: sp.Expr) -> sp.Expr:
    """A bounded simplification for display (never for numerics): fu's TR10i folds
    sin a sin b + cos a cos b into cos(a - b) cheaply, then small results get trigsimp.
    Bounded by operation counts only (`lagcli.emit.tidy`), never by a clock."""
    return _tidy(sp.sympify(expr))


def _tidy(expr: sp.Expr) -> sp.Expr:
    ops = sp.count_ops(expr)
    if expr.is_Atom or ops > TIDY_MAX_OPS or not expandable(expr):
        return expr
    best, best_ops = expr, ops
    candidate = sp.factor_terms(TR10i(expr))
    candidate_ops = sp.count_ops(candidate)
    if candidate_ops <= best_ops:
        best, best_ops = candidate, candidate_ops
    if best_ops <= TRIGSIMP_MAX_OPS and trigsimp_safe(best):
        candidate = sp.factor_terms(sp.trigsimp(best))
        if sp.count_ops(candidate) <= best_ops:
            best = candidate
    return best


def report_content(d: Derivation, printer: Callable[[sp.Expr], str], simplify: bool = True) -> dict:
    m = d.model
    cache: dict = {}

    def t(expr) -> sp.Expr:
        expr = sp.sympify(expr)
        if expr not in cache:
            cache[expr] = tidy(expr) if simplify else expr
        return cache[expr]

    def p(expr) -> str:
        return printer(t(expr))

    # T and L are assembled from their tidied parts: tidying the whole sum at once
    # is slow and misses cos(W t)**2 + sin(W t)**2 hidden inside products.
    T1 = sum((t(a_i) * v for a_i, v in zip(d.t1_coefficients, m.qd)), sp.S.Zero)
    T = t(d.T2) + T1 + t(d.T0)
    # Likewise each equation, from the tidied named terms of the explicit form (the
    # tests check these terms add up to the numerics' M q'' - F).
    F = [_forcing_from_terms(d, i, t) for i in range(len(m.q))]
    lhs = [sum((t(d.mass_matrix[i, j]) * a for j, a in enumerate(m.qdd)), sp.S.Zero) - F[i]
           for i in range(len(m.q))]

    def column(matrix) -> dict:
        return {q.name: p(e) for q, e in zip(m.q, matrix)}

    def rows(matrix) -> list:
        return [[p(matrix[i, j]) for j in range(matrix.cols)] for i in range(matrix.rows)]

    return {
        "name": m.name,
        "description": m.description,
        "coordinates": [q.name for q in m.q],
        "velocities": [v.name for v in m.qd],
        "parameters": {pi.symbol.name: pi.value for pi in m.parameters},
        "known": {name: p(expr) for name, expr in m.known},
        "counts": {"coordinates": len(m.q), "holonomic": d.n_holonomic,
                   "nonholonomic": d.n_nonholonomic},
        "dof": d.dof,
        "scleronomic": d.scleronomic,
        "kinetic_energy": {"T": printer(T), "T2": p(d.T2), "T1": printer(T1), "T0": p(d.T0)},
        "mass_matrix": rows(d.mass_matrix),
        "potential_energy": p(d.V),
        "lagrangian": printer(T - t(d.V)),
        "generalized_forces": column(d.generalized_forces),
        "nonconservative_forces": column(d.nonconservative_forces),
        "forces_conservative": d.forces_conservative,
        "force_potential": None if d.force_potential is None else p(d.force_potential),
        "equations": [{"coordinate": eq.coordinate.name, "lhs": printer(lhs_i), "rhs": p(eq.rhs)}
                      for eq, lhs_i in zip(d.equations, lhs)],
        "explicit_form": {
            "velocity_terms": column(d.velocity_terms),
            "mass_rate_terms": column(d.mass_rate_terms),
            "t1_rate_terms": column(d.t1_rate_terms),
            "position_terms": column(d.position_terms),
            "forcing": {q.name: printer(F_i) for q, F_i in zip(m.q, F)},
        },
        "constraints": [{"kind": r.kind, "name": r.label, "multiplier": r.multiplier.name,
                         "expr": p(r.expr), "a": [p(e) for e in r.a], "d": p(r.d),
                         "integrable": r.integrable} for r in d.constraints],
        "multipliers": [lam.name for lam in d.multipliers],
        "constraint_forces": {
            "generalized": column(d.generalized_constraint_forces) if d.constraints else {},
            "particles": {name: [p(e) for e in vec[: m.dimension]]
                          for name, vec in d.particle_constraint_forces.items()},
        },
        "gyroscopic_matrix": rows(d.gyroscopic_matrix),
        "ignorable_coordinates": [q.name for q in d.ignorable],
        "conserved_quantities": [{"name": c.name, "kind": c.kind, "expr": p(c.expr)} for c in d.conserved],
        "jacobi_integral": None if d.jacobi_integral is None else p(d.jacobi_integral),
        "energy_is_jacobi": d.energy_is_jacobi,
    }


def _forcing_from_terms(d: Derivation, i: int, t) -> sp.Expr:
    """F_i = Q'_i - c_i - (M_t q')_i - (gamma q')_i - a_t,i - (dV/dq - dT0/dq)_i, each term tidied."""
    gyroscopic = sum((t(d.gyroscopic_matrix[i, j]) * v for j, v in enumerate(d.model.qd)), sp.S.Zero)
    return (t(d.nonconservative_forces[i]) - t(d.velocity_terms[i]) - t(d.mass_rate_terms[i])
            - gyroscopic - t(d.t1_rate_terms[i]) - t(d.position_terms[i]))


def check_content(d: Derivation) -> dict:
    """The one-screen summary of `lagcli check`, as plain strings and numbers."""
    m = d.model
    if d.jacobi_integral is None:
        jacobi = "does not exist"
    else:
        jacobi = "exists (= total energy)" if d.energy_is_jacobi else "exists (differs from the total energy)"
    return {
        "source": m.source, "name": m.name, "description": m.description,
        "coordinates": ", ".join(q.name for q in m.q), "n": len(m.q),
        "parameters": ", ".join(f"{p.symbol.name} = {p.value:g}" for p in m.parameters) or "none",
        "particles": ", ".join(p.name for p in m.particles) or "none",
        "bodies": ", ".join(b.name for b in m.bodies) or "none",
        "holonomic": d.n_holonomic, "nonholonomic": d.n_nonholonomic,
        "integrable": [c.multiplier.name for c in d.constraints if c.integrable],
        "dof": d.dof,
        "time": "scleronomic" if d.scleronomic else "rheonomic",
        "ignorable": ", ".join(q.name for q in d.ignorable) or "none",
        "jacobi": jacobi,
    }
