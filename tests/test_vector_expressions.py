"""Vector expressions, frames and kinematic functions (docs/frames.md), checked against
sympy.physics.vector (rotation matrices and angular velocities of body-fixed rotation
chains) and against identities that do not use lagcli's kinematics (a point fixed in a
body moves with the time derivative of its position)."""
from __future__ import annotations

import pytest
import sympy as sp
import sympy.physics.vector as spv

from lagcli.derive.pipeline import load_model
from lagcli.derive import derive
from lagcli.errors import SpecError

SPEC = """
coordinates: [x, y, psi, theta, phi]
parameters: {m: 1.0, r: 0.3, h: 0.2, k: 2.0, tau: 0.5}
frames:
  C: {rotations: [[z, psi], [x, theta]]}
  D: {parent: C, rotations: [[y, phi]]}
definitions:
  P: '[x, y, r*cos(theta)]'
bodies:
  disc: {mass: m, inertia: [1, 2, 3], position: P, frame: D}
"""


def model_with(tmp_path, extra: str = "", text: str = SPEC):
    path = tmp_path / "spec.yaml"
    path.write_text(text + extra)
    return load_model(str(path))


def oracle(model):
    """sympy.physics.vector's frames for the same chain, as functions of time."""
    t = spv.dynamicsymbols._t
    psi, theta, phi = spv.dynamicsymbols("psi theta phi")
    N = spv.ReferenceFrame("N")
    C = N.orientnew("C", "Body", (psi, theta, 0), "ZXY")
    D = C.orientnew("D", "Axis", (phi, C.y))
    names = (("psi", psi), ("theta", theta), ("phi", phi))
    plain = [(f.diff(t), model.symbol(f"{n}_dot")) for n, f in names] + \
            [(f, model.symbol(n)) for n, f in names]  # in this order: rates before angles
    return N, D, plain


def components(vector, frame, plain):
    return sp.Matrix([vector.dot(u) for u in (frame.x, frame.y, frame.z)]).subs(plain)


def test_unit_vectors_and_angular_velocity_match_sympy_physics_vector(tmp_path, assert_zero):
    model = model_with(tmp_path, """
constraints:
  - {name: ux, expr: 'dot(D_x, [1, 0, 0]) + 2*dot(D_y, [0, 1, 0]) + 3*dot(D_z, [0, 0, 1])'}
  - {name: w, expr: 'dot(angular_velocity(D), [1, 2, 3])'}
  - {name: wb, expr: 'dot(angular_velocity(disc), [3, 2, 1])'}
""")
    N, D, plain = oracle(model)
    rows = {c.label: c.expr for c in model.constraints}
    expected_units = D.x.dot(N.x) + 2 * D.y.dot(N.y) + 3 * D.z.dot(N.z)
    assert_zero(rows["ux"] - expected_units.subs(plain), "unit vectors")
    omega = components(D.ang_vel_in(N), N, plain)
    expected = omega[0] + 2 * omega[1] + 3 * omega[2]
    assert_zero(rows["w"] - expected, "angular_velocity(D)")
    assert_zero(rows["wb"] - (3 * omega[0] + 2 * omega[1] + omega[2]), "angular_velocity(disc)")


def test_body_point_velocity_is_the_rate_of_a_body_fixed_point(tmp_path, ddt, assert_zero):
    """v_B + w x r for r fixed in the body (written with its unit vectors) equals d/dt of
    its position; cross and position agree with the components written out. (The rows
    come from two specs: in one, the velocity row would be the position row's time
    derivative, a dependent row, which lagcli drops.)"""
    model = model_with(tmp_path, """
constraints:
  - {name: v, expr: 'dot(velocity(point(disc, h*D_z + r*D_x)), [1, 2, 3])'}
  - {name: c, expr: 'dot(cross(D_x, D_y), D_z)*x'}
""")
    rows = {c.label: c.expr for c in model.constraints}
    rows["p"] = model_with(tmp_path, """
constraints:
  - {name: p, expr: 'dot(position(point(disc, h*D_z + r*D_x)), [1, 2, 3])'}
""").constraints[0].expr
    assert_zero(rows["v"] - ddt(model, rows["p"]), "material point velocity")
    assert_zero(rows["c"] - model.symbol("x"), "right-handed frame")   # (D_x x D_y) . D_z = 1


