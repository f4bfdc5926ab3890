"""The spec's events as C code: one source for the generated C model and its FMU.

`<name>.c` of `lagcli generate --lang c` (templates/c/model_events.c.jinja, included by
model.c.jinja) carries, for a spec with `events:`, the event functions g_k(t, y, p),
for an impact G = dg/dq, g_t and the restitution e, the reset maps, and the tables of
names, actions and directions: the `lagcli_events` table of lagcli_model.h that the C
driver runs (lagcli/runtime/c/lagcli_events.c) and the FMU's event indicators and
`fmi2NewDiscreteStates` use (templates/fmu/lagcli_fmu_model.h.jinja names them).
Expressions are printed by the C target's printer with the model table's slots:
y = [q..., q'...], p = the parameters then the inputs (the table's order).

`printed_events` is the part every target shares: each event's expressions printed by the
target's own printer (the C model here; the generated Python module's event functions,
lagcli/targets/python_events.py).
"""
from __future__ import annotations

ACTION_CODES = {"impact": 0, "reset": 1, "stop": 2}           # lagcli_model.h: LAGCLI_EVENT_*
DIRECTION_CODES = {"falling": -1, "rising": 1, "either": 0}


def event_context(d, printer_class) -> dict:
    """`events`: one dict per event (name, action, direction, g, and for an impact G,
    g_t, e; for a reset the (slot, code) of each new value), `bias`: the constraint rows'
    d (A q' + d = 0), printed by `printer_class` (the C target's, which calls this);
    {"events": ()} for a spec without events."""
    if not d.events:
        return dict(events=(), bias=())
    from lagcli.targets.slots import check_slots

    model = d.model
    table = {model.t: "t"}
    table.update({s: f"y[{k}]" for k, s in enumerate((*model.q, *model.qd))})
    table.update({s: f"p[{k}]" for k, s in enumerate((*model.parameter_symbols, *model.input_symbols))})
    printer = printer_class(table)

    def code(expr) -> str:
        check_slots([expr], table)
        return printer.code(expr)

    events = tuple(dict(e, action=ACTION_CODES[e["action"]], direction=DIRECTION_CODES[e["direction"]])
                   for e in printed_events(d, code))
    return dict(events=events, bias=tuple(code(row.d) for row in d.constraints))


def printed_events(d, code) -> tuple[dict, ...]:
    """One dict per event of `d`, its expressions printed by `code` (a target's printer
    with the state and parameter slots): index, name, action and direction (the spec's
    words), g, and for an impact G (per coordinate), g_t, e (the restitution); for a reset
    the (0-based state index, code) of each new value."""
    model = d.model
    names = [s.name for s in (*model.q, *model.qd)]
    return tuple(dict(index=k, name=e.name, action=e.action, direction=e.direction, g=code(e.g),
                      G=[code(x) for x in e.G] if e.action == "impact" else [],
                      g_t=code(e.g_t) if e.action == "impact" else "0.0",
                      e=code(e.restitution) if e.action == "impact" else "0.0",
                      reset=[(names.index(name), code(v)) for name, v in e.reset])
                 for k, e in enumerate(d.events))
