"""A contact held after an accumulation (an impact event with `rest: true`): from then on
its gap g = 0 is a constraint of the motion, so a ball with e < 1 rests on the floor
instead of the run ending at its accumulation time.

At the hold the velocities lose their approach speed by a plastic impact (e = 0, the
law of lagcli/runtime/event_loop_code.py: G q' + g_t = 0 while every spec constraint keeps holding).
Then each right-hand side adds the contact to the spec's accelerations q''0 (those of the
generated module, with its own constraint rows A):

    M (q'' - q''0) = G^T mu + A^T nu,   G q'' = h - 2 alpha (G q' + g_t) - beta^2 g,   A (q'' - q''0) = 0

with h = `hold_bias` (g'' = 0, lagcli/derive/event_functions.py) and the run's Baumgarte
gains, solved by the same augmented system as an impact. The contact is held for the
rest of the run (it does not release where mu would pull); its force is not a column.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from lagcli.runtime.event_loop_code import impact


def hold_contact(hybrid, k: int, fun, t: float, y, alpha: float, beta: float):
    """(the right-hand side with event k's contact held, `hybrid` without event k, the
    state at the hold with the approach speed removed)."""
    e = hybrid.events[k]
    y = np.asarray(y, dtype=float)
    n = len(y) // 2
    A, d = hybrid.constraint_rows(t, y)
    qd, _ = impact(hybrid.mass_matrix(t, y), A, d, e.G(t, y), float(e.g_t(t, y)), 0.0, y[n:])

    def held(t, y):
        free = fun(t, y)[n:]
        G, w = e.G(t, y), float(e.G(t, y) @ y[n:] + e.g_t(t, y))
        target = float(e.hold_bias(t, y)) - 2.0 * alpha * w - beta * beta * float(e.g(t, y))
        A, _ = hybrid.constraint_rows(t, y)
        qdd, _ = impact(hybrid.mass_matrix(t, y), A, -(A @ free), G, -target, 0.0, free)
        return np.concatenate([y[n:], qdd])

    others = dataclasses.replace(hybrid, events=hybrid.events[:k] + hybrid.events[k + 1:])
    return held, others, np.concatenate([y[:n], qd])


def hold_note(name: str, t: float, why: str) -> str:
    return (f"event '{name}' accumulates at t = {t:.10g} ({why}); its contact is held from there on "
            "(rest: true)")
