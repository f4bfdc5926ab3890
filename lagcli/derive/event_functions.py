"""Event functions from the model: g(t, q, q'), and for an impact G = dg/dq and g_t.

An impact at g(t, q) = 0 changes the velocities by an impulse P along G^T while every
constraint row (A, d of lagcli/derive/result.py) keeps holding (`impact` in lagcli/runtime/event_loop_code.py):

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
    hold_bias: sp.Expr | None = None         # rest: G q'' = hold_bias keeps g'' = 0 (see below)
    force_unit: str | None = None            # rest: the unit of its normal force (units given only)


def event_functions(model: Model) -> tuple[EventFunction, ...]:
    """One `EventFunction` per item of the spec's `events:`, in spec order."""
    result = []
    for e in model.events:
        G, g_t, hold, unit = (), sp.S.Zero, None, None
        if e.action == "impact":
            G = tuple(sp.diff(e.when, q) for q in model.q)
            g_t = sp.diff(e.when, model.t)
        if e.rest:
            hold, unit = _hold_bias(model, G, g_t), _force_unit(model, e.when)
        result.append(EventFunction(e.name, e.action, e.direction, e.when, G, g_t, e.restitution, e.reset, e.loc,
                                    hold, unit))
    return tuple(result)


def _hold_bias(model: Model, G, g_t) -> sp.Expr:
    """A held contact (`rest: true`) is the constraint g = 0: with w = G q' + g_t its
    velocity, g'' = G q'' + dw/dt|q'' = 0 gives G q'' = -(dw/dt + sum_j dw/dq_j q'_j)."""
    w = sum((G_k * qd for G_k, qd in zip(G, model.qd)), g_t)
    return -(sp.diff(w, model.t) + sum(sp.diff(w, q) * qd for q, qd in zip(model.q, model.qd)))


def _force_unit(model: Model, g: sp.Expr) -> str | None:
    """The unit of a held contact's normal force mu (M q'' = F + G^T mu): an energy per
    unit of the gap g, so N for a length and N*m for an angle; None without units."""
    from lagcli.model.units import ENERGY, FORCE, Mismatch, base_units, dimension_of, symbol_dimensions, times

    dims = symbol_dimensions(model)
    if not dims:
        return None
    try:
        dim = times(ENERGY, dimension_of(g, dims), -1)
    except Mismatch:
        return None
    return {FORCE: "N", ENERGY: "N*m"}.get(dim) or base_units(dim)
