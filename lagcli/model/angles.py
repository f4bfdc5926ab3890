"""Which coordinates of a model are angles (for the run interface: plot panels, `rad`)."""
from __future__ import annotations

import sympy as sp


def angle_coordinates(model) -> frozenset:
    """The coordinates of `model` that are angles: a body's rotation angle, or found
    inside a sin, cos or tan of a position, a spring end or an energy term."""
    q = set(model.q)
    found = set()
    for body in model.bodies:
        for _, angle in body.rotations:
            found |= angle.free_symbols & q
    exprs = [m.position for m in [*model.particles, *model.bodies]]
    exprs += [e for s in model.springs for e in (s.end_a, s.end_b)] + [model.potential, model.kinetic]
    for expr in exprs:
        for call in sp.sympify(expr).atoms(sp.sin, sp.cos, sp.tan):
            found |= call.free_symbols & q
    return frozenset(s.name for s in found)
