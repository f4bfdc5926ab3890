"""lagcli's event loop in Python, written once: lagcli's Python backend runs it
(lagcli/run/event_loop.py) and the generated Python module of a spec with events carries
this file's code verbatim after the run limits (`lagcli.runtime.python_event_loop`).
Numpy and the standard library only (scipy imported when a run starts, as the generated
module's `simulate` does), no `from __future__`, no lagcli: the generated module stays
self-contained. The C runtime states the same loop in lagcli/runtime/c/lagcli_events.c.

Each step of the solver (DOP853 by default) is checked for a sign change of every
event function g between the step's ends, in the event's direction; the earliest
root is found with `scipy.optimize.brentq` on the step's dense output (the same
interpolant scipy's own `solve_ivp(events=...)` searches), so event times are as
accurate as the integrator. Output rows before the event come from that dense
output; then the action happens and a new solver starts from (t*, y+): a grid row
never mixes the motion before and after an event (a row at exactly t* shows y+).

    impact  y+ from `impact` (positions kept), impulse P recorded
    reset   the listed states from the state before; checked against the constraints
    stop    the run ends at t*, its last row the state there

A run never loops forever on accumulating events (a ball with e < 1 bounces
infinitely often before a finite time). It ends, with a note, at the event where

    - the same event recurs within ACCUMULATION_GAP * max(1, |t|) of its last time, or
    - an impact leaves with a separation speed below RESTING_SPEED times the largest
      approach speed of that event so far (the contact has come to rest), or
    - EVENT_BUDGET events have happened;

the last row is the state after that event, at its time (the numbers and notes:
lagcli/runtime/run_limits.py). Right after an event, the event just handled is watched
on FIRST_STEP_SAMPLES samples of the first step's dense output (its g starts at zero): a
return to zero within that step is found too, and one that cannot be resolved there
counts as an accumulation. lagcli's Python backend may hold an accumulating contact
instead of ending the run (`contacts`: `rest: true`, lagcli/run/contact.py): held while it
pushes, released (a RELEASE event of the contacts' own, its function the normal force,
watched on FIRST_STEP_SAMPLES samples of every step) where it would pull.

The impact law, solved numerically like the augmented system (never a symbolic
inverse): at an impact of gap g(t, q) with G = dg/dq, restitution e and the constraint
rows A q' + d = 0, the velocities jump from q'- to q'+ with the impulse P (and Lambda
for the constraints):

    [ M  -G^T  -A^T ] [ q'+    ]   [ M q'-                  ]
    [ G   0     0   ] [ P      ] = [ -e (G q'- + g_t) - g_t ]
    [ A   0     0   ] [ Lambda ]   [ -d                     ]

The positions do not change. The matrix is singular when G lies in the span of the
constraint rows (the constraints already forbid the motion the impact would stop).
"""
# lagcli's imports of what the generated module has above this code (not pasted):
from lagcli.runtime.run_limits import (ACCUMULATION_GAP, EVENT_BUDGET, FIRST_STEP_SAMPLES, RELEASE, REST,
                                       RESTING_SPEED, STEP_BUDGET_TEXT, EventRecord, end_note)
from lagcli.runtime.run_rules import max_step

# --- lagcli's event loop (lagcli/runtime/event_loop_code.py) ---
from dataclasses import dataclass

import numpy as np

_XTOL = 4 * np.finfo(float).eps


class EventRunFailure(RuntimeError):
    """A run with events failed: the message says when and why ("at t = ...: ...")."""


@dataclass(frozen=True)
class Event:
    """One event of a run as functions of (t, y), y = [q..., q'...], the parameters bound."""

    name: str
    action: str                  # "impact" | "reset" | "stop"
    direction: str               # "falling" | "rising" | "either"
    g: object                    # g(t, y) -> float: the event happens where g crosses zero
    G: object = None             # impact: (t, y) -> (n,) row dg/dq
    g_t: object = None           # impact: (t, y) -> dg/dt
    restitution: float = None    # impact: e in [0, 1]
    reset: object = None         # reset: (t, y) -> the new y
    hold_bias: object = None     # rest (lagcli's Python backend): (t, y) -> the held contact's G q''


