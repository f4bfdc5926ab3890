"""Dissipative generalized forces from a Rayleigh dissipation function.

    R = R_spec(q, q', t) + sum over dampers 1/2 c (dL/dt)^2,   L = |r_a - r_b|
    Q'_j = -dR/dq'_j

A damper's force on end a is -c (dL/dt) e, e = (r_a - r_b)/L (it opposes the
rate of change of its length), and its virtual work gives exactly -dR/dq'_j
because dL/dt = sum_j dL/dq_j q'_j + dL/dt|_q. When R is homogeneous of degree 2
in q' and nothing depends on t, the energy decays as dE/dt = Q'.q' = -2R.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.calculus import TimeDerivative
from lagcli.model.model_types import LinearDamper, Model


def damper_length_rate(damper: LinearDamper, D: TimeDerivative) -> sp.Expr:
    """dL/dt = (r_a - r_b).(r_a - r_b)' / |r_a - r_b|."""
    delta = damper.end_a - damper.end_b
    return delta.dot(D.matrix(delta)) / sp.sqrt(delta.dot(delta))


def rayleigh_function(model: Model, D: TimeDerivative) -> sp.Expr:
    """R: the spec's `dissipation:` plus 1/2 c (dL/dt)^2 for every damper."""
    return model.dissipation + sum((d.damping * damper_length_rate(d, D) ** 2 / 2 for d in model.dampers),
                                   sp.S.Zero)


def dissipative_forces(model: Model, D: TimeDerivative) -> sp.Matrix:
    """Q'_j = -dR/dq'_j, one entry per coordinate (zeros without dampers or dissipation)."""
    if not model.dampers and model.dissipation == 0:
        return sp.zeros(len(model.q), 1)
    R = rayleigh_function(model, D)
    return sp.Matrix([-R.diff(v) for v in model.qd])


def damper_forces_on(model: Model, position: sp.ImmutableMatrix, D: TimeDerivative) -> sp.Matrix:
    """The dampers' force on the point at `position` (an end of each damper that acts on it)."""
    force = sp.zeros(3, 1)
    for damper in model.dampers:
        for here, there in ((damper.end_a, damper.end_b), (damper.end_b, damper.end_a)):
            if here == position:
                delta = here - there
                force -= damper.damping * damper_length_rate(damper, D) * delta / sp.sqrt(delta.dot(delta))
    return force
