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

from lagcli.errors import Problem
from lagcli.model.calculus import numerically_zero
from lagcli.model.constants import ConstantError, value_at
from lagcli.model.kinematics import AXES, ZERO, Vector
from lagcli.model.model_types import ConstraintSpec, RollingContact
from lagcli.spec.frames import rolling_row_prefix
from lagcli.spec.types import Rolling, Src, Surface

ROOT_MAX_OPS = 60         # larger squares are left under their root (trigsimp is slow)
GROUND = Surface(normal=(Src("0", None), Src("0", None), Src("1", None)))


def rolling_constraints(item: Rolling, model) -> tuple[ConstraintSpec, ...]:
    """The rows of one rolling contact; `model` is the model builder (its parser and scope)."""
    surface = item.surface or GROUND
    body = model.scope.names[item.body]
    reference = reference_state(model)
    problem = _normal_problem(model.vector(surface.normal, model.constant_in_motion), model.parameter_values, item)
    if problem:
        model.problems.append(problem)
        return ()
    normal, height = _plane(surface, model, reference)
    if item.wheel and _lies_flat(body.unit(item.wheel[1]), normal, reference):
        model.problems.append(Problem(item.loc.child("wheel") if item.loc else None,
                                      f"the wheel's axis '{item.wheel[1]}' is along the surface normal at the "
                                      "initial state: a wheel lying flat has no lowest rim point to roll on",
                                      "choose the axis about which the wheel turns (e.g. axis: y for a disc "
                                      "standing on the ground), or start it upright"))
        return ()
    offset = (_wheel_offset(body, model.expr(item.wheel[0], check=model.constant_in_motion), item.wheel[1],
                            normal, reference)
              if item.wheel else Vector.of(model.vector(item.contact, model.no_velocities)))
    contact = body.material_point(offset)
    slip = contact.velocity - _surface_velocity(surface, model, normal, contact.position)
    tangents, normal_axis = _tangents(normal, model.parameter_values, reference)
    prefix = rolling_row_prefix(item.body)
    rows = [ConstraintSpec(prefix + axis, _grouped(slip.dot(t), set(model.qd)), item.loc)
            for axis, t in tangents]
    gap = normal.dot(contact.position) - height
    if not numerically_zero([gap]):
        rows.insert(0, ConstraintSpec(prefix + normal_axis, gap, item.loc))
    return tuple(rows)


def _lies_flat(axis: Vector, normal: Vector, reference: dict) -> bool:
    """The wheel's axis is (numerically) the normal at `reference`: 1 - (n.a)^2 = 0."""
    try:
        return abs(value_at(sp.sympify(1 - normal.dot(axis) ** 2), reference, {})) < 1e-12
    except (ConstantError, TypeError, ValueError, ArithmeticError):
        return False


def _normal_problem(normal, values: dict, item: Rolling) -> Problem | None:
    """A surface normal that is not a finite, real, non-zero vector at the parameters' values
    (sqrt(1 - a) with a = 2 is complex there): no plane to roll on."""
    try:
        numbers = [value_at(c, values, {}) for c in normal]
    except (ConstantError, TypeError, ValueError, ArithmeticError):
        numbers = None
    loc = item.loc.child("surface").child("normal") if item.loc else None
    if numbers is None:
        return Problem(loc, "the surface normal is not a finite real vector at the parameters' values",
                       "the normal must be a real direction: check the parameters it uses")
    if not any(numbers):
        return Problem(loc, "the surface normal is the zero vector at the parameters' values",
                       "give the direction out of the surface, e.g. normal: [0, 0, 1]")
    return None


def rolling_contact(item: Rolling, model) -> RollingContact:
    """The element as pictures need it (`lagcli.viz.animate` draws the wheel and the plane)."""
    surface = item.surface or GROUND
    if _normal_problem(model.vector(surface.normal, model.constant_in_motion), model.parameter_values, item):
        surface = GROUND        # refused by rolling_constraints: the model is not built
    normal, height = _plane(surface, model, reference_state(model))
    radius = model.expr(item.wheel[0], check=model.constant_in_motion) if item.wheel else None
    return RollingContact(item.body, radius, item.wheel[1] if item.wheel else None,
                          sp.ImmutableMatrix(normal.components), height)


def _plane(surface: Surface, model, reference: dict) -> tuple[Vector, sp.Expr]:
    """The surface's unit normal n and height h (the plane n . X = h)."""
    normal = _unit(Vector.of(model.vector(surface.normal, model.constant_in_motion)), reference)
    return normal, model.expr(surface.height, sp.S.Zero, model.constant_in_motion)


