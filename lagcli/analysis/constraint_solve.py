"""The numeric half of `lagcli.analysis.initial_state`: a state made consistent with the
constraint rows (scipy's least squares on the holonomic rows, the least-norm velocity
correction), imported only for systems with constraints (numpy and scipy cost ~0.15 s of
start-up that `generate` and `simulate` of an unconstrained system do not pay). It returns
plain values and reads the `origin` it is given (`initial_state.Origin`: where each value
came from, for notes and hints) without importing its module, which imports this one."""
from __future__ import annotations

import numpy as np
import sympy as sp

from lagcli.render.spec_printer import spec_str
from lagcli.errors import UsageError, clip
from lagcli.analysis.velocity_scale import NATURAL_FACTOR, ROUNDING, VelocityScale
from lagcli.interface import CONSTRAINT_TOLERANCE as TOLERANCE

_SOLVE_TOL = 1e-11      # what the least-squares solves aim for
_ROW_ECHO = 60          # characters of a row's expression in a message: every row must fit
_RCOND = 1e-8           # singular values of the free velocities' columns below this (relative) are not used


def consistent_state(d, given: dict[str, float], params: dict[str, float], t0: float,
                     origin) -> tuple[tuple[float, ...], tuple[str, ...]]:
    """`initial_state` of a system with constraint rows: the given state, its dependent
    coordinates and velocities solved for where it violates them ([q, q'], notes)."""
    model = d.model
    q = np.array([given.get(s.name, 0.0) for s in model.q], dtype=float)
    qd = np.array([given.get(s.name, 0.0) for s in model.qd], dtype=float)
    soft = origin.soft
    f = _ConstraintFunctions(d, params, t0)
    notes = []
    holonomic = [j for j, row in enumerate(d.constraints) if row.kind == "holonomic"]
    if holonomic and _worst(f.phi(q)) > TOLERANCE:
        q, free = _first_solution(lambda free: _solve_positions(f, q, free, d, origin),
                                  _free(model.q, given, soft))
        notes.append(origin.note("coordinates", model.q, free, q))
    residual = f.velocity_residual(q, qd)
    if _worst(residual) > TOLERANCE:
        qd, free = _first_solution(lambda free: _solve_velocities(f, q, qd, free, d, origin),
                                   _free(model.qd, given, soft))
        notes.append(origin.note("velocities", model.qd, free, qd))
    return tuple(float(v) for v in (*q, *qd)), tuple(notes)


def _free(symbols, given, soft) -> list[list[int]]:
    """The unknowns to solve for, in the order to try them: the values not given, then
    those together with the spec's own (`soft`) values, when that adds any."""
    missing = [k for k, s in enumerate(symbols) if s.name not in given]
    widened = [k for k, s in enumerate(symbols) if s.name not in given or s.name in soft]
    return [missing, widened] if missing and widened != missing else [widened]


def _first_solution(solve, choices):
    """solve(free) for each choice of unknowns until one succeeds: (values, free). The
    last choice's failure (a UsageError naming what was given) is the one raised."""
    for free in choices[:-1]:
        try:
            return solve(free), free
        except UsageError:
            continue
    return solve(choices[-1]), choices[-1]


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
        self._M = lambda: sp.lambdify([q], sp.Matrix(d.mass_matrix).xreplace(subs), "numpy")
        self.n, self.m = len(q), len(d.constraints)

    def mass_matrix(self, q) -> np.ndarray:
        """M(q, t0); made only when a velocity repair is judged."""
        return np.asarray(self._M()(q), dtype=float).reshape(self.n, self.n)

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


def _solve_positions(f: _ConstraintFunctions, q, free, d, origin) -> np.ndarray:
    if not free:
        _fail(d, [(d.constraints[j], r) for j, r in zip(f.rows, f.phi(q))],
              "every coordinate is given, so none can be solved for", origin)
    for start in _starts(q, free):
        found = _least_squares(f, start, free)
        if found is not None:
            return found
    names = ", ".join(str(d.model.q[k]) for k in free)
    _fail(d, [(d.constraints[j], r) for j, r in zip(f.rows, f.phi(q))],
          f"solving for the coordinates {names} did not converge", origin)


def _starts(q, free):
    yield q.copy()
    rng = np.random.default_rng(0)
    shifts = [-0.1, 0.1] + [None] * 6
    for shift in shifts:
        start = q.copy()
        scale = 1.0 + np.abs(q[free])
        start[free] += scale * (shift if shift is not None else rng.normal(0.0, 0.5, len(free)))
        yield start


