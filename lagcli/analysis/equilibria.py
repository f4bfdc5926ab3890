"""Equilibria: points where the system can rest, q' = 0, q'' = 0.

With q' = 0 the forcing (docs/design.md) is F(q, 0, t) = Q'(q, 0) - a_t + dT0/dq - dV/dq,
so for a scleronomic system the equilibria are the stationary points of V
(static equilibria), and for a rheonomic or gyroscopic one whose L has no
explicit t (a bead on a spinning hoop) those of the fictitious potential
V' = V - T0 (relative equilibria, lecture notes Ex. 6.6). Constrained systems
add the multipliers: F(q, 0) + A^T lambda = 0 with phi(q) = 0. Steady motions
at given momenta of ignorable coordinates are the Routhian's business
(`routh.py`, its effective potential).

Closed forms, for the parameters as symbols, come from an elimination in bounded work
(`closed_forms.py`: one factor, one unknown at a time, counted budgets; multipliers
and holonomic rows included); when it finishes every branch without a solution, there
is no point of rest, and the result says so. The numeric search of `rest_search`
(every angle's full turn, families brought to one member, repeats merged by pose) runs
in every case, from each guess (`--guess`, else the spec's initial state and the
origin), and adds what the closed forms missed. Where the mass matrix is singular
because of the coordinates, `singular_chart.py` decides.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagcli.analysis.rest_search import RestProblem, Stationary, distinct, search

def _symbolic(equations, unknowns, parameters) -> tuple[list[Stationary], bool]:
    """The real closed-form solutions (`closed_forms.eliminate`), and whether the elimination
    was complete and found no point of rest at all (then there is none)."""
    from lagcli.analysis.closed_forms import eliminate

    numbers = {s: sp.Float(v, 30) for s, v in parameters.items()}
    elimination = eliminate([e for e in equations if e != 0], unknowns, numbers)
    found = []
    for solution in elimination.solutions:
        exprs = tuple(solution.get(u, u) for u in unknowns)
        if any(e.free_symbols - set(parameters) for e in exprs):
            continue                                     # a family: left to the numeric search
        values = [complex(e.xreplace(numbers).evalf(30)) for e in exprs]
        if all(abs(v.imag) < 1e-12 and np.isfinite(v.real) for v in values):
            # a real value written with I (a casus irreducibilis root) is kept as a number only
            closed = None if any(e.has(sp.I) for e in exprs) else exprs
            found.append(Stationary(tuple(v.real for v in values), closed))
    return found, elimination.complete and not elimination.solutions


def solve_stationary(equations, unknowns, parameters: dict, guesses) -> list[Stationary]:
    """Real solutions of `equations` = 0 for `unknowns` (`parameters` symbol -> value): the
    closed forms, else those reached from each guess itself (Routh's steady motions)."""
    problem = rest_problem(equations, unknowns, len(unknowns), parameters, ())
    return distinct(_symbolic(equations, unknowns, parameters)[0] or search(problem, guesses, vary=False), problem)


def rest_problem(equations, unknowns, n: int, parameters: dict, angles, pose=None) -> RestProblem:
    """The equations with the parameters' values, compiled for the numeric search
    (`pose`: the pose key of the coordinates, `pose.pose_function`)."""
    numbers = {s: sp.Float(v, 30) for s, v in parameters.items()}
    exprs = [sp.sympify(e).xreplace(numbers) for e in equations]
    k = len(unknowns)
    f = sp.lambdify([list(unknowns)], exprs, modules="numpy", cse=True)
    jac = sp.lambdify([list(unknowns)], sp.Matrix(exprs).jacobian(list(unknowns)), modules="numpy", cse=True)
    index = {s: i for i, s in enumerate(unknowns)}
    return RestProblem(lambda z: np.asarray(f(z), dtype=float).reshape(-1),
                       lambda z: np.asarray(jac(z), dtype=float).reshape(len(exprs), k),
                       n,
                       frozenset(index[s] for s in angles), pose)


@dataclass(frozen=True)
class RestPoint:
    coordinates: dict                   # name -> value
    symbolic: dict | None               # name -> closed form (sympy)
    linear: object                      # LinearModel about it (None at a singular point)
    stability: object                   # Stability (None at a singular point)
    free: tuple[str, ...] = ()          # coordinates it is an equilibrium for any value of
    singular: object = None             # singular_chart.CoordinateSingularity where M is singular


def equilibria(d, parameters: dict, guesses: list[dict], independent=(), compiled=None) -> "RestPoints":
    """Every equilibrium found, with its linearization and stability (`compiled`: the
    derivation's `linearize.CompiledSystem`, when the caller has it)."""
    from lagcli.analysis.linearize import CompiledSystem
    from lagcli.analysis.pose import pose_expressions, pose_function
    from lagcli.analysis.singular_chart import Charts
    from lagcli.model.angles import angle_coordinates

    model = d.model
    rest = {v: 0 for v in model.qd} | {model.t: 0}
    _require_autonomous(d)
    forcing = sp.Matrix(d.forcing).xreplace(rest)
    balance = forcing
    if d.constraints:
        balance = forcing + sp.Matrix(d.constraint_matrix).xreplace(rest).T * sp.Matrix(d.multipliers)
    holonomic = [c.expr.xreplace(rest) for c in d.constraints if c.kind == "holonomic"]
    unknowns = list(model.q) + list(d.multipliers)
    symbols = {p.symbol: parameters[p.symbol.name] for p in (*model.parameters, *model.inputs)}
    angles = [q for q in model.q if q.name in angle_coordinates(model)]
    pose = pose_expressions(model, symbols)
    problem = rest_problem(list(balance) + holonomic, unknowns, len(model.q), symbols, angles,
                           pose_function(model, symbols, pose))
    closed, none = _symbolic(list(balance) + holonomic, unknowns, symbols)
    starts = [[g.get(s.name, 0.0) for s in unknowns] for g in guesses]
    found = distinct(closed + search(problem, starts), problem)
    system = compiled or CompiledSystem(d)
    charts = _Lazy(lambda: Charts(d, parameters, pose))
    points = [_rest_point(system, charts, s, parameters, independent, problem.angles) for s in found]
    return RestPoints(p for p in points if p is not None).proved(none)


class RestPoints(list):
    """The RestPoints found; `proved_none`: the closed forms show there is no point of rest."""

    proved_none = False

    def proved(self, none: bool) -> "RestPoints":
        self.proved_none = none and not self
        return self


class _Lazy:
    """A value made on first use (the charts of singular points are compiled only when needed)."""

    def __init__(self, make):
        self._make, self._value = make, None

    def __call__(self):
        if self._value is None:
            self._value = self._make()
        return self._value


def _rest_point(system, charts, s: Stationary, parameters: dict, independent, angles) -> RestPoint | None:
    """`s` linearized (a RestPoint); `system` is the derivation's `CompiledSystem`. Where the
    mass matrix is singular because of the coordinates, the other descriptions of the pose
    decide (`singular_chart.py`); None when they show it is no equilibrium."""
    from lagcli.analysis.linearize import SingularPoint, linearize
    from lagcli.analysis.operating_point import Point
    from lagcli.analysis.singular_chart import examine
    from lagcli.analysis.stability import stability

    model = system.derivation.model
    n = len(model.q)
    names = [q.name for q in model.q]
    q = np.array(s.values[:n])
    lm, singular = None, None
    turning = frozenset(names[k] for k in angles)
    if _examinable(system, charts, q, parameters, turning):
        singular = examine(charts(), q, turning)
        if not singular.equilibrium:
            return None
        lm = singular.linear
    else:
        try:
            lm = linearize(system, Point(0.0, q, np.zeros(n), dict(parameters)), independent)
        except SingularPoint:
            lm = None
    return RestPoint(dict(zip(names, s.values[:n])), dict(zip(names, s.symbolic[:n])) if s.symbolic else None,
                     lm, stability(lm) if lm is not None else None, tuple(names[k] for k in s.free), singular)


def _examinable(system, charts, q: np.ndarray, parameters: dict, angles: frozenset) -> bool:
    """M is singular at q and the other descriptions of the pose decide there: always for
    an unconstrained system, for a constrained one where the velocities that move nothing
    turn angles only (its charts are compiled only then)."""
    from scipy.linalg import null_space

    from lagcli.analysis.operating_point import Point
    from lagcli.analysis.singular_chart import SINGULAR

    d = system.derivation
    if not d.constraints:
        return charts().singular(q)
    with np.errstate(all="ignore"):
        M = system.mass_matrix(Point(0.0, q, np.zeros(len(q)), dict(parameters)))
        s = np.linalg.svd(M, compute_uv=False) if np.all(np.isfinite(M)) else None
    if s is None or s[-1] > SINGULAR * max(s[0], 1e-300):
        return False
    still = null_space(M, rcond=SINGULAR)
    names = [x.name for x in d.model.q]
    moved = {names[k] for k in range(len(names)) if np.max(np.abs(still[k]), initial=0.0) > 1e-6}
    return bool(moved) and moved <= angles


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
