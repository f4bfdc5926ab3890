"""The input laws and events of a spec in its MATLAB/Octave files (`--lang octave`).

    <name>_inputs.m        u = <name>_inputs(t, y, p): the spec's laws (`simulate: inputs:`)
    <name>_events.m        [value, isterminal, direction] = <name>_events(t, y, p): ode45's 'Events'
    <name>_event_action.m  [y_new, impulse, speeds] = <name>_event_action(k, t, y, p, u)
    lagcli_event_loop.m    the event loop (lagcli/runtime/octave/, shipped as it is)

Each file exists only when the spec has laws or events, so every other spec's files are
unchanged. Expressions are printed by the Octave printer with the model's slots (y(i),
p(j)); the impact solves the augmented system of lagcli/runtime/event_loop_code.py with `\\`.
"""
from __future__ import annotations

from lagcli.interface import ACCUMULATION_GAP, EVENT_BUDGET, FIRST_STEP_SAMPLES, RESTING_SPEED
from lagcli.targets.event_code import DIRECTION_CODES
from lagcli.render.spec_printer import spec_str
from lagcli.targets.laws import printed_laws, state_printer

EVENT_FILES = ("events", "event_action")


def hybrid_context(d, printer_class) -> dict:
    """`laws` (per input: its law printed, or None) and `events` (their printed parts)."""
    model = d.model
    base = printer_class.index_base
    code = state_printer(d, printer_class)
    laws = printed_laws(d, printer_class)
    names = [s.name for s in (*model.q, *model.qd)]
    events = tuple(dict(name=e.name, action=e.action, direction=DIRECTION_CODES[e.direction], g=code(e.g),
                        when=spec_str(e.g),
                        G=[code(x) for x in e.G], g_t=code(e.g_t),
                        e=code(e.restitution) if e.restitution is not None else None,
                        reset=[(names.index(name) + base, code(v)) for name, v in e.reset])
                   for e in d.events)
    rules = dict(gap=ACCUMULATION_GAP, resting=RESTING_SPEED, budget=EVENT_BUDGET, samples=FIRST_STEP_SAMPLES)
    return dict(laws=laws, events=events, constraint_d=tuple(code(row.d) for row in d.constraints),
                event_rules={k: printer_class.literal(v) for k, v in rules.items()})
