"""The point an analysis is about: a number for every coordinate, velocity, parameter and t.

`--at NAME=VALUE` gives coordinates, velocities (`q_dot`), parameters, inputs and `t`; a
value is a constant expression that may use the parameters and a sweep variable
(`--at phi_R_dot=-v/rR --sweep v=0:10:101`). It is parsed by lagcli's safe
expression parser (never evaluated as Python). Whatever is not given is 0
(parameters and inputs: their spec value).

On a constrained system the point must lie on the constraint manifold. The
dependent coordinates are solved for by Newton's method on the holonomic rows
phi(q, t) = 0, the dependent velocities from A q' + d = 0, given the independent
ones (`Partition`): so `--at` need only give the independent values. Newton starts,
and the partition is chosen, where the coordinates `--at` does not give take the
spec's consistent initial state (`Assignments.start`), not 0: at all zeros a
Cartesian pendulum's rod row has no gradient, and the initial state picks the branch
(hanging, not standing). A point that cannot be solved is named in the error.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from lagcli.errors import Loc, UsageError

_NEWTON_TOL = 1e-14      # relative residual of phi at which Newton stops
_NEWTON_STEPS = 50


@dataclass(frozen=True)
class Assignments:
    """`--at` values as sympy expressions of the parameters and the sweep variable."""

    values: dict            # name -> sympy expression
    sweep: sp.Symbol | None # the sweep variable's symbol (a parameter's own symbol, or a new one)
    start: dict = field(default_factory=dict)   # coordinate -> where its solve starts when not given

    def given(self, numbers: dict) -> "Assignments":
        """These values with `numbers` {name: float} (names already checked) taking precedence."""
        return replace(self, values={**self.values, **{k: sp.Float(float(v)) for k, v in numbers.items()}})

    def starting_at(self, start: dict) -> "Assignments":
        """These values, the coordinates they do not give solved for from `start` {name: float}."""
        return replace(self, start=dict(start))


def parse_assignments(d, items, sweep_name: str | None = None) -> Assignments:
    """`("theta=0", "phi_dot=Omega")` -> Assignments; names checked against the model."""
    from lagcli.run.options import parse_assignments as assignments

    scope, sweep = _scope(d, sweep_name)
    values = assignments(tuple(items), "--at", _names(d), "name", "coordinates, velocities, parameters and inputs",
                         parse=lambda text, where: _parse(text, scope, where))
    return Assignments(values, sweep)


def assignments_of(d, given: dict, sweep_name: str | None = None, argument: str = "at=") -> Assignments:
    """The Python API's `{name: number or expression text}` -> Assignments (as `parse_assignments`)."""
    from lagcli.run.options import _hint

    scope, sweep = _scope(d, sweep_name)
    allowed = _names(d)
    values = {}
    for name, value in given.items():
        if name not in allowed:
            raise UsageError(f"{argument}: unknown name {name!r}"
                             + _hint(name, allowed, "coordinates, velocities, parameters and inputs"))
        values[name] = (_parse(value, scope, f"{argument} {name}") if isinstance(value, str)
                        else sp.Float(float(value)))
    return Assignments(values, sweep)


def _names(d) -> list[str]:
    model = d.model
    return [s.name for s in (*model.q, *model.qd, *model.parameter_symbols, *model.input_symbols)] + ["t"]


def _scope(d, sweep_name: str | None) -> tuple[dict, sp.Symbol | None]:
    """The names an `--at` value may use, and the sweep variable's symbol (a parameter's own, or a new one)."""
    scope = {"pi": sp.pi, **{p.name: p for p in d.model.parameter_symbols}}
    sweep = None
    if sweep_name is not None:
        sweep = scope.get(sweep_name) or sp.Symbol(sweep_name, real=True)
        scope[sweep_name] = sweep
    return scope, sweep


