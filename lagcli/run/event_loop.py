"""The Python backend's run with events: the event loop of lagcli/runtime/event_loop_code.py
(the one the generated Python module carries), with what only lagcli adds to it: the
contacts of impact events with `rest: true` (lagcli/run/contact.py), held as a constraint
where their impacts accumulate (or where the run starts resting on them) while they push,
released where they would pull; and its failures as `SimulationError`s.
"""
from __future__ import annotations

from lagcli.errors import SimulationError
from lagcli.interface import CONSTRAINT_TOLERANCE
from lagcli.runtime import event_loop_code


def run_events(solver_class, fun, row, y0, s, cap, hybrid, times, sink, progress, check, residual,
               contacts=None):
    """Integrate from t = 0 to s.t_end with `hybrid`'s events (lagcli.targets.numeric.Hybrid),
    giving rows for the output `times` (an iterator, 0 first) to `sink`; the events go to
    `sink.events` as they happen. `check(t, y)` raises on a non-finite state;
    `residual(t, y)` is the constraint residual (None: unconstrained); `contacts`: the
    `rest: true` events (lagcli.run.contact.Contacts; then `fun` is its `rhs`). Returns why
    the run ended early (or None)."""
    try:
        return event_loop_code.run_events(solver_class, fun, row, y0, s, cap, hybrid, times, sink, progress,
                                          check, residual, CONSTRAINT_TOLERANCE, contacts)
    except event_loop_code.EventRunFailure as exc:
        raise SimulationError(str(exc)) from None
