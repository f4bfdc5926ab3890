"""Consistent initial states of constrained systems.

The state starts as the spec's `initial:` values overridden by `--init`
(anything not given is 0).  For constrained systems it must satisfy, at t0,

    phi_j(q, t0) = 0                 (holonomic rows)
    sum_k a_jk q'_k + d_j = 0        (every row; holonomic ones differentiated)

to 1e-8.  When it does not, the quantities the user did *not* give are solved for:

- dependent coordinates: Gauss-Newton (least squares, so any number of unknowns)
  on the holonomic rows, first from the given values (0 for missing ones), then
  from deterministic nearby starts (the unknowns shifted down, then up, by
  0.1 (1 + |q|), then a few seeded random shifts) — so a Cartesian pendulum with
  only x given hangs down (y < 0) rather than standing up;
- dependent velocities: the least-norm correction that makes A q' + d = 0, over
  the velocities not given (which start from 0).

When every coordinate (velocity) has a value, the ones in `soft` — the spec's
`initial:` values that `--init` did not override — are solved for instead,
starting from their given values: `--init x=0.5` on a Cartesian pendulum moves y
back onto the rod and projects the spec's (x', y') onto the rod's tangent (the
smallest change to the given velocities, not a reset to 0).

What was solved is reported in `notes` (shown on stderr).  When nothing may be
solved for, or the solve fails, a `UsageError` (exit status 2) names each
violated constraint and its residual.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagcli.spec_printer import spec_str
from lagcli.errors import UsageError
from lagcli.numerics import CONSTRAINT_TOLERANCE as TOLERANCE

_SOLVE_TOL = 1e-11      # what the Newton / least-squares solves aim for


@dataclass(frozen=True)
class InitialState:
    values: tuple[float, ...]          # [q..., q'...]
    notes: tuple[str, ...] = ()        # "solved for dependent coordinates: y = -0.8"


def initial_state(d, given: dict[str, float], params: dict[str, float], t0: float = 0.0,
                  soft=()) -> InitialState:
    """The state [q, q'] from `given` (name -> value), made consistent with the constraints.

    `d` is the Derivation, `params` every parameter's value by name, `soft` the given
    names that may still be solved for when nothing else can be.
    """
    model = d.model
    q = np.array([given.get(s.name, 0.0) for s in model.q], dtype=float)
    qd = np.array([given.get(s.name, 0.0) for s in model.qd], dtype=float)
    if not d.constraints:
        return InitialState(tuple(q) + tuple(qd))
    f = _ConstraintFunctions(d, params, t0)
    notes = []
    holonomic = [j for j, row in enumerate(d.constraints) if row.kind == "holonomic"]
    if holonomic and _worst(f.phi(q)) > TOLERANCE:
        free = _free(model.q, given, soft)
        q = _solve_positions(f, q, free, d)
        notes.append(_note("coordinates", model.q, free, q))
    residual = f.velocity_residual(q, qd)
    if _worst(residual) > TOLERANCE:
        free = _free(model.qd, given, soft)
        qd = _solve_velocities(f, q, qd, free, d)
        notes.append(_note("velocities", model.qd, free, qd))
    return InitialState(tuple(float(v) for v in (*q, *qd)), tuple(notes))


def spec_initial_state(d) -> tuple[InitialState, bool]:
    """The spec's own `initial:` state (missing values 0, default parameters) made
    consistent as `simulate` does, and True; when that is impossible, the state as
    given with a note saying so, and False. What generated code embeds as its
    default initial state (`lagcli.emit.interface.interface`)."""
    model = d.model
    given = dict(model.initial)
    try:
        return initial_state(d, given, {p.symbol.name: p.value for p in model.parameters}), True
    except UsageError:
        values = tuple(float(given.get(s.name, 0.0)) for s in model.q + model.qd)
        return InitialState(values, ("initial state: inconsistent with the constraints; used as given",)), False


def _free(symbols, given, soft) -> list[int]:
    free = [k for k, s in enumerate(symbols) if s.name not in given]
    return free or [k for k, s in enumerate(symbols) if s.name in soft]


class _ConstraintFunctions:
    """phi(q), its Jacobian, and A(q) q' + d(q) at t0, as numpy functions."""

    def __init__(self, d, params: dict[str, float], t0: float):
        model = d.model
        subs = {p.symbol: sp.Float(params[p.symbol.name]) for p in model.parameters}
        subs[model.t] = sp.Float(t0)
        q = list(model.q)
        self.rows = [j for j, row in enumerate(d.constraints) if row.kind == "holonomic"]
        phi = sp.Matrix([d.constraints[j].expr for j in self.rows]).xreplace(subs)
        A = sp.Matrix(d.constraint_matrix).xreplace(subs)
        bias = sp.Matrix([row.d for row in d.constraints]).xreplace(subs)
        self._phi = sp.lambdify([q], phi, "numpy")
        self._jac = sp.lambdify([q], phi.jacobian(q) if self.rows else phi, "numpy")
        self._A = sp.lambdify([q], A, "numpy")
        self._d = sp.lambdify([q], bias, "numpy")
        self.n, self.m = len(q), len(d.constraints)

    def phi(self, q) -> np.ndarray:
        return np.asarray(self._phi(q), dtype=float).reshape(len(self.rows))

    def jacobian(self, q) -> np.ndarray:
        return np.asarray(self._jac(q), dtype=float).reshape(len(self.rows), self.n)

    def A(self, q) -> np.ndarray:
        return np.asarray(self._A(q), dtype=float).reshape(self.m, self.n)

    def d(self, q) -> np.ndarray:
        return np.asarray(self._d(q), dtype=float).reshape(self.m)

    def velocity_residual(self, q, qd) -> np.ndarray:
        return self.A(q) @ qd + self.d(q)


def _solve_positions(f: _ConstraintFunctions, q, free, d) -> np.ndarray:
    if not free:
        _fail(d, [(d.constraints[j], r) for j, r in zip(f.rows, f.phi(q))],
              "every coordinate is given, so none can be solved for")
    for start in _starts(q, free):
        found = _gauss_newton(f, start, free)
        if found is not None:
            return found
    names = ", ".join(str(d.model.q[k]) for k in free)
    _fail(d, [(d.constraints[j], r) for j, r in zip(f.rows, f.phi(q))],
          f"solving for the coordinates not given ({names}) did not converge")


def _starts(q, free):
    yield q.copy()
    rng = np.random.default_rng(0)
    shifts = [-0.1, 0.1] + [None] * 6
    for shift in shifts:
        start = q.copy()
        scale = 1.0 + np.abs(q[free])
        start[free] += scale * (shift if shift is not None else rng.normal(0.0, 0.5, len(free)))
        yield start


def _gauss_newton(f: _ConstraintFunctions, q, free, iterations: int = 60):
    q = q.copy()
    for _ in range(iterations):
        r = f.phi(q)
        if not np.all(np.isfinite(r)):
            return None
        if _worst(r) <= _SOLVE_TOL:
            return q
        J = f.jacobian(q)[:, free]
        step = np.linalg.lstsq(J, -r, rcond=None)[0]
        if not np.any(step):
            return None
        norm, factor = np.linalg.norm(r), 1.0          # backtracking on |phi|
        while factor > 1e-6:
            trial = q.copy()
            trial[free] += factor * step
            if np.linalg.norm(f.phi(trial)) < norm:
                q = trial
                break
            factor /= 2
        else:
            return None
    return q if _worst(f.phi(q)) <= 10 * _SOLVE_TOL else None


def _solve_velocities(f: _ConstraintFunctions, q, qd, free, d) -> np.ndarray:
    residual = f.velocity_residual(q, qd)
    if not free:
        _fail(d, list(zip(d.constraints, residual)), "every velocity is given, so none can be solved for",
              level="velocity")
    A = f.A(q)
    qd = qd.copy()       # unknowns not given are 0 here; soft ones keep their given values
    qd[free] += np.linalg.lstsq(A[:, free], -(A @ qd + f.d(q)), rcond=None)[0]   # least-norm change
    after = f.velocity_residual(q, qd)
    if not np.all(np.isfinite(after)) or _worst(after) > TOLERANCE * 1e-2:
        names = ", ".join(str(d.model.qd[k]) for k in free)
        _fail(d, list(zip(d.constraints, residual)),
              f"the velocities not given ({names}) cannot satisfy them", level="velocity")
    return qd


def _worst(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.max(np.abs(values))) if values.size else 0.0


def _note(what: str, symbols, free, values) -> str:
    solved = ", ".join(f"{symbols[k]} = {values[k]:.12g}" for k in free)
    return f"initial state: solved for dependent {what}: {solved}"


def _fail(d, rows_and_residuals, reason: str, level: str = "position") -> None:
    lines = [f"{d.model.source}: the initial state violates the constraints ({reason}):"]
    for row, value in rows_and_residuals:
        if abs(value) > TOLERANCE or not np.isfinite(value):
            label = f"{row.label!r}" if row.label else row.multiplier.name
            lines.append(f"  constraint {label}: {spec_str(row.expr)} = 0 "
                         f"({row.kind}; {level} residual {value:.3g})")
    lines.append("  hint: give fewer coordinates/velocities with --init (the others are solved for), "
                 "or a consistent state")
    raise UsageError("\n".join(lines))