def _wheel_offset(body, radius: sp.Expr, axis: str, normal: Vector, reference: dict) -> Vector:
    a = body.unit(axis)
    along_axis = normal.dot(a)
    # |n - (n.a) a| = sqrt(1 - (n.a)^2) for unit n and a: the short form of the length
    in_plane = Vector(tuple(_tidy(c) for c in (normal - a.scaled(along_axis)).components))
    return in_plane.scaled(-radius / root(1 - along_axis**2, reference))


def _grouped(row: sp.Expr, velocities: set) -> sp.Expr:
    """A row as a textbook writes it: the plain velocity terms (x_dot) and the terms free
    of velocities apart, the common factor of the others pulled out
    (`x_dot - r*(phi_dot*cos(psi) + ...)`); small rows only."""
    if row.count_ops() > 4 * ROOT_MAX_OPS:
        return row
    terms = sp.Add.make_args(sp.expand(row))
    plain = [term for term in terms
             if term in velocities or -term in velocities or not term.free_symbols & velocities]
    rest = sp.Add(*[term for term in terms if term not in plain])
    return sp.Add(*plain) + sp.factor_terms(rest, sign=True)


def _tidy(value: sp.Expr) -> sp.Expr:
    """`value` with sin(x)**2 or cos(x)**2 of one argument x rewritten by the Pythagorean
    identity where that makes it shorter (`1 - sin(theta)**2` -> cos(theta)**2); small
    values only (a targeted rewrite: sympy's trigsimp turns products into sums of angles)."""
    if value.count_ops() > ROOT_MAX_OPS:
        return value
    best = value
    for x in sorted({f.args[0] for f in value.atoms(sp.sin, sp.cos)}, key=sp.default_sort_key):
        for square, other in ((sp.sin(x)**2, sp.cos(x)**2), (sp.cos(x)**2, sp.sin(x)**2)):
            candidate = sp.expand(best.subs(square, 1 - other))
            if sp.count_ops(candidate) < sp.count_ops(best):
                best = candidate
    return sp.factor_terms(best)


def _surface_velocity(surface: Surface, model, normal: Vector, where: Vector) -> Vector:
    if surface.angular_velocity is None:
        return ZERO
    rate = model.expr(surface.angular_velocity, check=model.no_velocities)
    centre = Vector.of(model.vector(surface.centre, model.constant_in_motion)) if surface.centre else ZERO
    return normal.scaled(rate).cross(where - centre)


def _unit(vector: Vector, reference: dict) -> Vector:
    length = root(vector.dot(vector), reference)
    return vector if length == 1 else vector.scaled(1 / length)


def reference_state(model) -> dict:
    """The parameters' values and the spec's initial coordinates (0 where not given):
    where `root` takes the sign of what it un-squares."""
    initial = model.spec_initial_values()
    return {**model.parameter_values, **{q: initial.get(q.name, 0.0) for q in model.q}}


def root(square: sp.Expr, reference: dict) -> sp.Expr:
    """sqrt(square), written as the textbook does when `square` is a perfect square c**2
    (`1 - sin(theta)**2` -> cos(theta), `cos(alpha)**2` -> cos(alpha)): |c| becomes c or -c,
    the sign c has at `reference`. The rows then hold while c keeps that sign, i.e. (for a
    wheel) while it does not lie flat, which no rolling motion passes through. Where c is 0
    at the reference, or the square is not a perfect one, the root stays as it is."""
    if square.count_ops() > ROOT_MAX_OPS:
        return sp.sqrt(square)
    length = sp.sqrt(sp.factor(_tidy(square)))
    if not length.has(sp.Abs):
        return length if not isinstance(length, sp.Pow) else sp.sqrt(square)
    signs = {a: _sign_at(a.args[0], reference) for a in length.atoms(sp.Abs)}
    if 0 in signs.values():
        return sp.sqrt(square)
    return length.xreplace({a: sign * a.args[0] for a, sign in signs.items()})


def _sign_at(value: sp.Expr, reference: dict) -> int:
    if not value.free_symbols <= set(reference):
        return 0
    number = complex(value.xreplace(reference).evalf())
    return 0 if number.imag or number.real == 0 else (1 if number.real > 0 else -1)


def _tangents(normal: Vector, values: dict, reference: dict) -> tuple[list[tuple[str, Vector]], str]:
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
        t = Vector(tuple(_tidy(c) for c in t.components))
        tangents.append((axis, _unit(t, reference)))
    return tangents, normal_axis
