"""The spec's events in the generated Python module (`lagcli generate --lang python`).

A spec with `events:` gets, in its one module (templates/python/events.py.jinja):

    EVENTS                          [{"name", "action", "direction"}, ...] in spec order
    event_functions(t, y, p)        [g_1, ...]: an event happens where its g crosses zero
    impact_terms(k, t, y, p)        (G = dg/dq, g_t, e) of impact event k (0-based)
    reset(k, t, y, p)               the state after reset event k, from the state before
    event_model(p)                  the events with p bound, as `run_events` takes them
    simulate(..., max_steps=None)   -> (header, rows, events, note)

and the code of lagcli/runtime/run_limits.py and lagcli/runtime/event_loop_code.py,
pasted verbatim: the event loop lagcli's own Python backend runs, so the module stays
one self-contained file (numpy, and scipy inside `simulate`). The expressions are the
derivation's (`event_code.printed_events`, shared with the C model), printed by the
Python printer with the module's state and parameter slots.
"""
from __future__ import annotations

from lagcli.runtime import python_event_loop, python_run_limits
from lagcli.targets.event_code import printed_events


def events_context(d, code) -> dict:
    """What the module template needs of `d`'s events, printed by `code` (the Python
    target's `laws.state_printer`); `events` is () for a spec without events."""
    if not d.events:
        return dict(events=())
    return dict(events=printed_events(d, code), constraint_d=tuple(code(row.d) for row in d.constraints),
                run_limits=python_run_limits(),          # lagcli's budgets, records and notes, verbatim
                event_loop=python_event_loop())          # and its event loop
