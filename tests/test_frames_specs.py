"""Specs written with frames, vector expressions and rolling elements against their long forms.

Each `*_frames` bundled spec describes the same system as a long-form spec that spells
out rotation matrices and no-slip rows by hand. They must give the same equations:
at seeded random states the same mass matrix M and forcing F, the same constraint
rows (A and bias, row by row, with the sign each spec's header documents), and at
seeded random states made consistent with the constraints the same q'' and
multipliers, from the augmented system [[M, -A^T], [A, 0]] [q''; lambda] = [F; bias],
all to 1e-12 (relative). The short forms are at most a third of the long forms'
lines (comments and blank lines not counted).

The sphere on a turntable is checked against the classic result: its centre moves
on a circle at the angular velocity 2 W / 7 (its velocity turns at that rate and
keeps its length).
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from conftest import spec_path

TOL = 1e-12

# long form, short form, {long multiplier: (short multiplier, sign)}, coordinate fixed by
# the holonomic rows (solved by Newton to make a state consistent), or None
CASES = {
    "rolling_disc": ("rolling_disc", "rolling_disc_frames",
                     {"lambda_roll_x": ("lambda_rolling_disc_x", 1),
                      "lambda_roll_y": ("lambda_rolling_disc_y", 1)}, None),
    "top": ("heavy_symmetric_top", "heavy_symmetric_top_frames", {}, None),
    "ex6_9": ("ex6_9_two_wheels_axle", "ex6_9_two_wheels_axle_frames", {"lambda_1": ("lambda_1", 1)}, None),
    "bicycle": ("benchmark_bicycle", "benchmark_bicycle_frames",
                {"lambda_front_ground": ("lambda_rolling_front_wheel_z", -1),
                 "lambda_rear_x": ("lambda_rolling_rear_wheel_x", 1),
                 "lambda_rear_y": ("lambda_rolling_rear_wheel_y", 1),
                 "lambda_front_x": ("lambda_rolling_front_wheel_x", 1),
                 "lambda_front_y": ("lambda_rolling_front_wheel_y", 1)}, "theta"),
}
PARAMS = [pytest.param(key, marks=pytest.mark.slow) if key == "bicycle" else key for key in CASES]


class Numeric:
    """M, F, A, bias of a derivation as numpy functions of (q, q'), parameters at their defaults."""

    def __init__(self, d):
        model = d.model
        self.q, self.qd = list(model.q), list(model.qd)
        values = {p.symbol: sp.Float(p.value) for p in model.parameters}
        args = [self.q, self.qd]
        compile_ = lambda m: sp.lambdify(args, sp.Matrix(m).xreplace(values), modules="numpy", cse=True)
        self.M, self.F = compile_(d.mass_matrix), compile_(d.forcing)
        self.names = [str(m) for m in d.multipliers]
        self.holonomic = [row.expr for row in d.constraints if row.kind == "holonomic"]
        if self.names:
            self.A, self.bias = compile_(d.constraint_matrix), compile_(d.constraint_bias)
        self.values = values

    def rows(self, q, qd) -> tuple[np.ndarray, np.ndarray]:
        if not self.names:
            return np.zeros((0, len(self.q))), np.zeros(0)
        return self.A(q, qd).reshape(len(self.names), -1), self.bias(q, qd).ravel()

    def solve(self, q, qd) -> tuple[np.ndarray, np.ndarray]:
        M, F = self.M(q, qd), self.F(q, qd).ravel()
        A, bias = self.rows(q, qd)
        m = len(self.names)
        K = np.block([[M, -A.T], [A, np.zeros((m, m))]])
        sol = np.linalg.solve(K, np.concatenate([F, bias]))
        return sol[:len(self.q)], sol[len(self.q):]


def close(a, b) -> bool:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return np.max(np.abs(a - b), initial=0.0) <= TOL * (1 + np.max(np.abs(a), initial=0.0))


@pytest.fixture(scope="module")
def pairs(request):
    cache = {}

    def get(key, derived):
        if key not in cache:
            long_name, short_name, rows, fixed = CASES[key]
            cache[key] = (Numeric(derived(long_name)), Numeric(derived(short_name)), rows, fixed)
        return cache[key]
    return get


def random_state(long, rng, fixed):
    """q, q' at random, then on the constraints: the `fixed` coordinate by Newton on the
    holonomic row, the velocities projected on the null space of A."""
    n = len(long.q)
    q, qd = rng.uniform(-0.6, 0.6, n), rng.uniform(-1.0, 1.0, n)
    if fixed:
        k = [s.name for s in long.q].index(fixed)
        row = long.holonomic[0].xreplace(long.values)
        phi = sp.lambdify([long.q], row)
        slope = sp.lambdify([long.q], row.diff(long.q[k]))
        for _ in range(50):
            step = phi(q) / slope(q)
            q[k] -= step
            if abs(step) < 1e-15:
                break
    A, _ = long.rows(q, qd)
    if len(A):
        qd = qd - np.linalg.pinv(A) @ (A @ qd)
    return q, qd


@pytest.mark.parametrize("key", PARAMS)
def test_same_mass_matrix_forcing_and_rows(key, derived, pairs):
    long, short, row_map, _ = pairs(key, derived)
    assert [s.name for s in long.q] == [s.name for s in short.q]
    assert sorted(short.names) == sorted(name for name, _ in row_map.values())
    rng = np.random.default_rng(11)
    for _ in range(5):
        q, qd = rng.uniform(-1.0, 1.0, len(long.q)), rng.uniform(-1.0, 1.0, len(long.q))
        assert close(long.M(q, qd), short.M(q, qd))
        assert close(long.F(q, qd), short.F(q, qd))
        (A_long, b_long), (A_short, b_short) = long.rows(q, qd), short.rows(q, qd)
        for i, name in enumerate(long.names):
            other, sign = row_map[name]
            j = short.names.index(other)
            assert close(A_long[i], sign * A_short[j]), name
            assert close(b_long[i], sign * b_short[j]), name


@pytest.mark.parametrize("key", PARAMS)
def test_same_accelerations_and_multipliers_on_the_constraints(key, derived, pairs):
    long, short, row_map, fixed = pairs(key, derived)
    rng = np.random.default_rng(20261122)
    for _ in range(5):
        q, qd = random_state(long, rng, fixed)
        A, _ = long.rows(q, qd)
        assert np.max(np.abs(A @ qd), initial=0.0) < 1e-12
        qdd_long, lam_long = long.solve(q, qd)
        qdd_short, lam_short = short.solve(q, qd)
        assert close(qdd_long, qdd_short)
        for i, name in enumerate(long.names):
            other, sign = row_map[name]
            assert close(lam_long[i], sign * lam_short[short.names.index(other)]), name


def meaningful_lines(name: str) -> int:
    lines = spec_path(name).read_text().splitlines()
    return sum(1 for line in lines if line.strip() and not line.lstrip().startswith("#"))


@pytest.mark.parametrize("key", ["rolling_disc", "bicycle"])
def test_short_form_is_at_most_a_third_of_the_long_form(key):
    long_name, short_name, _, _ = CASES[key]
    assert 3 * meaningful_lines(short_name) <= meaningful_lines(long_name)


def test_sphere_on_turntable_centre_circles_at_two_sevenths_of_the_rate():
    import lagcli

    system = lagcli.load(spec_path("sphere_on_turntable"))
    rate = 2 * system.model.parameter_values[system.model.symbol("W")] / 7
    trajectory = system.simulate(t_end=1.5, dt=0.05)
    t = trajectory.t
    vx, vy = trajectory["x_dot"], trajectory["y_dot"]
    heading = np.unwrap(np.arctan2(vy, vx))
    assert np.max(np.abs(heading - heading[0] - rate * t)) < 1e-7
    assert np.max(np.abs(np.hypot(vx, vy) - np.hypot(vx[0], vy[0]))) < 1e-9
    # and the circle does not move: its centre is position + (e_z x v) / rate
    cx, cy = trajectory["x"] - vy / rate, trajectory["y"] + vx / rate
    assert np.ptp(cx) < 1e-7 and np.ptp(cy) < 1e-7


def test_sphere_on_an_incline_rolls_down_at_five_sevenths_of_g_sin_alpha(tmp_path, augmented):
    """A tilted plane (normal not along an axis): from rest, a uniform sphere's centre
    accelerates down the slope at (5/7) g sin(alpha) (closed form), the normal row's
    multiplier is the normal force m g cos(alpha) and the friction is (2/7) m g sin(alpha)
    up the slope."""
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive

    path = tmp_path / "incline.yaml"
    path.write_text("""
coordinates: [x, y, z, a, b, c]
parameters: {m: 2.0, r: 0.3, g: 9.81, al: 0.4}
gravity: [0, 0, -g]
frames: {S: {rotations: [[x, a], [y, b], [z, c]]}}
bodies:
  ball: {mass: m, inertia: [2*m*r**2/5, 2*m*r**2/5, 2*m*r**2/5], position: [x, y, z], frame: S}
rolling:
  - {body: ball, contact: '-r*[-sin(al), 0, cos(al)]', surface: {normal: [-sin(al), 0, cos(al)]}}
""")
    d = derive(load_model(str(path)))
    assert [str(m) for m in d.multipliers] == ["lambda_rolling_ball_z", "lambda_rolling_ball_x",
                                                "lambda_rolling_ball_y"]
    m, r, g, al = 2.0, 0.3, 9.81, 0.4
    symbols = {s.name: s for s in (*d.model.q, *d.model.qd)}
    state = {symbols[n]: 0.0 for n in symbols}
    state[symbols["x"]], state[symbols["z"]] = -r * np.sin(al), r * np.cos(al)
    qdd, lam = augmented(d, state)
    down = -np.array([np.cos(al), 0.0, np.sin(al)])
    assert np.allclose(qdd[:3], 5 / 7 * g * np.sin(al) * down, rtol=0, atol=1e-12)
    assert abs(lam[0] - m * g * np.cos(al)) < 1e-12
    assert abs(lam[1] - 2 / 7 * m * g * np.sin(al)) < 1e-12  # t_x = (cos al, 0, sin al): up the slope
    assert abs(lam[2]) < 1e-12
