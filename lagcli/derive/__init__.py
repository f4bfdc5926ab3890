"""Model -> Derivation: Lagrange's equations and everything reported about them.

`derive(model)` is a pure function returning a complete, frozen `Derivation`
(see `result.py` for the equation forms and sign conventions). Large
expressions are never simplified here; tests and reports decide that. The
forcing F, the equations M q'' - F and the total generalized forces are the
Derivation's to compute on first use (`forcing.py`): reports never read them.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.calculus import TimeDerivative, almost_everywhere, free_symbols, numerically_zero
from lagcli.derive.constraints import constraint_bias, constraint_matrix, constraint_rows
from lagcli.derive.dissipation import damper_forces_on
from lagcli.derive.energy import energies, quadratic_part
from lagcli.derive.forces import applied_generalized_forces
from lagcli.derive.invariants import (LagrangianProbe, conserved_quantities, ignorable_coordinates,
                                      jacobi_integral, jacobi_obstacle, momenta)
from lagcli.derive.result import Derivation
from lagcli.derive.event_functions import event_functions
from lagcli.model.model_types import Model
from lagcli.model.products import product
from lagcli.model.sums import dot, negated_terms, total

__all__ = ["derive", "Derivation"]


def derive(model: Model) -> Derivation:
    D = TimeDerivative(model.t, model.q, model.qd, model.qdd)
    qd = sp.Matrix(model.qd)
    e = energies(model, D)
    M, a = e.mass_matrix, e.t1_coefficients
    n = len(model.q)
    T2 = quadratic_part(M, model.qd)
    T1 = dot(a, qd)
    T = total([total([T2, T1]), e.T0])       # T2 + T1 + T0 (sympy's `+` sorted V's terms anew)
    L = total([T, *negated_terms(e.V)])      # T - V
    Q_applied = almost_everywhere(applied_generalized_forces(model, D))
    rows = constraint_rows(model)
    A = constraint_matrix(model, rows)
    multipliers = tuple(r.multiplier for r in rows)
    constraint_force = A.T * sp.Matrix(multipliers) if rows else sp.zeros(n, 1)

    probe = LagrangianProbe(M, a, e.T0, e.V)
    ignorable = ignorable_coordinates(model, probe, Q_applied, rows)
    no_jacobi = jacobi_obstacle(model, probe, Q_applied, rows)
    h = None if no_jacobi else jacobi_integral(model, T2, e.T0, e.V, probe)
    energy = total([T, e.V])
    energy_is_jacobi = h is not None and numerically_zero([T1 + 2 * e.T0])
    return Derivation(
        model=model, T=T, T2=T2, T1=T1, T0=e.T0, V=e.V, L=L,
        mass_matrix=M, t1_coefficients=a,
        nonconservative_forces=Q_applied,
        constraints=rows, constraint_matrix=A, constraint_bias=constraint_bias(model, rows, D),
        multipliers=multipliers,
        generalized_constraint_forces=sp.ImmutableMatrix(constraint_force),
        particle_constraint_forces=_particle_constraint_forces(model, D) if rows else {},
        energy=energy, ignorable=ignorable,
        conserved=conserved_quantities(model, ignorable, momenta(M, a, model.qd, ignorable, model.q), h,
                                       energy_is_jacobi),
        jacobi_integral=h, energy_is_jacobi=energy_is_jacobi, no_jacobi_reason=no_jacobi,
        scleronomic=_is_scleronomic(model),
        events=event_functions(model),
    )


def _particle_constraint_forces(model: Model, D: TimeDerivative) -> dict:
    """R_i = m_i r_i'' - F_i (lecture notes, 6.6): what the constraints must supply to each particle."""
    result = {}
    for p in model.particles:
        applied = sp.zeros(3, 1)
        if model.gravity is not None:
            applied += p.mass * model.gravity
        for force in model.forces:
            if force.force is not None and force.point == p.position:
                applied += force.force
        for spring in model.springs:
            for here, there in ((spring.end_a, spring.end_b), (spring.end_b, spring.end_a)):
                if here == p.position:
                    delta = here - there
                    length = sp.sqrt(delta.dot(delta))
                    applied -= spring.stiffness * (1 - spring.rest_length / length) * delta
        applied += damper_forces_on(model, p.position, D)
        acceleration = D.matrix(D.matrix(p.position))
        result[p.name] = almost_everywhere(p.mass * acceleration - applied)
    return result


def _is_scleronomic(model: Model) -> bool:
    """docs/spec.md, "scleronomic": no position, orientation, energy term or constraint depends on t,
    and no `known` function of t is declared."""
    if model.known:
        return False
    exprs = [p.position for p in model.particles] + [b.position for b in model.bodies]
    exprs += [angle for b in model.bodies for _, angle in b.rotations]
    exprs += [model.kinetic, model.potential] + [c.expr for c in model.constraints]
    exprs += [s.end_a for s in model.springs] + [s.end_b for s in model.springs]
    free: dict = {}     # the positions share their terms: each walked once, not once a position
    return not any(model.t in free_symbols(part, free)
                   for e in exprs for part in (e if isinstance(e, sp.MatrixBase) else (sp.sympify(e),)))
