"""Equilibria: points where the system can rest, q' = 0, q'' = 0.

With q' = 0 the forcing (docs/design.md) is F(q, 0, t) = Q'(q, 0) - a_t + dT0/dq - dV/dq,
so for a scleronomic system the equilibria are the stationary points of V
(static equilibria), and for a rheonomic or gyroscopic one whose L has no
explicit t (a bead on a spinning hoop) those of the fictitious potential
V' = V - T0 (relative equilibria, lecture notes Ex. 6.6). Constrained systems
add the multipliers: F(q, 0) + A^T lambda = 0 with phi(q) = 0. Steady motions
at given momenta of ignorable coordinates are the Routhian's business
(`routh.py`, its effective potential).

Solutions are symbolic (sympy's solve, for the parameters as symbols) when the
equations are small (`SYMBOLIC_BUDGET` operations, at most 2 unknowns, no
constraints), else numeric: scipy's least_squares from each guess (`--guess`,
the spec's initial state and the origin), duplicates merged.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

SYMBOLIC_BUDGET = 80        # count_ops of the equations sympy's solve is given
SYMBOLIC_UNKNOWNS = 2
_SAME = 1e-7                # solutions this close (max norm) are one


@dataclass(frozen=True)
class Stationary:
    values: tuple[float, ...]           # the unknowns' values
    symbolic: tuple[sp.Expr, ...] | None  # closed forms (None: found numerically)


def solve_stationary(equations, unknowns, parameters: dict, guesses) -> list[Stationary]:
    """Real solutions of `equations` = 0 for `unknowns`, `parameters` symbol -> value."""
    found = _symbolic(equations, unknowns, parameters)
    if not found:   # not attempted, or nothing real in closed form: search numerically
        found = _numeric(equations, unknowns, parameters, guesses)
    return distinct(found, len(unknowns))


def distinct(found: list[Stationary], k: int) -> list[Stationary]:
    """`found` without repeats (the first k values within _SAME), sorted."""
    unique: list[Stationary] = []
    for s in found:
        if not any(np.max(np.abs(np.subtract(s.values[:k], u.values[:k])), initial=0.0) < _SAME for u in unique):
            unique.append(s)
    return sorted(unique, key=lambda s: s.values)


def _symbolic(equations, unknowns, parameters) -> list[Stationary] | None:
    equations = [sp.factor_terms(e) for e in equations if e != 0]
    if len(unknowns) > SYMBOLIC_UNKNOWNS or sum(sp.count_ops(e) for e in equations) > SYMBOLIC_BUDGET:
        return None
    if not equations:
        return [Stationary(tuple(0.0 for _ in unknowns), tuple(sp.S.Zero for _ in unknowns))]
    try:
        solutions = sp.solve(equations, list(unknowns), dict=True)
    except (NotImplementedError, ValueError):
        return None
    numbers = {s: sp.Float(v, 30) for s, v in parameters.items()}
    found = []
    for solution in solutions:
        exprs = tuple(solution.get(u, sp.S.Zero) for u in unknowns)
        if any(e.free_symbols - set(parameters) for e in exprs):
            continue                                     # a family: left to the numeric search
        values = [complex(e.xreplace(numbers).evalf(30)) for e in exprs]
        if all(abs(v.imag) < 1e-12 and np.isfinite(v.real) for v in values):
            found.append(Stationary(tuple(v.real for v in values), exprs))
    return found


def _numeric(equations, unknowns, parameters, guesses) -> list[Stationary]:
    from scipy.optimize import least_squares

    numbers = {s: sp.Float(v, 30) for s, v in parameters.items()}
    exprs = [sp.sympify(e).xreplace(numbers) for e in equations]
    f = sp.lambdify([list(unknowns)], exprs, modules="numpy", cse=True)
    jac = sp.lambdify([list(unknowns)], sp.Matrix(exprs).jacobian(list(unknowns)), modules="numpy", cse=True)
    found = []
    for guess in guesses:
        with np.errstate(all="ignore"):   # a guess at a singular point just fails
            result = least_squares(lambda z: np.asarray(f(z), dtype=float).reshape(-1),
                                   np.asarray(guess, dtype=float),
                                   jac=lambda z: np.asarray(jac(z), dtype=float).reshape(len(exprs), len(unknowns)),
                                   xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
        if np.all(np.isfinite(result.fun)) and np.max(np.abs(result.fun), initial=0.0) < 1e-10:
            found.append(Stationary(tuple(0.0 if abs(v) < 1e-13 else float(v) for v in result.x), None))
    return found


@dataclass(frozen=True)
class RestPoint:
    coordinates: dict                   # name -> value
    symbolic: dict | None               # name -> closed form (sympy)
    linear: object                      # LinearModel about it (None at a singular point)
    stability: object                   # Stability (None at a singular point)


def equilibria(d, parameters: dict, guesses: list[dict], independent=()) -> list[RestPoint]:
    """Every equilibrium found, with its linearization and stability."""
    from lagcli.analysis.linearize import CompiledSystem, SingularPoint, linearize
    from lagcli.analysis.operating_point import Point
    from lagcli.analysis.stability import stability

    model = d.model
    rest = {v: 0 for v in model.qd} | {model.t: 0}
    lam = sp.Matrix(d.multipliers)
    _require_autonomous(d)
    balance = sp.Matrix(d.forcing).xreplace(rest)
    if d.constraints:
        balance += sp.Matrix(d.constraint_matrix).xreplace(rest).T * lam
    holonomic = [c.expr.xreplace(rest) for c in d.constraints if c.kind == "holonomic"]
    unknowns = list(model.q) + list(d.multipliers)
    symbols = {p.symbol: parameters[p.symbol.name] for p in (*model.parameters, *model.inputs)}
    starts = [[g.get(s.name, 0.0) for s in unknowns] for g in guesses]
    if d.constraints:
        found = distinct(_numeric(list(balance) + holonomic, unknowns, symbols, starts), len(model.q))
    else:
        found = solve_stationary(list(balance), unknowns, symbols, starts)
    system = CompiledSystem(d)
    n = len(model.q)
    out = []
    for s in found:
        point = Point(0.0, np.array(s.values[:n]), np.zeros(n), dict(parameters))
        try:
            lm = linearize(system, point, independent)
        except SingularPoint:
            lm = None
        names = [q.name for q in model.q]
        out.append(RestPoint(dict(zip(names, s.values[:n])),
                               dict(zip(names, s.symbolic[:n])) if s.symbolic else None,
                               lm, stability(lm) if lm is not None else None))
    return out


def _require_autonomous(d) -> None:
    """Equilibria need F(q, 0, t) without t (a cancelling W t, as on the spinning hoop, is fine)."""
    from lagcli.model.calculus import numerically_zero
    from lagcli.errors import UsageError

    model = d.model
    at_rest = sp.Matrix(d.forcing).xreplace({v: 0 for v in model.qd})
    if model.t in at_rest.free_symbols and not numerically_zero([e.diff(model.t) for e in at_rest]):
        raise UsageError(f"{model.source}: the equations at rest depend explicitly on t, so there is "
                         "no equilibrium in the usual sense\n  hint: `lagcli linearize --at t=...` "
                         "gives the instantaneous linear model")


def default_guesses(d, given: list[dict]) -> list[dict]:
    """The user's guesses, else the spec's initial state and the origin."""
    if given:
        return given
    return [dict(d.model.initial), {}]
