"""The pose of a system: what its coordinates put where, as numbers (to tell poses apart).

Two sets of coordinates can describe one pose: an angle and the same angle a turn on,
Euler angles z-x-z (psi, theta, phi) and (psi + pi, -theta, phi + pi), any psi and phi
with the same psi + phi at theta = 0. The pose key is a vector that is equal exactly
when the poses are:

- every particle's position, every body's centre of mass and rotation matrix, where
  every force acts, the force and torque there at rest, the ends of springs and dampers;
- a coordinate the kinematics above do not contain, by cos and sin when it occurs only
  inside sin, cos and tan (an angle), else by its value;
- a coordinate's value when it occurs outside sin, cos and tan in a term the kinematics
  do not show (a potential k theta^2/2 tells theta from theta + 2 pi, a holonomic
  constraint s - r theta does too).
"""
from __future__ import annotations

import numpy as np
import sympy as sp

SAME_POSE = 1e-7          # keys this close (max norm, relative to max(1, |key|)) are one pose


def pose_function(model, parameters: dict, exprs: list | None = None):
    """`key(q) -> ndarray`: the pose key (module docstring) at coordinates q, with the
    `parameters` {symbol: value}, t = 0 and every velocity 0 (`exprs`: the key's
    `pose_expressions`, when the caller has them)."""
    exprs = pose_expressions(model, parameters) if exprs is None else exprs
    f = sp.lambdify([list(model.q)], exprs, modules="numpy", cse=True)
    return lambda q: np.asarray(f(list(q)), dtype=float).reshape(-1)


def pose_expressions(model, parameters: dict) -> list:
    """The entries of the pose key, expressions of the coordinates (as `pose_function`)."""
    rest = {v: 0 for v in model.qd} | {model.t: 0} | {s: sp.Float(v, 30) for s, v in parameters.items()}
    kinematic = [e for m in _kinematics(model) for e in m]
    seen = set().union(*(e.free_symbols for e in kinematic)) if kinematic else set()
    others = [model.potential, model.kinetic, model.dissipation, *model.generalized_forces,
              *(c.expr for c in model.constraints)]
    raw = set().union(*(_outside_trig(e) for e in others)) if others else set()
    extra = []
    for q in model.q:
        if q in raw:
            extra.append(q)
        elif q not in seen:
            extra += [sp.cos(q), sp.sin(q)]
    return [sp.sympify(e).xreplace(rest) for e in kinematic + extra]


def same_pose(a: np.ndarray, b: np.ndarray) -> bool:
    """The pose keys `a` and `b` describe one pose."""
    scale = max(1.0, float(np.max(np.abs(a), initial=0.0)), float(np.max(np.abs(b), initial=0.0)))
    return bool(np.max(np.abs(a - b), initial=0.0) <= SAME_POSE * scale)


def _kinematics(model) -> list:
    """The matrices of positions, rotations, force points and values, spring and damper ends."""
    out = [p.position for p in model.particles]
    for body in model.bodies:
        out += [body.position, body.rotation]
    for force in model.forces:
        out += [m for m in (force.point, force.force, force.torque) if m is not None]
    for link in (*model.springs, *model.dampers):
        out += [link.end_a, link.end_b]
    return [list(sp.Matrix(m)) for m in out]


def _outside_trig(expr) -> set:
    """The symbols of `expr` that occur outside every sin, cos and tan."""
    expr = sp.sympify(expr)
    calls = expr.atoms(sp.sin, sp.cos, sp.tan)
    return expr.xreplace({c: sp.Dummy() for c in calls}).free_symbols
