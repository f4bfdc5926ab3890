"""Kinetic and potential energy, split as T = 1/2 q'^T M q' + a^T q' + T0.

For each point with position r(q, t) (particle or centre of mass) and each
body angular velocity w = J_w q' + w_t (body axes):

    M  += m J^T J + J_w^T I J_w          J = dr/dq
    a  += m J^T r_t + J_w^T I w_t        r_t = dr/dt
    T0 += 1/2 m r_t.r_t + 1/2 w_t^T I w_t

This is the notes' construction (section 6.6) and avoids differentiating T twice.
"""
from __future__ import annotations

import functools
from collections import defaultdict
from dataclasses import dataclass

import sympy as sp

from lagcli.model.calculus import TimeDerivative, almost_everywhere, derivative, jacobian_columns, matrix_of_entries
from lagcli.model.model_types import Model, RigidBody, elementary_rotation
from lagcli.model.ordering import class_key
from lagcli.model.products import product
from lagcli.model.sums import dot, scaled, total

AXES = {"x": 0, "y": 1, "z": 2}
_ZERO = sp.S.Zero     # the z components of a planar model's vectors
_SUM_CLASS = class_key(sp.Add)
_UNKNOWN = object()     # a pair of vectors whose dot product is not formed yet


@dataclass(frozen=True)
class Energies:
    mass_matrix: sp.ImmutableMatrix
    t1_coefficients: sp.ImmutableMatrix
    T0: sp.Expr
    V: sp.Expr


@functools.lru_cache(maxsize=256)  # energy, forcing and torques all need it, per derivation
def body_angular_velocity(body: RigidBody, D: TimeDerivative) -> sp.ImmutableMatrix:
    """Angular velocity in body axes for successive body-fixed rotations R = R1 R2 ... Rk:
    w_body = sum_i (R_{i+1} ... R_k)^T e_i  d(angle_i)/dt, accumulated as w <- R_i^T w + e_i angle_i'."""
    omega = sp.zeros(3, 1)
    for axis, angle in body.rotations:
        unit = sp.zeros(3, 1)
        unit[AXES[axis]] = 1
        omega = elementary_rotation(axis, angle).T * omega + unit * D(angle)
    return sp.ImmutableMatrix(omega)


def kinetic_parts(model: Model, D: TimeDerivative) -> tuple[sp.Matrix, sp.Matrix, sp.Expr]:
    """The terms of M, a and T0 from every point and body, each entry summed once at the
    end (adding n x n matrices point by point rebuilt every growing sum n times)."""
    n = len(model.q)
    M: dict = defaultdict(list)     # (i, j) -> (mass, dot product) pairs, upper triangle (J^T J is symmetric)
    a, T0 = [[] for _ in range(n)], []
    dots = _DotProducts()
    for mass, r in model.mass_points:
        J, r_t = jacobian_columns(r, model.q, D.free, D.partials), r.applyfunc(lambda e: derivative(e, model.t, D.free))
        _add_products(M, a, T0, J, None, r_t, mass, dots)
    for body in model.bodies:
        omega = body_angular_velocity(body, D)
        J_w = jacobian_columns(omega, model.qd, D.free)
        w_t = omega.subs({v: 0 for v in model.qd})
        _add_products(M, a, T0, J_w, body.inertia, w_t, 1, dots)
    entries, masses = {}, {}
    for (i, j), terms in sorted(M.items()):
        entries[i, j] = entries[j, i] = _entry(terms, masses)
    M, a, T0 = matrix_of_entries(n, n, entries), sp.Matrix([total(terms) for terms in a]), total(T0)
    if model.kinetic == 0:
        return M, a, T0
    extra_M, extra_a, extra_T0 = _split_extra_kinetic(model)
    return M + extra_M, a + extra_a, T0 + extra_T0


def _entry(terms: list, masses: dict) -> sp.Expr:
    """The sum of the (mass, dot product) pairs of one entry of M: a chain's points share
    their Jacobian columns, so an entry is mostly one dot product X times every mass,
    built as X (m_k + ... + m_n): one product, not n (the n^3 terms of a chain's M).
    `masses`: the sums of masses formed so far, by the masses' identities (the entries
    M_ij of a chain with one max(i, j) have the same one: summing it for each was the n^3
    part of M; hashing the masses' tuples by value then was most of what was left of it).
    The masses stay alive in `terms` while `masses` is used, so their ids stay theirs."""
    weights, entries = zip(*terms)
    if len(set(map(id, entries))) == 1:        # one object (identities, compared in C)
        key = tuple(map(id, weights))     # by identity: no Python-level hash per mass
        if key not in masses:
            masses[key] = total(weights)
        return product(masses[key], entries[0])
    return total([product(mass, entry) for mass, entry in terms])


class _DotProducts:
    """u . w of vectors of expressions, each pair formed once (a chain's points share their
    Jacobian columns). Vectors are numbered when first seen, so the pairs of a point's
    columns are looked up by number (hashing tuples of expressions per pair cost more)."""

    def __init__(self):
        self.numbers: dict = {}
        self.vectors: list = []
        self.values: dict = {}

    def number(self, vector: tuple) -> int:
        found = self.numbers.get(vector)
        if found is None:
            found = self.numbers[vector] = len(self.vectors)
            self.vectors.append(vector)
        return found

    def __call__(self, u: int, w: int) -> sp.Expr | None:
        """The dot product of vectors u and w (numbers); None when it is zero."""
        key = (u, w)
        if key not in self.values:
            value = total([product(x, y) for x, y in zip(self.vectors[u], self.vectors[w])
                           if x is not _ZERO and y is not _ZERO])    # 0 * y is 0: y is finite
            self.values[key] = None if value is _ZERO or (type(value) is not sp.Add and value == 0) else value
        return self.values[key]


