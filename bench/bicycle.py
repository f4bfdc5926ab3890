"""A bicycle-sized spatial system as a spec (for bench/whole_command.py).

Four spatial bodies (rear wheel, frame, fork, front wheel), eight coordinates
(x, y, yaw psi, lean theta, rear spin phi, frame pitch beta, steer delta, front
spin phi_f) and five constraints: the rear wheel rolls without slipping (two
nonholonomic rows, as in specs/rolling_disc.yaml), the front wheel rolls on a
knife edge below its centre (two nonholonomic rows) and that centre stays at
height r_f (one holonomic row). Not a validated Whipple model (the front contact
is the point below the centre, exact only upright): a system of the Whipple
bicycle's size and structure, to time whole commands.

    python bench/bicycle.py > bench/specs/bicycle.yaml
"""
from __future__ import annotations

import sympy as sp

from lagcli.render.spec_printer import spec_str

COORDINATES = ("x", "y", "psi", "theta", "phi", "beta", "delta", "phi_f")
PARAMETERS = {"g": 9.81, "r": 0.3, "r_f": 0.35, "m_r": 2.0, "m_b": 85.0, "m_h": 4.0, "m_f": 3.0,
              "b_x": 0.3, "b_z": -0.9, "h_x": 0.9, "h_z": -0.8, "f_x": 0.02, "f_z": 0.2,
              "lam": 0.31}


def _rotation(axis: str, angle):
    c, s = sp.cos(angle), sp.sin(angle)
    return {"x": sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def bicycle_spec_text() -> str:
    q = {name: sp.Symbol(name, real=True) for name in COORDINATES}
    qd = {name: sp.Symbol(f"{name}_dot", real=True) for name in COORDINATES}
    p = {name: sp.Symbol(name, real=True) for name in PARAMETERS}
    rear_axes = [("z", q["psi"]), ("x", q["theta"])]
    frame_axes = rear_axes + [("y", q["beta"])]
    fork_axes = frame_axes + [("y", p["lam"]), ("z", q["delta"])]
    R_lean = _rotation("z", q["psi"]) * _rotation("x", q["theta"])
    R_frame = R_lean * _rotation("y", q["beta"])
    R_fork = R_frame * _rotation("y", p["lam"]) * _rotation("z", q["delta"])
    rear = sp.Matrix([q["x"], q["y"], p["r"] * sp.cos(q["theta"])])
    frame = rear + R_frame * sp.Matrix([p["b_x"], 0, p["b_z"]])
    head = rear + R_frame * sp.Matrix([p["h_x"], 0, p["h_z"]])
    fork = head + R_fork * sp.Matrix([p["f_x"], 0, p["f_z"]])
    front = head + R_fork * sp.Matrix([2 * p["f_x"], 0, 2 * p["f_z"]])
    # Front knife edge: the material point below the centre has no horizontal velocity.
    # omega = sum of each rate about its axis, rotated by the rotations before it
    R_yaw = _rotation("z", q["psi"])
    omega = (qd["psi"] * sp.Matrix([0, 0, 1]) + qd["theta"] * R_yaw * sp.Matrix([1, 0, 0])
             + qd["beta"] * R_lean * sp.Matrix([0, 1, 0]) + qd["delta"] * R_fork * sp.Matrix([0, 0, 1])
             + qd["phi_f"] * R_fork * sp.Matrix([0, 1, 0]))
    front_velocity = sum((front.diff(q[n]) * qd[n] for n in COORDINATES), sp.zeros(3, 1))
    slip = front_velocity + omega.cross(sp.Matrix([0, 0, -p["r_f"]]))

    def vec(v):
        return "[" + ", ".join(spec_str(e) for e in v) + "]"

    def orient(axes):
        return "[" + ", ".join(f"[{axis}, {spec_str(angle)}]" for axis, angle in axes) + "]"

    lines = ["name: bicycle_like",
             "description: A bicycle-sized spatial system (rear wheel, frame, fork, front wheel)",
             f"coordinates: [{', '.join(COORDINATES)}]", "parameters:"]
    lines += [f"  {name}: {value}" for name, value in PARAMETERS.items()]
    lines += ["gravity: [0, 0, -g]", "bodies:"]
    bodies = [("rear_wheel", "m_r", "[m_r*r**2/4, m_r*r**2/2, m_r*r**2/4]", rear, rear_axes + [("y", q["phi"])]),
              ("frame", "m_b", "[9.2, 11.0, 2.8]", frame, frame_axes),
              ("fork", "m_h", "[0.06, 0.08, 0.02]", fork, fork_axes),
              ("front_wheel", "m_f", "[m_f*r_f**2/4, m_f*r_f**2/2, m_f*r_f**2/4]", front,
               fork_axes + [("y", q["phi_f"])])]
    for name, mass, inertia, position, axes in bodies:
        lines += [f"  {name}:", f"    mass: {mass}", f"    inertia: {inertia}",
                  f"    position: {vec(position)}", f"    orientation: {orient(axes)}"]
    lines += ["constraints:",
              "  - name: rear_x",
              "    expr: x_dot - r*(psi_dot*cos(psi)*sin(theta) + theta_dot*sin(psi)*cos(theta) + phi_dot*cos(psi))",
              "  - name: rear_y",
              "    expr: y_dot - r*(psi_dot*sin(psi)*sin(theta) - theta_dot*cos(psi)*cos(theta) + phi_dot*sin(psi))",
              f"  - name: front_x\n    expr: {spec_str(slip[0])}",
              f"  - name: front_y\n    expr: {spec_str(slip[1])}",
              f"  - name: front_height\n    expr: {spec_str(front[2] - p['r_f'])}"]
    lines += ["initial: {theta: 0.0, beta: 0.0, phi_dot: 10.0, x_dot: 3.0}"]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(bicycle_spec_text(), end="")
