"""How a run ends before t_end, and what a run with events records, in Python, written
once: the interface, the run layer and the code targets import it; the generated Python
module of a spec with events carries this file's code verbatim after its run rules
(`lagcli.runtime.python_run_limits`). Standard library only, no `from __future__` (the
text is pasted into another module), no numpy: the warm C path reads the driver's event
log with it (lagcli/run/records.py).

    STEP_BUDGET_*, default_max_steps   the integrator steps a run may take (`--max-steps`)
    ACCUMULATION_GAP, RESTING_SPEED,   when accumulating events end a run
    EVENT_BUDGET, FIRST_STEP_SAMPLES   (docs/simulate.md, "Events and input laws")
    EventRecord                        one event: t, name, action, the state before and after,
                                       the impulse of an impact (REST, RELEASE: a held contact)
    end_note                           the note saying why a run with events ended early
    events_csv                         the `--events` file: one row per event

The C runtime states the same numbers in lagcli/runtime/c/lagcli_events.h and
lagcli_driver.c (checked equal by tests/test_c_events.py, tests/test_step_budget.py).
"""
# --- lagcli's run limits and event records (lagcli/runtime/run_limits.py) ---
import math
from dataclasses import dataclass

STEP_BUDGET_BASE = 20_000         # a run takes at most this many integrator steps, plus
STEP_BUDGET_PER_OUTPUT = 1_000    # this many per output interval, unless --max-steps says otherwise
STEP_BUDGET_TEXT = ("the integration reached its bound of {steps} steps before t_end (a stiff or "
                    "blowing-up solution?); raise the bound with --max-steps N")
ACCUMULATION_GAP = 1e-9           # the same event again within this x max(1, |t|)
RESTING_SPEED = 1e-9              # separation speed below this x the largest approach speed
EVENT_BUDGET = 100_000            # events of one run
FIRST_STEP_SAMPLES = 8            # samples of the first step after an impact (its gap starts at 0)
REST, RELEASE = "rest", "release"  # the actions of the records of a contact held and let go (lagcli's rest: true)


def default_max_steps(t_end, dt):
    """The step budget of a run (`--max-steps` default): deterministic, from the output grid
    (the C driver's `step_budget` is the same rule)."""
    return STEP_BUDGET_BASE + STEP_BUDGET_PER_OUTPUT * math.ceil(t_end / dt - 1e-9)


@dataclass(frozen=True)
class EventRecord:
    """One event of a run: the state y- just before it and y+ just after (in STATE order)."""

    t: float
    name: str
    action: str                      # "impact" | "reset" | "stop"; REST | RELEASE (a held contact)
    before: tuple                    # the state y-
    after: tuple                     # the state y+
    impulse: float = None            # impact: P; None for a reset or a stop


def end_note(kind, name, t, value):
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


def events_header(state_names):
    """t, event, action, <state>- for each state, <state>+ for each state, impulse."""
    return (["t", "event", "action"] + [f"{s}-" for s in state_names] + [f"{s}+" for s in state_names]
            + ["impulse"])


def events_csv(records, state_names):
    """The `--events` file's text: one row per event (`%.17g`); `impulse` is empty but for impacts."""
    lines = [",".join(events_header(state_names))]
    for r in records:
        values = [format(r.t, ".17g"), r.name, r.action, *(format(v, ".17g") for v in (*r.before, *r.after)),
                  "" if r.impulse is None else format(r.impulse, ".17g")]
        lines.append(",".join(values))
    return "".join(line + "\n" for line in lines)
