"""What happened during a run, for lagcli's commands: the stderr summary ("12 events:
floor x12, first at t = 0.4515 s") and the C driver's event log read back
(`read_event_log`, lagcli/runtime/c/lagcli_events.h), so both backends give the same
`EventRecord`s, `--events` CSV and end notes.

The records, the CSV and the notes themselves are lagcli/runtime/run_limits.py's (the
generated Python module carries that code too), and so are the rules that end a run
early (ACCUMULATION_GAP, RESTING_SPEED, EVENT_BUDGET, FIRST_STEP_SAMPLES; the C side's in
lagcli_events.h, checked equal by tests/test_c_events.py)."""
from __future__ import annotations

from collections import Counter

from lagcli.runtime.run_limits import (RELEASE, REST, EventRecord, end_note, events_csv,  # noqa: F401
                                       events_header)                                     # (the records' home)


def summary(records) -> str:
    """One line: how many events of each name (a held contact's rests and releases apart:
    "floor rest"), and when the first happened."""
    if not records:
        return "0 events"
    keys = [r.name if r.action not in (REST, RELEASE) else f"{r.name} {r.action}" for r in records]
    counts = Counter(keys)
    names = sorted(counts, key=keys.index)
    each = ", ".join(f"{name} \u00d7{counts[name]}" for name in names)
    plural = "" if len(records) == 1 else "s"
    return f"{len(records)} event{plural}: {each}, first at t = {records[0].t:.10g} s"


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