def _least_squares(f: _ConstraintFunctions, q, free):
    """phi(q) = 0 over the coordinates `free`, from `q`, by scipy's trust-region least
    squares ("trf" accepts more unknowns than rows); None when it does not get there."""
    from scipy.optimize import least_squares

    def residual(x):
        trial = q.copy()
        trial[free] = x
        return f.phi(trial)

    def jacobian(x):
        trial = q.copy()
        trial[free] = x
        return f.jacobian(trial)[:, free]

    if not np.all(np.isfinite(residual(q[free]))):
        return None
    found = least_squares(residual, q[free], jac=jacobian, method="trf",
                          xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
    result = q.copy()
    result[free] = found.x
    ok = np.all(np.isfinite(found.x)) and _worst(f.phi(result)) <= 10 * _SOLVE_TOL
    return result if ok else None


def _solve_velocities(f: _ConstraintFunctions, q, qd, free, d, origin) -> np.ndarray:
    residual = f.velocity_residual(q, qd)
    if not free:
        _fail(d, list(zip(d.constraints, residual)), "every velocity is given, so none can be solved for",
              origin, level="velocity")
    A = f.A(q)
    given = qd
    qd = qd.copy()       # unknowns not given are 0 here; soft ones keep their given values
    # least-norm change; directions the free velocities move only by a hair (singular values
    # below RCOND of the largest) are not used: they would "fix" a row with a huge velocity
    change = np.zeros_like(qd)
    change[free] = np.linalg.lstsq(A[:, free], -(A @ qd + f.d(q)), rcond=_RCOND)[0]
    qd += change
    after = f.velocity_residual(q, qd)
    names = ", ".join(str(d.model.qd[k]) for k in free)
    if not np.all(np.isfinite(after)) or _worst(after) > TOLERANCE * 1e-2:
        unsatisfied = [(row, value) for row, value, now in zip(d.constraints, residual, after)
                       if not abs(now) <= TOLERANCE * 1e-2]
        _fail(d, unsatisfied, f"the velocities solved for ({names}) cannot satisfy these rows", origin,
              level="velocity")
    _judge_in_scale(VelocityScale.of(f.mass_matrix(q), given, A, residual), change, free, d, origin,
                    list(zip(d.constraints, residual)))
    return qd


def _judge_in_scale(scale: VelocityScale, change, free, d, origin, rows) -> None:
    """Refuse a repair out of the state's scale (lagcli.analysis.velocity_scale)."""
    symbols = d.model.qd
    fast = scale.too_fast(change, free)
    if fast:
        said = ", ".join(f"{symbols[k]} by {value:.3g} (natural velocity {natural:.3g})"
                         for k, value, natural in fast)
        _fail(d, rows, f"solving for the velocities would change {said}: over {NATURAL_FACTOR:g} times "
              "the natural velocity of the given state's kinetic energy; the rows are ill-conditioned there",
              origin, level="velocity")
    moved = [k for k in free if symbols[k].name in origin.soft and change[k] != 0]
    if moved and not origin.overridden():
        only = np.zeros_like(change)
        only[moved] = change[moved]
        size = scale.relative(only)
        if size > ROUNDING:
            largest = sorted(moved, key=lambda k: -abs(change[k]))[:3]
            said = ", ".join(f"{symbols[k]} by {change[k]:.3g}" for k in largest)
            _fail(d, rows, f"the velocities not given cannot satisfy these rows; satisfying them would change "
                  f"the spec's {origin.sources.spec} velocities by {size:.0%} of the state's scale ({said}), "
                  f"more than rounding ({ROUNDING:.0%})", origin, level="velocity")


def _worst(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.max(np.abs(values))) if values.size else 0.0


def _fail(d, rows_and_residuals, reason: str, origin, level: str = "position") -> None:
    lines = [f"{d.model.source}: the initial state violates the constraints ({reason}):"]
    for row, value in rows_and_residuals:
        if abs(value) > TOLERANCE or not np.isfinite(value):
            # a named row with a long expression (a rolling contact's, pages long) by its name only
            label = f"{row.label!r}" if row.label else row.multiplier.name
            text = spec_str(row.expr)
            written = label if row.label and len(text) > _ROW_ECHO else f"{label}: {clip(text, _ROW_ECHO)} = 0"
            lines.append(f"  constraint {written} ({row.kind}; {level} residual {value:.3g})")
    lines.append(origin.hint())
    raise UsageError("\n".join(lines))
