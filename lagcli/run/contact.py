"""Contacts at rest (an impact event with `rest: true`): held as a constraint while they
push, released where they would pull.

A contact is held where the impacts of its event accumulate (the rules of
lagcli/run/event_loop.py, which otherwise end the run there), or from t = 0 when the run
starts on it at rest (|g| and |G q' + g_t| at most CONSTRAINT_TOLERANCE) pressed into it.
A plastic impact (e = 0, the law of lagcli/runtime/event_loop_code.py: G q' + g_t = 0 while every spec
constraint keeps holding) removes the approach speed; then each right-hand side adds the
contact to the spec's accelerations q''0 (those of the generated module, with its own
constraint rows A and multipliers lambda0):

    M (q'' - q''0) = G^T mu + A^T nu,   G q'' = h - 2 alpha (G q' + g_t) - beta^2 g,   A (q'' - q''0) = 0

with h = `hold_bias` (g'' = 0, lagcli/derive/event_functions.py) and the run's Baumgarte
gains, solved by the same augmented system as an impact. The spec's multipliers are
lambda0 + nu while held. The normal force is N = s mu, s = +1 when the free side is g > 0
(a falling event), -1 when it is g < 0 (rising; `either`: the sign of mu at the hold, which
pushes there); it is the column `force_<event>` (0 while
free). A contact pushes and never pulls: where N falls through zero the contact is released,
located like any event (Brent's method on the step's dense output, N being a function of
(t, y); its sign is watched on FIRST_STEP_SAMPLES samples of every step, since the held
motion is smooth enough for steps longer than a brief pull), and the free motion resumes
with the impact event watched again. One contact is
held at a time: another `rest: true` event accumulating meanwhile ends the run as without
`rest`. The hold and the release are event records (actions "rest" and "release").
"""
from __future__ import annotations

import dataclasses

import numpy as np

from lagcli.interface import CONSTRAINT_TOLERANCE
from lagcli.runtime.event_loop_code import approach_speed, impact

from lagcli.runtime.run_limits import RELEASE, REST  # noqa: F401  (the actions of a hold and a release)


class Contacts:
    """The `rest: true` events of one run and the one held, if any. `accelerations(t, y)`
    -> (q''0, lambda0): the spec's motion without the contact."""

    def __init__(self, hybrid, accelerations, alpha: float, beta: float):
        self.free, self.accelerations, self.alpha, self.beta = hybrid, accelerations, alpha, beta
        self.resting = tuple(k for k, e in enumerate(hybrid.events) if e.hold_bias is not None)
        self.held: int | None = None        # index of the held event in `free.events`
        self.side = 1.0
        self.watched = hybrid               # the events to watch: the held one's release instead of it

    def rhs(self, t, y):
        n = len(y) // 2
        qdd = self.accelerations(t, y)[0] if self.held is None else self._solve(t, y)[0]
        return np.concatenate([y[n:], qdd])

    def multipliers(self, t, y) -> tuple[np.ndarray, list[float]]:
        """(the spec's multipliers, the normal force of each `rest: true` event in order)."""
        if self.held is None:
            return self.accelerations(t, y)[1], [0.0] * len(self.resting)
        _, lam, mu = self._solve(t, y)
        return lam, [self.side * mu if k == self.held else 0.0 for k in self.resting]

    def force(self, t, y) -> float:
        """N of the held contact: positive while it pushes."""
        return self.side * self._solve(t, y)[2]

    def _solve(self, t, y):
        """(q'', the spec's multipliers, mu) with the held contact (module docstring)."""
        e = self.free.events[self.held]
        y = np.asarray(y, dtype=float)
        n = len(y) // 2
        free, lam0 = self.accelerations(t, y)
        G, M = e.G(t, y), self.free.mass_matrix(t, y)
        A, _ = self.free.constraint_rows(t, y)
        w = approach_speed(G, float(e.g_t(t, y)), y[n:])
        target = float(e.hold_bias(t, y)) - 2.0 * self.alpha * w - self.beta ** 2 * float(e.g(t, y))
        qdd, mu = impact(M, A, -(A @ free), G, -target, 0.0, free)
        nu = np.linalg.lstsq(A.T, M @ (qdd - free) - G * mu, rcond=None)[0] if len(lam0) else lam0
        return qdd, np.asarray(lam0, dtype=float) + nu, mu

    def at_start(self, t: float, y):
        """(index, y+, impulse) of a contact the run starts resting on (held from t), or None."""
        y = np.asarray(y, dtype=float)
        n = len(y) // 2
        for k in self.resting:
            e = self.free.events[k]
            touching = abs(float(e.g(t, y))) <= CONSTRAINT_TOLERANCE
            if touching and abs(approach_speed(e.G(t, y), float(e.g_t(t, y)), y[n:])) <= CONSTRAINT_TOLERANCE:
                held = self.hold(k, t, y)
                if held is not None:
                    return (k, *held)
        return None

    def hold(self, k: int, t: float, y):
        """Hold event k's contact from (t, y): (y+, impulse of the plastic impact), or None
        when it cannot be held (one is held already, k is not `rest: true`, or the contact
        would pull at once)."""
        if self.held is not None or k not in self.resting:
            return None
        e = self.free.events[k]
        y = np.asarray(y, dtype=float)
        n = len(y) // 2
        G, g_t = e.G(t, y), float(e.g_t(t, y))
        A, d = self.free.constraint_rows(t, y)
        qd, impulse = impact(self.free.mass_matrix(t, y), A, d, G, g_t, 0.0, y[n:])
        y_plus = np.concatenate([y[:n], qd])
        self.held = k
        mu = self._solve(t, y_plus)[2]
        self.side = _free_side(e.direction, mu)
        if not self.side * mu > 0.0:
            self.held = None
            return None
        release = dataclasses.replace(e, action=RELEASE, direction="falling", g=self.force)
        self.watched = dataclasses.replace(self.free, events=(*self.free.events[:k], *self.free.events[k + 1:],
                                                              release))
        return y_plus, impulse + 0.0            # + 0.0: a plastic impact of nothing is 0, not -0

    def release(self) -> int:
        """Let the held contact go; its index (its impact event is watched again)."""
        k, self.held, self.watched = self.held, None, self.free
        return k


def contacts_of(hybrid, accelerations, alpha: float, beta: float) -> Contacts | None:
    """The run's contacts, or None when no event has `rest: true`."""
    if not any(e.hold_bias is not None for e in hybrid.events):
        return None
    return Contacts(hybrid, accelerations, alpha, beta)


def _free_side(direction: str, mu: float) -> float:
    """+1 when the free side of the gap is g > 0, -1 when it is g < 0: a falling event's and
    a rising event's; for `either`, the side the held contact pushes to (held where the
    motion presses into the contact, it pushes away from it)."""
    if direction != "either":
        return 1.0 if direction == "falling" else -1.0
    return 1.0 if mu >= 0.0 else -1.0
