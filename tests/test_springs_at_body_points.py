"""Planar springs and dampers attached at a point of a body off its centre: an end may be a
position that moves with the coordinates (issue 25: it was taken for a fixed point and the
spring refused as "between two fixed points"). Checked against the closed forms
V = k (|P - A| - L0)^2 / 2 and Q'_j = -dR/dq'_j with R = c (dL/dt)^2 / 2, built here
with sympy from the geometry alone."""
from __future__ import annotations

import sympy as sp

import lagcli

SPEC = """coordinates: [x, theta]
parameters: {m: 1.0, I: 0.2, k: 3.0, l: 0.5, L0: 0.3, c: 0.4}
bodies:
  B: {mass: m, inertia: I, position: [x, 0], angle: theta}
springs:
  - {between: [[x + l*cos(theta), l*sin(theta)], [2, 1]], stiffness: k, rest_length: L0}
dampers:
  - {between: [[x - l*cos(theta), -l*sin(theta)], [-2, 0]], damping: c}
initial: {x: 0.1, theta: 0.3}
"""


def test_a_spring_and_a_damper_at_points_of_a_body_follow_the_closed_form():
    d = lagcli.load(SPEC).derivation
    model = d.model
    x, th = model.q
    xd, thd = model.qd
    k, l, L0, c = (model.symbol(n) for n in ("k", "l", "L0", "c"))
    spring_end = sp.Matrix([x + l * sp.cos(th), l * sp.sin(th)])
    V = k * (sp.sqrt((spring_end - sp.Matrix([2, 1])).dot(spring_end - sp.Matrix([2, 1]))) - L0) ** 2 / 2
    damper_end = sp.Matrix([x - l * sp.cos(th), -l * sp.sin(th)])
    length = sp.sqrt((damper_end - sp.Matrix([-2, 0])).dot(damper_end - sp.Matrix([-2, 0])))
    rate = sum(length.diff(q) * v for q, v in ((x, xd), (th, thd)))
    R = c * rate ** 2 / 2
    point = {x: 0.37, th: -0.8, xd: 1.3, thd: 0.7, k: 3.0, l: 0.5, L0: 0.3, c: 0.4}
    assert abs(float((d.V - V).subs(point))) < 1e-12
    for j, v in enumerate((xd, thd)):
        assert abs(float((d.nonconservative_forces[j] + R.diff(v)).subs(point))) < 1e-12
