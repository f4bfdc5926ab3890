"""The Python backend's run with events: the event loop of lagcli/runtime/event_loop_code.py
(the one the generated Python module carries) with what only lagcli adds to it, a
contact held after its accumulation (an impact event with `rest: true`,
lagcli/run/contact.py): that event then does not end the run; its contact is held from
there on as a constraint, without that event, and the run goes on to t_end with a note.
Its failures become `SimulationError`s.
"""
from __future__ import annotations

from lagcli.errors import SimulationError
from lagcli.interface import CONSTRAINT_TOLERANCE
from lagcli.run.contact import hold_contact, hold_note
from lagcli.runtime import event_loop_code
from lagcli.runtime.run_rules import max_step


def run_events(solver_class, fun, row, y0, s, cap, hybrid, times, sink, progress, check, residual):
    """Integrate from t = 0 to s.t_end with `hybrid`'s events (lagcli.targets.numeric.Hybrid),
    giving rows for the output `times` (an iterator, 0 first) to `sink`; the events go to
    `sink.events` as they happen. `check(t, y)` raises on a non-finite state;
    `residual(t, y)` is the constraint residual (None: unconstrained). Returns why the run
    ended early (or None)."""
    def hold(model, k, fun, t, y, why):
        if model.events[k].hold_bias is None:
            return None
        fun, others, y = hold_contact(model, k, fun, t, y, s.alpha, s.beta)
        return fun, others, y, hold_note(model.events[k].name, t, why), max_step(s.method, s.alpha, s.beta, True)

    try:
        return event_loop_code.run_events(solver_class, fun, row, y0, s, cap, hybrid, times, sink, progress,
                                          check, residual, CONSTRAINT_TOLERANCE, hold)
    except event_loop_code.EventRunFailure as exc:
        raise SimulationError(str(exc)) from None