@dataclass(frozen=True)
class EventModel:
    """What the loop needs of the system besides its right-hand side."""

    events: tuple                # Event, in the spec's order
    mass_matrix: object          # (t, y) -> M (n, n)
    constraint_rows: object      # (t, y) -> (A (m, n), d (m,)): A q' + d = 0


class Collected:
    """A sink of a run's rows and events in memory: what the generated module's simulate returns."""

    def __init__(self):
        self.rows, self.events = [], []

    def add_row(self, values):
        self.rows.append(values)


def impact(M, A, d, G, g_t, e, qd_minus):
    """(q'+, P) for one impact (see the module docstring)."""
    n, m = len(qd_minus), len(d)
    K = np.zeros((n + 1 + m, n + 1 + m))
    K[:n, :n], K[:n, n], K[:n, n + 1:] = M, -G, -A.T
    K[n, :n], K[n + 1:, :n] = G, A
    rhs = np.concatenate([M @ qd_minus, [-e * (G @ qd_minus + g_t) - g_t], -d])
    try:
        x = np.linalg.solve(K, rhs)
    except np.linalg.LinAlgError:
        raise EventRunFailure("the impact's direction dg/dq lies in the span of the constraint rows "
                              "(or the mass matrix is singular): no impulse can change the approach speed")
    return x[:n], float(x[n])


def approach_speed(G, g_t, qd):
    """dg/dt = G q' + g_t: negative while a falling gap closes."""
    return float(G @ qd + g_t)


def check_finite(t, y):
    """Raise when the state is no longer finite."""
    if not np.all(np.isfinite(y)):
        raise EventRunFailure(f"at t = {t:.10g}: the state is no longer finite (inf/nan): the solution blows up")


class _End(Exception):
    """The run ends early at an event (stop, accumulation, budget): `note` says why."""

    def __init__(self, note, event=None, why=""):
        self.note, self.event, self.why = note, event, why     # event: the one that accumulates


def run_events(solver_class, fun, row, y0, s, cap, model, times, sink, progress=None, check=check_finite,
               residual=None, tolerance=0.0, contacts=None):
    """Integrate from t = 0 to s.t_end (s: t_end, rtol, atol, step_budget and, optionally,
    budget_option: how the step budget's message names its option) with `model`'s
    events (an EventModel), giving `sink.add_row` the rows `row(t, y)` for the output
    `times` (an iterator, 0 first) and appending the EventRecords to `sink.events` as they
    happen; returns why the run ended early (a note) or None. `check(t, y)` raises on a
    state that must not go on; `residual(t, y)`: the constraint residual a reset must keep
    within `tolerance` (None: unconstrained). `contacts`: lagcli's held contacts
    (`rest: true`, lagcli/run/contact.py; then `fun` is their right-hand side and s also
    holds method, alpha, beta), None in the generated module. Raises EventRunFailure."""
    from scipy.optimize import brentq

    state = _State(model, sink.events, residual, tolerance)
    t0, y, fired = 0.0, np.array(y0, dtype=float), None
    pending = next(times, None)
    budget = _StepBudget(s.step_budget, getattr(s, "budget_option", None))
    free_cap = cap
    held_cap = max_step(s.method, s.alpha, s.beta, True) if contacts is not None else None
    if contacts is not None and (start := contacts.at_start(t0, y)) is not None:
        y = state.rest(contacts, t0, y, *start)
        cap = held_cap
    while True:
        try:
            solver = solver_class(fun, t0, y, s.t_end, rtol=s.rtol, atol=s.atol, max_step=cap)
            hit, pending = _segment(solver, state.model, fired, pending, times, row, sink, progress, check,
                                    budget, brentq)
            if hit is None:
                return None
            if state.model.events[hit[0]].action == RELEASE:
                t0, y, fired = state.release(contacts, *hit[1:])
                cap = free_cap
                continue
            t0, y, fired = state.act(*hit)
        except _End as end:
            held = None if contacts is None or end.event is None else contacts.hold(end.event, state.t, state.y)
            if held is None:
                sink.add_row(row(state.t, state.y))
                return end.note
            t0, y, fired = state.t, state.rest(contacts, state.t, state.y, end.event, *held), None
            cap = held_cap


