"""Event functions from the model: g(t, q, q'), and for an impact G = dg/dq and g_t.

An impact at g(t, q) = 0 changes the velocities by an impulse P along G^T while every
constraint row (A, d of lagcli/derive/result.py) keeps holding (lagcli/run/impact.py):

    M (q'+ - q'-) = G^T P + A^T Lambda
    G q'+ + g_t = -e (G q'- + g_t)
    A q'+ + d = 0
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagcli.errors import Loc
from lagcli.model.model_types import Model


@dataclass(frozen=True)
class EventFunction:
    name: str
    action: str                              # "impact" | "reset" | "stop"
    direction: str                           # "falling" | "rising" | "either"
    g: sp.Expr                               # the event happens where g crosses zero
    G: tuple[sp.Expr, ...] = ()              # impact: dg/dq_k, one per coordinate
    g_t: sp.Expr = sp.S.Zero                 # impact: dg/dt
    restitution: sp.Expr | None = None       # impact: e (parameters only)
    reset: tuple[tuple[str, sp.Expr], ...] = ()
    loc: Loc | None = None


def event_functions(model: Model) -> tuple[EventFunction, ...]:
    """One `EventFunction` per item of the spec's `events:`, in spec order."""
    result = []
    for e in model.events:
        G, g_t = (), sp.S.Zero
        if e.action == "impact":
            G = tuple(sp.diff(e.when, q) for q in model.q)
            g_t = sp.diff(e.when, model.t)
        result.append(EventFunction(e.name, e.action, e.direction, e.when, G, g_t, e.restitution, e.reset, e.loc))
    return tuple(result)
