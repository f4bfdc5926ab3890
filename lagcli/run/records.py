"""What happened during a run: one `EventRecord` per event, the `--events` CSV, the
stderr summary ("12 events: floor x12, first at t = 0.4515 s") and the note saying why a
run ended early: for both backends (lagcli/run/event_loop.py; the C driver's log,
lagcli/runtime/c/lagcli_events.h, read by `read_event_log`).

The rules that end a run early are the same on both backends (lagcli/interface.py's
ACCUMULATION_GAP, RESTING_SPEED, EVENT_BUDGET, FIRST_STEP_SAMPLES; the C side's in
lagcli_events.h, checked equal by tests/test_c_events.py)."""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

from lagcli.interface import ACCUMULATION_GAP, EVENT_BUDGET, RESTING_SPEED


@dataclass(frozen=True)
class EventRecord:
    t: float
    name: str
    action: str                      # "impact" | "reset" | "stop"; "rest" | "release" (a held contact)
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
    """One line: how many events of each name (a held contact's rests and releases apart:
    "floor rest"), and when the first happened."""
    if not records:
        return "0 events"
    keys = [r.name if r.action not in ("rest", "release") else f"{r.name} {r.action}" for r in records]
    counts = Counter(keys)
    names = sorted(counts, key=keys.index)
    each = ", ".join(f"{name} \u00d7{counts[name]}" for name in names)
    plural = "" if len(records) == 1 else "s"
    return f"{len(records)} event{plural}: {each}, first at t = {records[0].t:.10g} s"


def end_note(kind: str, name: str, t: float, value: float) -> str:
    """Why a run ended at event `name` at time t: `kind` "recurred" (value: the gap since its
    last time), "resting" (the separation speed after the impact), "unresolved" (it returns
    within the first step after it) or "budget" (EVENT_BUDGET events)."""
    if kind == "recurred":
        return (f"event '{name}' recurred after {value:.3g} s at t = {t:.10g} "
                f"(accumulation: closer than {ACCUMULATION_GAP:g} x max(1, t)); the run ends there")
    if kind == "resting":
        return (f"event '{name}' at t = {t:.10g}: separation speed {value:.3g} after the impact "
                f"(below {RESTING_SPEED:g} x the largest approach speed: the contact has come to rest); "
                "the run ends there")
    if kind == "unresolved":
        return (f"event '{name}' recurs at t = {t:.10g} faster than the integrator's step can "
                "resolve (accumulation); the run ends there")
    return f"{EVENT_BUDGET} events (the budget of one run) by t = {t:.10g}; the run ends there"


def read_event_log(text: str, nstate: int) -> tuple[list[EventRecord], str | None]:
    """The records and the end note of the C driver's `--events` log (lagcli_events.h); a
    last line cut off (the driver killed while writing it) is left out."""
    records, note = [], None
    for line in text[:text.rfind("\n") + 1].splitlines():
        fields = line.split(",")
        if fields[0] == "event":
            values = [float(v) for v in fields[3:3 + 2 * nstate + 1]]
            impulse = fields[4 + 2 * nstate]
            records.append(EventRecord(values[0], fields[1], fields[2], tuple(values[1:1 + nstate]),
                                       tuple(values[1 + nstate:]), float(impulse) if impulse else None))
        elif fields[0] == "end":
            note = end_note(fields[1], fields[2], float(fields[3]), float(fields[4]))
    return records, note