def _parse(text: str, names: dict, where: str) -> sp.Expr:
    from lagcli.errors import LagcliError
    from lagcli.model.expr import Scope, parse

    try:
        return parse(text.strip(), Scope(names, sp.Symbol("t")), Loc("<command line>"))
    except LagcliError as exc:
        reason = str(exc).splitlines()[0].removeprefix("<command line>: ")
        raise UsageError(f"{where}: {text!r} is not a constant expression ({reason})\n"
                         "  hint: VALUE may use numbers, pi, the parameters and the sweep variable") from None


@dataclass(frozen=True)
class Point:
    """Numbers for the whole state and every parameter (by name)."""

    t: float
    q: np.ndarray
    qd: np.ndarray
    parameters: dict        # name -> float, for every parameter and input
    notes: tuple[str, ...] = ()
    guess: np.ndarray | None = None   # coordinates to start the constraint solve from (None: q)

    @property
    def start(self) -> np.ndarray:
        """The coordinates the constraint solve starts from."""
        return self.q if self.guess is None else self.guess


def evaluate(d, at: Assignments, sweep_value: float | None = None) -> Point:
    """The numbers of `at` (with the sweep variable at `sweep_value`), before any constraint solve."""
    model = d.model
    constants = (*model.parameters, *model.inputs)       # an input is held at its value
    params = {p.symbol.name: float(p.value) for p in constants}
    known = {p.symbol: p.value for p in constants}
    if at.sweep is not None:
        if sweep_value is None:
            raise UsageError("a sweep variable needs a value")
        known[at.sweep] = sweep_value
        if at.sweep.name in params:
            params[at.sweep.name] = float(sweep_value)
    # parameters given by --at first: other values may use them
    for name, expr in at.values.items():
        if name in params:
            params[name] = _number(expr, known, f"--at {name}")
    known.update({p.symbol: params[p.symbol.name] for p in constants})
    if at.sweep is not None:
        known[at.sweep] = sweep_value
    number = {name: _number(expr, known, f"--at {name}") for name, expr in at.values.items()}
    q = np.array([number.get(s.name, 0.0) for s in model.q])
    qd = np.array([number.get(s.name, 0.0) for s in model.qd])
    guess = np.array([number.get(s.name, at.start.get(s.name, 0.0)) for s in model.q]) if at.start else None
    return Point(number.get("t", 0.0), q, qd, params, guess=guess)


def describe(d, point: Point, q=None) -> str:
    """`x = 0, y = -0.8, x_dot = 0, ...`: the point's state (`q` in place of its coordinates)."""
    model = d.model
    q = point.q if q is None else q
    return ", ".join(f"{s.name} = {v:.10g}" for s, v in zip([*model.q, *model.qd], [*q, *point.qd]))


def _number(expr: sp.Expr, known: dict, where: str) -> float:
    value = sp.sympify(expr).xreplace({s: sp.Float(v, 30) for s, v in known.items()})
    if value.free_symbols:
        raise UsageError(f"{where}: uses {', '.join(sorted(map(str, value.free_symbols)))}, "
                         "which has no value here")
    number = complex(value.evalf(30))
    if number.imag != 0 or not np.isfinite(number.real):
        raise UsageError(f"{where}: not a finite real number")
    return float(number.real)


@dataclass(frozen=True)
class Partition:
    """Which coordinates and speeds are independent (indices into q, in model order)."""

    coordinates: tuple[int, ...]        # independent coordinates
    speeds: tuple[int, ...]             # independent speeds (q'_k for k in speeds)
    dependent_coordinates: tuple[int, ...]
    dependent_speeds: tuple[int, ...]