class _StepBudget:
    """The run's bound on integrator steps (`--max-steps`, or `option` in the message), over
    all its segments."""

    def __init__(self, steps, option=None):
        self.steps, self.left, self.option = steps, steps, option

    def take(self, t):
        if self.left == 0:
            text = STEP_BUDGET_TEXT.format(steps=self.steps)
            if self.option is not None:
                text = text.replace("--max-steps N", self.option)
            raise EventRunFailure(f"at t = {t:.10g}: " + text)
        self.left -= 1


def _segment(solver, model, fired, pending, times, row, sink, progress, check, budget, brentq):
    """Step until an event or t_end; rows for output times before it. Returns ((index, t*,
    y-), next output time) or (None, ...) at t_end."""
    events = model.events
    g_old = [e.g(solver.t, solver.y) for e in events]
    first = True
    while solver.status == "running":
        t_old = solver.t
        budget.take(t_old)
        message = solver.step()
        if solver.status == "failed":
            raise EventRunFailure(f"at t = {solver.t:.10g}: the {type(solver).__name__} integrator failed: "
                                  f"{message}")
        check(solver.t, solver.y)
        dense = solver.dense_output()
        g_new = [e.g(solver.t, solver.y) for e in events]
        hit = _earliest(events, g_old, g_new, t_old, solver.t, dense, fired if first else None, brentq)
        end = hit[1] if hit else solver.t
        while pending is not None and (pending < end or (hit is None and pending <= end)):
            sink.add_row(row(pending, dense(pending)))
            pending = next(times, None)
        if hit is not None:
            return hit, pending
        g_old, first = g_new, False
        if progress is not None:
            progress(solver.t)
    return None, pending


def _earliest(events, g_old, g_new, t_old, t_new, dense, fired, brentq):
    """(index, t*, y(t*)) of the earliest crossing in (t_old, t_new], or None; `fired`:
    (index, from_zero, impact) of the event handled just before this step, or None."""
    best = None
    for k, e in enumerate(events):
        if fired is not None and k == fired[0]:
            bracket = _bracket_after_event(k, e, t_old, t_new, dense, *fired[1:])
        elif e.action == RELEASE:     # a held contact's force may dip below 0 and back within a step
            samples = np.linspace(t_old, t_new, FIRST_STEP_SAMPLES + 1)
            bracket = _first_crossing(e.direction, samples, [e.g(t, dense(t)) for t in samples])
        else:
            bracket = (t_old, t_new) if _crosses(e.direction, g_old[k], g_new[k]) else None
        if bracket is None:
            continue
        a, b = bracket
        root = brentq(lambda t: e.g(t, dense(t)), a, b, xtol=_XTOL * max(1.0, abs(b)), rtol=_XTOL) \
            if a < b else b
        if best is None or root < best[1]:
            best = (k, root, dense(root))
    return best


def _crosses(direction, before, after):
    falling, rising = before > 0 >= after, before < 0 <= after
    return falling if direction == "falling" else rising if direction == "rising" else falling or rising


def _first_crossing(direction, samples, values):
    """(a, b): the first interval between samples where the values cross zero in `direction`, or None."""
    for i in range(1, len(values)):
        if _crosses(direction, values[i - 1], values[i]):
            return samples[i - 1], samples[i]
    return None


def _bracket_after_event(k, e, t_old, t_new, dense, from_zero, impact):
    """The event just handled, in the first step after it: where, if anywhere, does g
    cross again in its direction? Found on FIRST_STEP_SAMPLES samples of the step
    (`from_zero`: g starts at exactly zero, after an impact or a reset that left g as it
    was; only an impact must turn back: else it accumulates)."""
    samples = np.linspace(t_old, t_new, FIRST_STEP_SAMPLES + 1)
    values = [0.0 if from_zero and i == 0 else e.g(t, dense(t)) for i, t in enumerate(samples)]
    bracket = _first_crossing(e.direction, samples, values)
    if bracket is not None:
        return bracket
    first = next((v for v in values if v != 0.0), None)
    wrong_side = first is not None and ((e.direction == "falling" and first < 0)
                                        or (e.direction == "rising" and first > 0))
    if first is None or (impact and wrong_side):
        raise _End(end_note("unresolved", e.name, t_old, t_old), k, "it recurs faster than a step resolves")
    return None


