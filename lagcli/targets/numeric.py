"""Laws, event functions and event actions as numpy functions of (t, y), for one run.

Everything is made with `sympy.lambdify` from the sympy objects of the derivation
(built by lagcli's safe parser, never from spec text), with the run's parameter
values bound: y = [q..., q'...] as everywhere.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from lagcli.derive.result import Derivation
from lagcli.errors import UsageError


@dataclass(frozen=True)
class NumericEvent:
    name: str
    action: str
    direction: str
    g: Callable                  # g(t, y) -> float
    G: Callable | None           # impact: (t, y) -> (n,) row dg/dq
    g_t: Callable | None         # impact: (t, y) -> dg/dt
    restitution: float | None
    reset: Callable | None       # reset: (t, y) -> new y
    hold_bias: Callable | None = None   # rest: (t, y) -> the held contact's G q'' (lagcli/derive/event_functions.py)


@dataclass(frozen=True)
class Hybrid:
    """One run's numeric laws and events. `inputs(t, y)` -> u in the layout's input order
    (None for a spec without inputs); `described`: the laws in words, for notes."""

    events: tuple[NumericEvent, ...]
    inputs: Callable | None
    mass_matrix: Callable        # (t, y) -> (n, n)
    constraint_rows: Callable    # (t, y) -> (A (m, n), d (m,))
    has_callable: bool = False

    @property
    def active(self) -> bool:
        return bool(self.events) or self.inputs is not None


def hybrid_run(d: Derivation, parameters: dict[str, float], inputs: dict) -> Hybrid:
    """The numeric laws and events of `d` with `parameters` (every parameter's value) and
    `inputs` (input name -> a number, a sympy law, or a Python callable u(t, y))."""
    model = d.model
    args = (model.t, *model.q, *model.qd)
    values = {s: parameters[s.name] for s in model.parameter_symbols}

    def function(expr) -> Callable:
        f = sp.lambdify(args, sp.sympify(expr).subs(values), modules="numpy", cse=True)
        return lambda t, y: f(t, *y)

    events = tuple(_numeric_event(e, function, model, values) for e in d.events)
    n, m = len(model.q), len(d.constraints)
    M_f = sp.lambdify(args, sp.ImmutableMatrix(d.mass_matrix).subs(values), modules="numpy", cse=True)
    rows = _constraint_rows(d, args, values, n, m)
    return Hybrid(events, _inputs(model, inputs, function),
                  lambda t, y: np.array(M_f(t, *y), dtype=float).reshape(n, n), rows,
                  any(callable(v) and not isinstance(v, sp.Basic) for v in inputs.values()))


def _constraint_rows(d: Derivation, args, values, n: int, m: int) -> Callable:
    """(t, y) -> (A, d): the constraint rows A q' + d = 0 (empty without constraints)."""
    if not m:
        return lambda t, y: (np.zeros((0, n)), np.zeros(0))
    A = sp.lambdify(args, sp.ImmutableMatrix(d.constraint_matrix).subs(values), modules="numpy", cse=True)
    bias = sp.lambdify(args, sp.ImmutableMatrix([row.d for row in d.constraints]).subs(values),
                       modules="numpy", cse=True)
    return lambda t, y: (np.array(A(t, *y), dtype=float).reshape(m, n),
                         np.array(bias(t, *y), dtype=float).reshape(m))


def _numeric_event(e, function, model, values) -> NumericEvent:
    G = g_t = restitution = reset = None
    if e.action == "impact":
        row = [function(x) for x in e.G]
        G = lambda t, y: np.array([f(t, y) for f in row], dtype=float)   # noqa: E731
        g_t = function(e.g_t)
        restitution = float(sp.sympify(e.restitution).subs(values))
        if not 0.0 <= restitution <= 1.0:
            raise UsageError(f"event '{e.name}': restitution = {restitution:g} with these parameter values; "
                             "it must be in [0, 1]")
    if e.action == "reset":
        names = [s.name for s in (*model.q, *model.qd)]
        slots = [(names.index(name), function(expr)) for name, expr in e.reset]

        def reset(t, y, slots=slots):
            new = np.array(y, dtype=float)
            for k, f in slots:                      # every value from the state before
                new[k] = f(t, y)
            return new
    hold = function(e.hold_bias) if e.hold_bias is not None else None
    return NumericEvent(e.name, e.action, e.direction, function(e.g), G, g_t, restitution, reset, hold)


def _inputs(model, inputs: dict, function) -> Callable | None:
    """u(t, y) in the model's input order, or None when every input is a constant."""
    symbols = model.input_symbols
    if not symbols or all(isinstance(inputs.get(s.name), (int, float)) for s in symbols):
        return None
    parts = []
    for s in symbols:
        value = inputs[s.name]
        if isinstance(value, (int, float)):
            parts.append(lambda t, y, v=float(value): v)
        elif isinstance(value, sp.Basic):
            parts.append(function(value))
        else:
            parts.append(_checked_callable(s.name, value))
    return lambda t, y: [float(f(t, y)) for f in parts]


def _checked_callable(name: str, f: Callable) -> Callable:
    def call(t, y):
        value = f(t, np.asarray(y))
        try:
            return float(value)
        except (TypeError, ValueError):
            raise UsageError(f"inputs={{{name!r}: ...}}: the callable returned {value!r}, "
                             "not a number") from None
    return call


def input_number(name: str, value) -> float:
    """A constant of `System.simulate(inputs=...)`; anything else is a clear error."""
    try:
        return float(value)
    except (TypeError, ValueError):
        raise UsageError(f"inputs={{{name!r}: ...}}: {value!r} is not a number, an expression string "
                         "or a callable u(t, y)") from None


def law_callable(name: str, f):
    """A law given as a Python callable, checked to take (t, y) before the run starts."""
    import inspect

    try:
        inspect.signature(f).bind(0.0, ())
    except TypeError as problem:
        raise UsageError(f"inputs={{{name!r}: ...}}: the callable must take (t, y), the time and the "
                         f"state [q..., q_dot...]: {problem}") from None
    except ValueError:          # no signature to read (some builtins): called as it is
        pass
    return f

