"""What `derive` and `check` say about input laws and events (only when a spec has them,
so every other report is unchanged): the laws, and per event its g, direction and
action; an impact's G = dg/dq row, g_t and restitution; a reset's new values."""
from __future__ import annotations

from lagcli.interface import contact_force_name


def hybrid_content(d, p) -> dict:
    """The report keys `input_laws` and `events` (absent when the spec has none); `p`
    prints one expression."""
    m = d.model
    content = {}
    if m.laws:
        content["input_laws"] = {law.symbol.name: p(law.expr) for law in m.laws}
    if d.events:
        content["events"] = [_event(e, p) for e in d.events]
    return content


def _event(e, p) -> dict:
    item = {"name": e.name, "action": e.action, "direction": e.direction, "when": p(e.g)}
    if e.action == "impact":
        item.update(G=[p(x) for x in e.G], g_t=p(e.g_t), restitution=p(e.restitution))
        if e.hold_bias is not None:
            item["rest"] = True
    if e.action == "reset":
        item["reset"] = {name: p(value) for name, value in e.reset}
    return item


def check_lines(d) -> list[str]:
    """`lagcli check`: one line per law and per event."""
    from lagcli.render.spec_printer import spec_str

    lines = [f"input law   : {law.symbol.name} = {spec_str(law.expr)}" for law in d.model.laws]
    for e in d.events:
        line = f"event       : {e.name}: {e.action} where {spec_str(e.g)} crosses 0 ({e.direction})"
        if e.action == "impact":
            line += f"; G = [{', '.join(spec_str(x) for x in e.G)}], e = {spec_str(e.restitution)}"
            if e.hold_bias is not None:
                line += f"; held while it pushes (rest: true), force column {contact_force_name(e.name)}"
        if e.action == "reset":
            line += "; " + ", ".join(f"{name} <- {spec_str(v)}" for name, v in e.reset)
        lines.append(line)
    return lines
