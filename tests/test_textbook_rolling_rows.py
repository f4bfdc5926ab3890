"""Rolling rows as a textbook writes them (issue 21: "textbook rolling rows").

A `rolling:` element finds the contact point with the length |n - (n.a) a| =
sqrt(1 - (n.a)^2) and unit tangents of the plane. Where these are perfect squares
(a disc on a level plane: sqrt(1 - sin(theta)^2); a tilted plane's tangent:
sqrt(cos(alpha)^2)) the rows carry cos(theta), cos(alpha) with the sign they have at
the spec's initial state and parameter values — the stated assumption: the wheel does
not lie flat (docs/frames.md, "Rolling").

- The frames and long forms of the bundled rolling specs print the SAME rows (the JSON
  `expr`, `a` and `d` of every constraint, string for string).
- No sqrt(1 - sin(x)**2) and no x/Abs(x) is left in their reports.
- The sign rule against an independent computation: the no-slip velocity of the rim
  point closest to the ground, found numerically with numpy (the lowest point of the
  rim circle), for a disc leaning either way and for one started upside down
  (cos(theta) < 0 at the initial state, where the textbook form takes -cos(theta)).
"""
from __future__ import annotations

import json

import numpy as np
import pytest

import lagcli
from conftest import spec_path

PAIRS = [("rolling_disc", "rolling_disc_frames"),
         ("ex6_9_two_wheels_axle", "ex6_9_two_wheels_axle_frames")]


def rows(name: str) -> list:
    report = json.loads(lagcli.load(spec_path(name)).report("json"))
    return [(c["expr"], c["a"], c["d"]) for c in report["constraints"]]


@pytest.mark.parametrize("long,short", PAIRS)
def test_frames_and_long_form_print_the_same_rows(long, short):
    assert rows(long) == rows(short)


@pytest.mark.parametrize("name", ["rolling_disc_frames", "sphere_on_turntable"])
def test_no_absolute_values_or_roots_of_squares_in_rolling_reports(name):
    system = lagcli.load(spec_path(name))
    for text in (system.report("text"), system.report("latex")):
        assert "sqrt(1 - sin" not in text and "Abs(" not in text and r"\left|" not in text


DISC = """
coordinates: [x, y, psi, theta, phi]
parameters: {{m: 1.0, r: 0.3, g: 9.81}}
gravity: [0, 0, -g]
frames: {{D: {{rotations: [[z, psi], [x, theta], [y, phi]]}}}}
bodies:
  disc: {{mass: m, inertia: [m*r**2/4, m*r**2/2, m*r**2/4], position: [x, y, {height}], frame: D}}
rolling: [{{body: disc, wheel: {{radius: r, axis: y}}}}]
initial: {{theta: {theta}}}
"""


def rim_contact_slip(state: dict, r: float) -> np.ndarray:
    """The velocity of the disc's material point lowest on the rim, numerically: the rim
    point cos(a) e1 + sin(a) e3 with the least z (a = atan2(e3_z, e1_z) + pi), then
    v_C = v_B + w x (C - B), w from dR/dt R^T by central differences."""
    def rot(axis, angle):
        c, s = np.cos(angle), np.sin(angle)
        i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
        m = np.eye(3)
        m[i, i] = m[j, j] = c
        m[i, j], m[j, i] = -s, s
        return m

    psi, theta, phi = state["psi"], state["theta"], state["phi"]
    R = rot("z", psi) @ rot("x", theta) @ rot("y", phi)
    e1, e3 = R[:, 0], R[:, 2]                        # the disc's plane (its axis is R[:, 1])
    lowest = np.arctan2(e3[2], e1[2]) + np.pi
    offset = r * (np.cos(lowest) * e1 + np.sin(lowest) * e3)
    h = 1e-5
    rates = {k: state[k + "_dot"] for k in ("psi", "theta", "phi")}
    turned = lambda s: (rot("z", psi + s * rates["psi"]) @ rot("x", theta + s * rates["theta"])
                        @ rot("y", phi + s * rates["phi"]))
    W = (turned(h) - turned(-h)) / (2 * h) @ R.T
    omega = np.array([W[2, 1], W[0, 2], W[1, 0]])
    v_body = np.array([state["x_dot"], state["y_dot"], -r * np.sin(theta) * state["theta_dot"]])
    return v_body + np.cross(omega, offset)


@pytest.mark.parametrize("theta0", [0.3, -0.4, 2.5])
def test_rows_are_the_no_slip_velocity_of_the_lowest_rim_point(theta0):
    """The rows' values equal the slip velocity found numerically, for states near the
    initial one (the sign of cos(theta) taken there: upright or upside down)."""
    height = "r*cos(theta)" if np.cos(theta0) > 0 else "-r*cos(theta)"
    system = lagcli.load(DISC.format(theta=theta0, height=height))
    d = system.derivation
    rng = np.random.default_rng(7)
    for _ in range(5):
        state = {"x": 0.1, "y": -0.2, "psi": rng.uniform(-3, 3), "theta": theta0 + rng.uniform(-0.2, 0.2),
                 "phi": rng.uniform(-3, 3)}
        state.update({k + "_dot": rng.uniform(-2, 2) for k in ("x", "y", "psi", "theta", "phi")})
        values = {p.symbol: p.value for p in d.model.parameters}
        values.update({s: state[s.name] for s in (*d.model.q, *d.model.qd)})
        rows = [float(row.expr.xreplace(values)) for row in d.constraints]
        slip = rim_contact_slip(state, 0.3)
        assert np.allclose(rows, slip[:2], atol=1e-8), (rows, slip)