def choose_partition(d, constraints, point: Point, independent=()) -> Partition:
    """The user's `--independent` names, completed by column-pivoted QR of the constraint
    Jacobians at the point (the best-conditioned dependent set) where they give none."""
    model = d.model
    n = len(model.q)
    holonomic_jacobian = constraints.holonomic_jacobian(point)
    A = constraints.A(point)
    names_q = [s.name for s in model.q]
    names_qd = [s.name for s in model.qd]
    for name in independent:
        if name not in names_q + names_qd:
            from lagcli.run.options import _hint
            raise UsageError(f"--independent {name!r}: not a coordinate or velocity"
                             + _hint(name, names_q + names_qd, "coordinates and velocities"))
    given_q = [names_q.index(x) for x in independent if x in names_q]
    given_u = [names_qd.index(x) for x in independent if x in names_qd]
    coordinates = _independent(holonomic_jacobian, n, given_q, "coordinates", names_q)
    speeds = _independent(A, n, given_u, "speeds", names_qd)
    return Partition(tuple(coordinates), tuple(speeds),
                     tuple(k for k in range(n) if k not in coordinates),
                     tuple(k for k in range(n) if k not in speeds))


def _independent(jacobian: np.ndarray, n: int, given: list[int], what: str, names) -> list[int]:
    rows = jacobian.shape[0]
    if not given:
        if rows == 0:
            return list(range(n))
        from scipy.linalg import qr
        _, _, pivots = qr(jacobian, pivoting=True, mode="economic")
        dependent = set(int(k) for k in pivots[:rows])
        return [k for k in range(n) if k not in dependent]
    if len(given) != n - rows:
        raise UsageError(f"--independent: {len(given)} {what} given ({', '.join(names[k] for k in given)}), "
                         f"but the constraints leave {n - rows} independent {what}")
    dependent = [k for k in range(n) if k not in given]
    block = jacobian[:, dependent]
    if rows and np.linalg.matrix_rank(block) < rows:
        raise UsageError(f"--independent: the constraints cannot be solved for the dependent {what} "
                         f"{', '.join(names[k] for k in dependent)} at this point\n"
                         "  hint: choose other independent ones")
    return sorted(given)


def on_manifold(constraints, point: Point, partition: Partition, names) -> Point:
    """`point` with dependent coordinates and speeds solved for (independent ones kept)."""
    if constraints.m == 0:
        return point
    q, notes = point.q.copy(), list(point.notes)
    dep = list(partition.dependent_coordinates)
    if dep:
        q[dep] = point.start[dep]
        q = _newton(constraints, point, q, dep, names)
    moved = point.__class__(point.t, q, point.qd, point.parameters)
    A, bias = constraints.A(moved), constraints.bias(moved)
    ind, dsp = list(partition.speeds), list(partition.dependent_speeds)
    qd = point.qd.copy()
    if dsp:
        qd[dsp] = np.linalg.solve(A[:, dsp], -(A[:, ind] @ qd[ind] + bias))
    for k in range(len(q)):
        if abs(q[k] - point.q[k]) > 1e-12 * (1 + abs(q[k])):
            notes.append(f"solved for {names[0][k]} = {q[k]:.15g}")
        if abs(qd[k] - point.qd[k]) > 1e-12 * (1 + abs(qd[k])):
            notes.append(f"solved for {names[1][k]} = {qd[k]:.15g}")
    return point.__class__(point.t, q, qd, point.parameters, tuple(notes))


def _newton(constraints, point: Point, q: np.ndarray, dep: list[int], names) -> np.ndarray:
    start = q.copy()
    for _ in range(_NEWTON_STEPS):
        here = point.__class__(point.t, q, point.qd, point.parameters)
        phi = constraints.phi(here)
        if np.max(np.abs(phi), initial=0.0) <= _NEWTON_TOL * (1 + np.max(np.abs(q))):
            return q
        step = np.linalg.lstsq(constraints.holonomic_jacobian(here)[:, dep], phi, rcond=None)[0]
        q = q.copy()
        q[dep] -= step
    tried = ", ".join(f"{name} = {v:.10g}" for name, v in zip(names[0], start))
    raise UsageError("the holonomic constraints could not be solved for the dependent coordinates "
                     f"{', '.join(names[0][k] for k in dep)}, starting from {tried}\n"
                     "  hint: give a point closer to the constraint manifold (--at NAME=VALUE), "
                     "or other --independent ones")