def test_one_line_no_slip_equals_the_rolling_element(tmp_path, assert_zero):
    """The rolling element's row and the same condition written with velocity(): the rim
    point closest to the ground is centre - r k, k = (e_z - (e_z.a) a)/cos(theta), a = D_y."""
    wheel = model_with(tmp_path, "rolling: [{body: disc, wheel: {radius: r, axis: y}}]\n")
    by_hand = model_with(tmp_path, """
constraints:
  - 'dot(velocity(point(disc, -r*([0, 0, 1] - dot([0, 0, 1], D_y)*D_y)/cos(theta))), [1, 0, 0])'
""")
    row = next(c.expr for c in wheel.constraints if c.label == "rolling_disc_x")
    assert_zero(row - by_hand.constraints[0].expr, "rolling_disc_x")


def test_vector_torque_spring_and_force_equal_the_component_forms(tmp_path, assert_zero):
    """A torque, a force at a body point and a spring end given as vector expressions
    derive the same forcing as with every component written out by hand."""
    common = SPEC.replace("frames:", "gravity: [0, 0, -9.81]\nframes:")
    vector = model_with(tmp_path, """
forces:
  - {body: disc, torque: tau*C_z}
  - {point: P + h*D_z, force: k*D_x}
springs:
  - {between: [disc, '[0, 0, 1] + h*[1, 0, 0]'], stiffness: k}
""", common)
    cx, cz = "[cos(psi), sin(psi), 0]", "[sin(psi)*sin(theta), -cos(psi)*sin(theta), cos(theta)]"
    dx, dz = f"(cos(phi)*{cx} - sin(phi)*{cz})", f"(sin(phi)*{cx} + cos(phi)*{cz})"
    by_hand = model_with(tmp_path, f"""
forces:
  - {{body: disc, torque: [tau*sin(psi)*sin(theta), -tau*cos(psi)*sin(theta), tau*cos(theta)]}}
  - {{point: 'P + h*{dz}', force: 'k*{dx}'}}
springs:
  - {{between: [disc, [h, 0, 1]], stiffness: k}}
""", common)
    assert_zero(derive(vector).forcing - derive(by_hand).forcing, "forcing")


@pytest.mark.parametrize("extra, message", [
    ("constraints: ['[1, 0, 0]']\n", "is a vector where a scalar is needed"),
    ("constraints: ['dot(D_x, 1)']\n", "is a scalar where a vector is needed"),
    ("constraints: ['velocity(D)']\n", "velocity() needs a particle, a body or point(B, r)"),
    ("constraints: ['angular_velocity(P)']\n", "angular_velocity() needs a frame or a body"),
    ("constraints: ['dot(D_x, [1, 0])']\n", "a vector literal has 3 components"),
    ("constraints: ['D_x**2']\n", "does not apply to vectors"),
    ("constraints: ['disc + 1']\n", "'disc' is a body, not a value"),
])
def test_misuse_is_a_located_error_with_a_hint(tmp_path, extra, message):
    with pytest.raises(SpecError) as error:
        model_with(tmp_path, extra)
    text = str(error.value)
    assert message in text and "constraints[0]" in text and "spec.yaml:" in text


def test_velocity_in_a_force_gives_the_viscous_generalized_force(tmp_path, assert_zero):
    """A drag force -c velocity(P) on a pendulum bob: Q_theta = -c l^2 theta_dot."""
    model = model_with(tmp_path, "", """
coordinates: [theta]
parameters: {m: 1.0, l: 0.7, c: 0.3}
particles:
  P: {mass: m, position: '[l*sin(theta), -l*cos(theta), 0]'}
forces:
  - {at: P, force: -c*velocity(P)}
""")
    d = derive(model)
    l, c, theta_dot = (model.symbol(n) for n in ("l", "c", "theta_dot"))
    assert_zero(d.forcing[0] + c * l**2 * theta_dot, "Q_theta")