def _add_products(M, a, T0, J, inertia, v_t, mass, dots: _DotProducts) -> None:
    """The terms of mass * (J^T I J, J^T I v_t, 1/2 v_t^T I v_t) for one point (I = None:
    the identity) or body; J is given by its nonzero columns (`jacobian_columns`)."""
    I_v = v_t if inertia is None else inertia * v_t
    moving = any(v_t)
    columns = [dots.number(column) for _, column in J]
    weighted = columns if inertia is None else [dots.number(tuple(inertia * sp.Matrix(column))) for _, column in J]
    v_t, I_v = dots.number(tuple(v_t)), dots.number(tuple(I_v))
    indices, known = [i for i, _ in J], dots.values
    for k, i in enumerate(indices):
        column = columns[k]
        for j, other in zip(indices[k:], weighted[k:]):
            entry = known.get((column, other), _UNKNOWN)     # the pairs of a chain's columns: n^3
            if entry is _UNKNOWN:
                entry = dots(column, other)
            if entry is not None:
                M[i, j].append((mass, entry))
        if moving:
            entry = dots(column, I_v)
            if entry is not None:
                a[i].append(product(mass, entry))
    if moving:
        entry = dots(v_t, I_v)
        T0.append(product(product(mass, entry if entry is not None else 0), sp.S.Half))


def quadratic_part(M: sp.MatrixBase, qd) -> sp.Expr:
    """T2 = 1/2 q'^T M q', summed row by row over M's nonzero entries (M of n uncoupled
    coordinates has n of n^2): 1/2 sum_j ((q'^T M)_j q'_j)."""
    row_sums = [total([_times_velocity(qd[i], M_ij) for i, M_ij in row]) for row in nonzero_rows(M)]
    return scaled(sp.S.Half, total([product(row_sums[j], qd[j]) for j in range(len(qd))]))


def _times_velocity(velocity: sp.Symbol, entry: sp.Expr) -> sp.Expr:
    """velocity * entry, the same expression as `product` builds. An entry that is a product
    of sums (a chain's X (m_k + ... + m_n)) takes the velocity where sympy's order puts it,
    without sorting the factors again: Mul keeps a rational number first and orders a
    symbol and a sum by their classes alone (`Basic.compare`, `class_key`). 1 600 such
    products at 40 links."""
    if not (velocity.is_Symbol and velocity.is_commutative and _is_product_of_sums(entry)):
        return product(velocity, entry)
    number, sums = (entry.args[:1], entry.args[1:]) if entry.args[0].is_Rational else ((), entry.args)
    if class_key(type(velocity)) < _SUM_CLASS:
        return sp.Mul._from_args((*number, velocity, *sums), True)
    return sp.Mul._from_args((*number, *sums, velocity), True)


def _is_product_of_sums(entry: sp.Expr) -> bool:
    """A commutative product of sums, maybe times a rational number."""
    if not (entry.is_Mul and entry.is_commutative):
        return False
    factors = entry.args[1:] if entry.args[0].is_Rational else entry.args
    return all(factor.is_Add for factor in factors)


def nonzero_rows(M: sp.MatrixBase) -> list[list[tuple[int, sp.Expr]]]:
    """(j, M_ij) of the nonzero entries of each row i (M is symmetric: also its columns)."""
    rows: list[list] = [[] for _ in range(M.rows)]
    for (i, j), entry in sorted(M.todok().items()):
        rows[i].append((j, entry))
    return rows


def _split_extra_kinetic(model: Model):
    """The `kinetic:` term, split by degree in q' (the model checked it is at most quadratic)."""
    K, qd = model.kinetic, sp.Matrix(model.qd)
    zero = {v: 0 for v in model.qd}
    M = sp.hessian(K, qd)
    a = sp.Matrix([K.diff(v).subs(zero) for v in qd])
    return M.subs(zero), a, K.subs(zero)


def potential_energy(model: Model) -> sp.Expr:
    """V = -sum m g.r (gravity) + sum 1/2 k (|r_a - r_b| - L0)^2 + potential, summed once
    (adding term by term rebuilt the growing sum: n^2 for n springs)."""
    terms = [model.potential]
    if model.gravity is not None:
        terms += [-product(mass, dot(model.gravity, r)) for mass, r in model.mass_points]     # Mul's, no flatten
    for spring in model.springs:
        delta = spring.end_a - spring.end_b
        squared = delta.dot(delta)
        stretch = sp.sqrt(squared) - spring.rest_length if spring.rest_length != 0 else None
        terms.append(spring.stiffness * (stretch ** 2 if stretch is not None else squared) / 2)
    return total(terms)


def energies(model: Model, D: TimeDerivative) -> Energies:
    M, a, T0 = kinetic_parts(model, D)
    return Energies(almost_everywhere(M), almost_everywhere(a), almost_everywhere(T0), potential_energy(model))