class _State:
    """The actions, the records and the accumulation rules."""

    def __init__(self, model, records, residual, tolerance):
        self.model, self.records = model, records
        self.residual, self.tolerance = residual, tolerance
        self.last = {}
        self.fastest = {}
        self.t, self.y = 0.0, None

    def act(self, k, t, y_minus):
        e = self.model.events[k]
        y_minus = np.asarray(y_minus, dtype=float)
        self.t, self.y = t, y_minus
        impulse, note, why = None, None, ""
        if e.action == "stop":
            self._record(t, e, y_minus, y_minus, None)
            raise _End(None)
        if e.action == "reset":
            y_plus = e.reset(t, y_minus)
            self._check_constraints(e, t, y_plus)
            from_zero = e.g(t, y_plus) == e.g(t, y_minus)     # g left at its root: it has crossed
        else:
            y_plus, impulse, note = self._impact(e, t, y_minus)
            why, from_zero = "the contact has come to rest", True
        self._record(t, e, y_minus, y_plus, impulse)
        self.y = y_plus
        gap = t - self.last.get(e.name, -np.inf)
        self.last[e.name] = t
        if note is None and gap < ACCUMULATION_GAP * max(1.0, abs(t)):
            note = end_note("recurred", e.name, t, gap)
            why = f"it recurred after {gap:.3g} s"
        if note is None and len(self.records) >= EVENT_BUDGET:
            raise _End(end_note("budget", e.name, t, EVENT_BUDGET))
        if note is not None:
            raise _End(note, k, why)
        return t, y_plus, (k, from_zero, e.action == "impact")

    def rest(self, contacts, t, y_minus, k, y_plus, impulse):
        """Event k's contact is held from t on (contacts.hold): record it, watch its release."""
        self._record(t, self.model.events[k], y_minus, y_plus, impulse, REST)
        self.model, self.t, self.y = contacts.watched, t, y_plus
        return y_plus

    def release(self, contacts, t, y):
        """The held contact lets go at t: record it; its impact event is watched again."""
        k = contacts.release()
        self._record(t, contacts.free.events[k], y, y, None, RELEASE)
        self.model, self.t, self.y = contacts.watched, t, np.asarray(y, dtype=float)
        return t, self.y, (k, True, True)

    def _impact(self, e, t, y_minus):
        n = len(y_minus) // 2
        q, qd = y_minus[:n], y_minus[n:]
        G, g_t = e.G(t, y_minus), float(e.g_t(t, y_minus))
        A, d = self.model.constraint_rows(t, y_minus)
        try:
            qd_plus, P = impact(self.model.mass_matrix(t, y_minus), A, d, G, g_t, e.restitution, qd)
        except EventRunFailure as exc:
            raise EventRunFailure(f"at t = {t:.10g}: event '{e.name}' (impact): {exc}") from None
        y_plus = np.concatenate([q, qd_plus])
        before, after = abs(approach_speed(G, g_t, qd)), abs(approach_speed(G, g_t, qd_plus))
        self.fastest[e.name] = max(self.fastest.get(e.name, 0.0), before)
        note = None
        if after <= RESTING_SPEED * self.fastest[e.name]:
            note = end_note("resting", e.name, t, after)
        return y_plus, P, note

    def _check_constraints(self, e, t, y_plus):
        value = self.residual(t, y_plus) if self.residual is not None else None
        if value is not None and value > self.tolerance:
            raise EventRunFailure(f"at t = {t:.10g}: event '{e.name}' (reset) gives a state that violates the "
                                  f"constraints (constraint_residual = {value:.3g}); reset the dependent "
                                  "coordinates and velocities consistently")

    def _record(self, t, e, before, after, impulse, action=None):
        self.records.append(EventRecord(float(t), e.name, action or e.action, tuple(map(float, before)),
                                        tuple(map(float, after)), None if impulse is None else float(impulse)))
