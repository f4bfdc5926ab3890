"""A run with events or input laws on the generated Python module (the Python backend).

`integrate_hybrid` is `lagcli.run.python_backend.integrate_module` with the inputs
given by laws u(t, y) and the events of lagcli/run/event_loop.py; the sink receives the
same columns, and its `events` (the `EventRecord`s) and `end_note` (why the run ended
early, if it did) tell what happened.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from lagcli.errors import SimulationError
from lagcli.interface import RESIDUAL, RunSettings
from lagcli.run.contact import contacts_of
from lagcli.run.python_backend import PythonModule
from lagcli.run.rows import RowSink
from lagcli.run.event_loop import run_events
from lagcli.runtime.run_rules import max_step, output_time_windows


def integrate_hybrid(module, p, y0, s, hybrid, u_constant, progress=None, sink=None):
    """Integrate `module` from t = 0 to s.t_end with `hybrid` (lagcli.targets.numeric.Hybrid);
    `u_constant`: the inputs held constant when `hybrid` has no laws (None without inputs)."""
    from lagcli.run.python_backend import SOLVERS
    from lagcli.run.rows import Trajectory

    n = len(module.COORDINATES)
    laws = hybrid.inputs

    def accelerations(t, y):
        u = () if u_constant is None and laws is None else ((laws(t, y) if laws else u_constant),)
        try:
            qdd, lam = module.accelerations(t, y, p, s.alpha, s.beta, *u)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            raise SimulationError(f"at t = {t:.10g}: {type(exc).__name__}: {exc}") from None
        return np.asarray(qdd, dtype=float), np.asarray(lam, dtype=float)

    def fun(t, y):
        return np.concatenate([y[n:], accelerations(t, y)[0]])

    def row(t, y):
        return module.output_row(t, y, accelerations(t, y)[1], p)

    contacts = contacts_of(hybrid, accelerations, s.alpha, s.beta)
    if contacts is not None:                 # `rest: true`: the contact forces are the last columns
        fun = contacts.rhs

        def row(t, y):
            lam, forces = contacts.multipliers(t, y)
            return module.output_row(t, y, lam, p) + forces

    def residual(t, y):
        return module.invariants(t, y, p)[RESIDUAL] if module.MULTIPLIERS else None

    sink = Trajectory() if sink is None else sink
    sink.begin(module.HEADER)
    times = itertools.chain.from_iterable(output_time_windows(s.t_end, s.dt))
    cap = max_step(s.method, s.alpha, s.beta, bool(module.MULTIPLIERS))
    with np.errstate(all="ignore"):
        try:
            _check_finite(0.0, np.asarray(y0, dtype=float))
            sink.end_note = run_events(SOLVERS[s.method], fun, row, y0, s, cap, hybrid, times,
                                       sink, progress, _check_finite, residual, contacts)
        except SimulationError as exc:
            sink.failure = str(exc)
        except KeyboardInterrupt:
            sink.interrupted = True
    return sink


def _check_finite(t: float, y) -> None:
    if not np.all(np.isfinite(y)):
        raise SimulationError(f"at t = {t:.10g}: the state is no longer finite (inf/nan): the solution blows up")


@dataclass(frozen=True)
class HybridModule(PythonModule):
    """The generated module with the numeric input laws and events of one run
    (`lagcli.targets.numeric.Hybrid`, made by the System): run by lagcli/run/hybrid_run.py."""

    hybrid: object = None

    def run(self, settings: RunSettings, values: dict[str, float], state, sink=None, progress=None,
            max_first_residual: float | None = None) -> RowSink:
        p, u = self.vectors(values)
        return integrate_hybrid(self.module, p, list(state), settings, self.hybrid, u, progress, sink)
