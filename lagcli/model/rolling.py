"""Rolling without slipping on a plane, as constraint rows (a `rolling:` entry).

The surface is the plane n.X = h (n made a unit vector), possibly turning at the
rate W about n through the point c, so that its material point at X moves with
v_s(X) = W n x (X - c). The contact point C of body B is

    wheel {radius r, axis a}:  C = B + r_off,  r_off = -r k,  k = (n - (n.a) a) / |n - (n.a) a|
                               (the point of the disc's rim closest to the plane; a = B's axis)
    contact: r_off             C = B + r_off   (e.g. [0, 0, -r] for a sphere on n = e_z)

and the material point of B there moves with v_C = v_B + w_B x r_off. The rows are

    rolling_<B>_<a1>:  (v_C - v_s(C)) . t1 = 0      nonholonomic: no slip along t1
    rolling_<B>_<a2>:  (v_C - v_s(C)) . t2 = 0      nonholonomic: no slip along t2
    rolling_<B>_<a3>:  n . C - h = 0                holonomic, only when it does not hold
                                                    identically (the spec's coordinates
                                                    keep the body on the plane otherwise)

a3 is the inertial axis closest to n (at the parameters' values), a1, a2 the other
two in x, y, z order and t1, t2 their directions projected on the plane (Gram-Schmidt).
With rows written this way the multipliers are the contact force on B: lambda of
a tangent row is the friction force along t, lambda of the normal row the normal
force along n (lagcli's convention: the generalized constraint force is
sum_j lambda_j a_j, i.e. the force lambda times the gradient of the row).
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.calculus import numerically_zero
from lagcli.model.kinematics import AXES, ZERO, Vector
from lagcli.model.model_types import ConstraintSpec
from lagcli.spec.frames import rolling_row_prefix
from lagcli.spec.types import Rolling, Src, Surface

GROUND = Surface(normal=(Src("0", None), Src("0", None), Src("1", None)))


def rolling_constraints(item: Rolling, model) -> tuple[ConstraintSpec, ...]:
    """The rows of one rolling contact; `model` is the model builder (its parser and scope)."""
    surface = item.surface or GROUND
    body = model.scope.names[item.body]
    normal = _unit(Vector.of(model.vector(surface.normal, model.constant_in_motion)))
    height = model.expr(surface.height, sp.S.Zero, model.constant_in_motion)
    offset = (_wheel_offset(body, model.expr(item.wheel[0], check=model.constant_in_motion), item.wheel[1],
                            normal) if item.wheel else Vector.of(model.vector(item.contact, model.no_velocities)))
    contact = body.material_point(offset)
    slip = contact.velocity - _surface_velocity(surface, model, normal, contact.position)
    tangents, normal_axis = _tangents(normal, model.parameter_values)
    prefix = rolling_row_prefix(item.body)
    rows = [ConstraintSpec(prefix + axis, slip.dot(t), item.loc) for axis, t in tangents]
    gap = normal.dot(contact.position) - height
    if not numerically_zero([gap]):
        rows.insert(0, ConstraintSpec(prefix + normal_axis, gap, item.loc))
    return tuple(rows)


def _wheel_offset(body, radius: sp.Expr, axis: str, normal: Vector) -> Vector:
    a = body.unit(axis)
    along_axis = normal.dot(a)
    # |n - (n.a) a| = sqrt(1 - (n.a)^2) for unit n and a: the short form of the length
    return (normal - a.scaled(along_axis)).scaled(-radius / sp.sqrt(1 - along_axis**2))


def _surface_velocity(surface: Surface, model, normal: Vector, where: Vector) -> Vector:
    if surface.angular_velocity is None:
        return ZERO
    rate = model.expr(surface.angular_velocity, check=model.no_velocities)
    centre = Vector.of(model.vector(surface.centre, model.constant_in_motion)) if surface.centre else ZERO
    return normal.scaled(rate).cross(where - centre)


def _unit(vector: Vector) -> Vector:
    length = sp.sqrt(sp.trigsimp(vector.dot(vector)))
    return vector if length == 1 else vector.scaled(1 / length)


def _tangents(normal: Vector, values: dict) -> tuple[list[tuple[str, Vector]], str]:
    """The plane's two directions, from the inertial axes least along the normal."""
    sizes = [abs(float(c.xreplace(values))) if c.free_symbols <= set(values) else 0.0
             for c in normal.components]
    normal_axis = AXES[max(range(3), key=lambda i: (sizes[i], -i))]
    tangents: list[tuple[str, Vector]] = []
    for axis in AXES:
        if axis == normal_axis:
            continue
        t = Vector(tuple(sp.S(int(axis == a)) for a in AXES))
        for other in [normal] + [u for _, u in tangents]:
            t = t - other.scaled(t.dot(other))
        tangents.append((axis, _unit(t)))
    return tangents, normal_axis
