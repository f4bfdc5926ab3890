"""What happened during a run: one `EventRecord` per event, the `--events` CSV and the
stderr summary ("12 events: floor x12, first at t = 0.4515 s")."""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass


@dataclass(frozen=True)
class EventRecord:
    t: float
    name: str
    action: str                      # "impact" | "reset" | "stop"
    before: tuple[float, ...]        # the state y- (layout order)
    after: tuple[float, ...]         # the state y+
    impulse: float | None = None     # impact: P


def events_header(state_names) -> list[str]:
    """t, event, action, <state>- for each state, <state>+ for each state, impulse."""
    return (["t", "event", "action"] + [f"{s}-" for s in state_names] + [f"{s}+" for s in state_names]
            + ["impulse"])


def events_csv(records, state_names) -> str:
    """The `--events` file: one row per event; `impulse` is empty but for impacts."""
    lines = [",".join(events_header(state_names))]
    for r in records:
        values = [format(r.t, ".17g"), r.name, r.action, *(format(v, ".17g") for v in (*r.before, *r.after)),
                  "" if r.impulse is None else format(r.impulse, ".17g")]
        lines.append(",".join(values))
    return "".join(line + "\n" for line in lines)


def summary(records) -> str:
    """One line: how many events of each name, and when the first happened."""
    if not records:
        return "0 events"
    counts = Counter(r.name for r in records)
    names = sorted(counts, key=lambda name: next(i for i, r in enumerate(records) if r.name == name))
    each = ", ".join(f"{name} \u00d7{counts[name]}" for name in names)
    plural = "" if len(records) == 1 else "s"
    return f"{len(records)} event{plural}: {each}, first at t = {records[0].t:.10g} s"
