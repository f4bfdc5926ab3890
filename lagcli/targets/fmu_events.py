"""The events of a spec inside its FMU: `sources/lagcli_fmu_events.c` (Model Exchange).

The event functions g_k are the FMU's event indicators (`numberOfEventIndicators`);
lagcli/runtime/fmi2/lagcli_fmi2.c keeps each indicator's last value, and where one has
crossed zero in its event's direction it does the action in `fmi2NewDiscreteStates`:
an impact solves the impact law of lagcli/run/impact.py in C (the same augmented
system), a reset sets the new state, a stop ends the simulation. Expressions are
printed by the C target's printer with the model's array slots (y[i], p[j]).
"""
from __future__ import annotations

from lagcli.render.templates import render

EVENTS_SOURCE = "lagcli_fmu_events.c"
ACTION_CODES = {"impact": 0, "reset": 1, "stop": 2}
DIRECTION_CODES = {"falling": -1, "rising": 1, "either": 0}


def fmu_event_sources(d, c_context: dict) -> dict[str, str]:
    """{file: text} of the events source ({} for a spec without events)."""
    if not d.events:
        return {}
    return {EVENTS_SOURCE: render(f"fmu/{EVENTS_SOURCE}.jinja", **event_context(d, c_context))}


def event_context(d, c_context: dict) -> dict:
    from lagcli.targets.c import CPrinter
    from lagcli.targets.slots import check_slots

    model = d.model
    table = {model.t: "t"}
    table.update({s: f"y[{k}]" for k, s in enumerate((*model.q, *model.qd))})
    table.update({s: f"p[{k}]" for k, s in enumerate(model.parameter_symbols)})
    printer = CPrinter(table)

    def code(expr) -> str:
        check_slots([expr], table)
        return printer.code(expr)

    names = [s.name for s in (*model.q, *model.qd)]
    events = d.events
    return dict(
        i=c_context["i"], m=c_context["m"], nstate=len(names), names=[e.name for e in events],
        g=[code(e.g) for e in events],
        actions=[ACTION_CODES[e.action] for e in events],
        directions=[DIRECTION_CODES[e.direction] for e in events],
        impacts=[dict(index=k, G=[code(x) for x in e.G], g_t=code(e.g_t), e=code(e.restitution))
                 for k, e in enumerate(events) if e.action == "impact"],
        resets=[dict(index=k, values=[(names.index(name), code(v)) for name, v in e.reset])
                for k, e in enumerate(events) if e.action == "reset"],
        d=[code(row.d) for row in d.constraints],
    )
