"""`rest: true` on an impact event: the contact is held as a constraint while it pushes
(after the accumulation of its bounces, or from the start when the run begins resting on
it) and released where it would pull (lagcli/run/contact.py), on the Python backend.

Closed forms, independent of lagcli:
- a ball dropped from rest at h0 first lands at t0 = sqrt(2 h0 / g) with speed v0 = g t0;
  each bounce leaves with e times the speed it came with and flies 2 v / g, so the bounces
  accumulate at t_inf = t0 + sum_k 2 e^k v0 / g = t0 + 2 v0 e / (g (1 - e)); from then on
  it lies on the floor, pressed by N = m g;
- a block on a floor pulled up by F = k t: N = m g - k t while it rests; it lifts off at
  t_L = m g / k and then y = k (t - t_L)^3 / (6 m);
- a particle sliding from the top of a sphere of radius R with speed v0 leaves it where
  N = m g cos(theta) - m v^2 / R = 0 with v^2 = v0^2 + 2 g R (1 - cos(theta)):
  cos(theta_L) = (2 + v0^2 / (g R)) / 3; then it flies on a parabola;
- a pendulum pressed against a wall at theta = alpha by a torque tau = tau0 - c t: the
  wall's reaction torque is tau - m g l sin(alpha) until it lets go at
  t_R = (tau0 - m g l sin(alpha)) / c;
- a Cartesian pendulum resting on a frictionless floor: N = m g and the rod's multiplier 0.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import lagcli

from test_hybrid_events import HYBRID, run

SPEC = HYBRID / "bouncing_ball_rest.yaml"
LIFT_OFF = HYBRID / "block_lift_off.yaml"


def test_the_ball_rests_on_the_floor_pressed_by_m_g_from_its_accumulation_time():
    traj = lagcli.load(SPEC).simulate()
    e, g, h0, m = 0.5, 9.81, 1.0, 1.0
    t0 = math.sqrt(2 * h0 / g)
    v0 = g * t0
    t_inf = t0 + 2 * v0 * e / (g * (1 - e))
    impacts = [r.t for r in traj.events if r.action == "impact"]
    expected = [t0 + sum(2 * e ** j * v0 / g for j in range(1, k + 1)) for k in range(len(impacts))]
    assert np.allclose(impacts[:10], expected[:10], rtol=1e-9, atol=0)          # the bounces before it
    rest = traj.events[-1]
    assert (rest.name, rest.action) == ("floor", "rest") and rest.t == pytest.approx(t_inf, abs=1e-8)
    assert traj.t[-1] == 3.0 and traj.end_note is None                          # the run goes on to t_end
    resting = traj.t > t_inf + 1e-6
    assert resting.sum() > 150
    assert np.all(np.abs(traj["y"][resting]) < 1e-12)
    assert np.all(np.abs(traj["y_dot"][resting]) < 1e-12)
    assert np.allclose(traj["force_floor"][resting], m * g, rtol=1e-9, atol=0)
    assert np.all(traj["force_floor"][traj.t < t_inf - 1e-6] == 0.0)             # free: no force
    energy = traj["energy"][resting]
    assert np.all(np.abs(energy) < 1e-12) and np.ptp(energy) < 1e-12


def test_an_either_way_floor_rests_the_ball_pressed_by_m_g_too(tmp_path):
    spec = tmp_path / "either.yaml"
    spec.write_text(SPEC.read_text().replace("direction: falling", "direction: either"))
    traj = lagcli.load(spec).simulate()
    assert traj.events[-1].action == "rest" and traj.t[-1] == 3.0
    assert traj["force_floor"][-1] == pytest.approx(9.81, rel=1e-9)


def test_a_block_pulled_up_lifts_off_at_m_g_over_k_and_then_flies_freely():
    traj = lagcli.load(LIFT_OFF).simulate()
    m, g, k = 2.0, 9.81, 4.0
    t_lift = m * g / k
    assert [(r.t, r.action) for r in traj.events] == [(0.0, "rest"), (pytest.approx(t_lift, rel=1e-9), "release")]
    on, off = traj.t < t_lift, traj.t > t_lift
    assert np.allclose(traj["force_floor"][on], m * g - k * traj.t[on], rtol=0, atol=1e-9)
    assert np.all(traj["y"][on] == 0.0) and np.all(traj["force_floor"][off] == 0.0)
    assert off.sum() > 150
    assert np.allclose(traj["y"][off], k * (traj.t[off] - t_lift) ** 3 / (6 * m), rtol=1e-8, atol=1e-12)
    assert np.allclose(traj["y_dot"][off], k * (traj.t[off] - t_lift) ** 2 / (2 * m), rtol=1e-8, atol=1e-12)
    assert traj.column_info[-1].name == "force_floor" and traj.column_info[-1].unit == "N"


def test_a_block_let_fall_again_lands_and_rests_again():
    """F = k t until t = 6 s, then 0: lift-off at t_L = m g / k, free flight, at 6 s
    y_T = k (6 - t_L)^3 / (6 m), v_T = k (6 - t_L)^2 / (2 m), then a fall under gravity
    alone to the floor (e = 0: a plastic landing), where the block rests again (N = m g)."""
    m, g, k, T = 2.0, 9.81, 4.0, 6.0
    traj = lagcli.load(LIFT_OFF).simulate(t_end=8.0, inputs={"F": "k*t*max(0, sign(6 - t))"})
    t_lift = m * g / k
    y_T, v_T = k * (T - t_lift) ** 3 / (6 * m), k * (T - t_lift) ** 2 / (2 * m)
    t_land = T + (v_T + math.sqrt(v_T ** 2 + 2 * g * y_T)) / g
    assert [r.action for r in traj.events] == ["rest", "release", "impact", "rest"]
    assert traj.events[1].t == pytest.approx(t_lift, rel=1e-9)
    assert traj.events[2].t == pytest.approx(t_land, rel=1e-9) and traj.events[3].t == traj.events[2].t
    assert traj.events[2].before[1] == pytest.approx(v_T - g * (t_land - T), rel=1e-8)   # F jumps at 6 s
    again = traj.t > t_land
    assert again.sum() > 100 and traj.end_note is None
    assert np.allclose(traj["force_floor"][again], m * g, rtol=1e-9, atol=0)
    assert np.all(np.abs(traj["y"][again]) < 1e-12)


@pytest.mark.parametrize("e", [0.0, 0.5])
def test_a_shaken_block_hops_and_rests_again_and_again_never_pulled_nor_sunk(tmp_path, e):
    """F = m g (0.5 - 0.6 cos(20 t)): the floor lets go each time F exceeds m g and takes
    the block back when it lands (after its bounces accumulate, for e > 0). The floor never
    pulls (force >= 0), the block never sinks (y >= 0), the energy T + V is m g y + m v^2/2,
    and the run reaches t_end, however often the contact is held and released."""
    spec = tmp_path / "shaken.yaml"
    spec.write_text(LIFT_OFF.read_text().replace("restitution: 0", f"restitution: {e}"))
    traj = lagcli.load(spec).simulate(t_end=3.0, inputs={"F": "m*g*(0.5 - 0.6*cos(20*t))"})
    actions = [r.action for r in traj.events]
    assert actions.count("rest") >= 4 and actions.count("release") >= 4 and traj.t[-1] == 3.0
    assert traj.end_note is None and traj.failure is None
    assert np.all(traj["force_floor"] >= -1e-9) and np.all(traj["y"] >= -1e-12)
    assert np.allclose(traj["energy"], 2.0 * 9.81 * traj["y"] + traj["y_dot"] ** 2, rtol=1e-12, atol=1e-12)


def test_lift_off_on_the_command_line_logs_the_rest_and_the_release(tmp_path):
    out, log = tmp_path / "lift.csv", tmp_path / "events.csv"
    result = run("simulate", LIFT_OFF, "-o", out, "--events", log)
    assert result.exit_code == 0, result.stderr
    assert "2 events: floor rest ×1, floor release ×1, first at t = 0 s" in result.stderr
    assert out.read_text().splitlines()[0] == "t,y,y_dot,energy,force_floor"
    rows = log.read_text().splitlines()
    assert rows[0] == "t,event,action,y-,y_dot-,y+,y_dot+,impulse"
    assert rows[1] == "0,floor,rest,0,0,0,0,0"
    assert rows[2].startswith("4.90") and rows[2].split(",")[1:3] == ["floor", "release"]
    units = run("simulate", LIFT_OFF, "--units")
    assert "force_floor,contact,N" in units.stdout.splitlines()


def _spec(tmp_path, name: str, text: str):
    path = tmp_path / f"{name}.yaml"
    path.write_text(f"name: {name}\n{text}")
    return path


SPHERE = """coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, R: 1.0, v0: 0.5}
gravity: [0, -g]
particles:
  p: {mass: m, position: [x, y]}
events:
  - {name: sphere, when: sqrt(x^2 + y^2) - R, action: impact, restitution: 0, rest: true}
initial: {x: 0, y: R, x_dot: v0}
simulate: {t_end: 1.5, dt: 0.01}
"""


def test_a_particle_slides_off_a_sphere_where_cos_theta_is_two_thirds_and_more(tmp_path):
    g, R, v0 = 9.81, 1.0, 0.5
    traj = lagcli.load(_spec(tmp_path, "sphere", SPHERE)).simulate()
    rest, release = traj.events
    assert (rest.t, rest.action, release.action) == (0.0, "rest", "release")
    x, y, xd, yd = release.before
    cos_leave = (2 + v0 ** 2 / (g * R)) / 3
    assert y / math.hypot(x, y) == pytest.approx(cos_leave, abs=1e-9)
    assert xd ** 2 + yd ** 2 == pytest.approx(v0 ** 2 + 2 * g * R * (1 - cos_leave), rel=1e-9)
    on = traj.t < release.t
    c = traj["y"][on] / np.hypot(traj["x"][on], traj["y"][on])                # N = m g (3 cos - 2) - m v0^2/R
    assert np.allclose(traj["force_sphere"][on], g * (3 * c - 2) - v0 ** 2 / R, rtol=0, atol=1e-7)
    off = traj.t > release.t
    s = traj.t[off] - release.t                                                   # the parabola from there
    assert np.allclose(traj["x"][off], x + xd * s, rtol=0, atol=1e-9)
    assert np.allclose(traj["y"][off], y + yd * s - g * s ** 2 / 2, rtol=0, atol=1e-9)


LOOP = """coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, R: 1.0, v0: 6.264184}
gravity: [0, -g]
particles:
  p: {mass: m, position: [x, y]}
events:
  - {name: track, when: R - sqrt(x^2 + y^2), action: impact, restitution: 0, rest: true}
initial: {x: 0, y: -R, x_dot: v0}
simulate: {t_end: 1.5, dt: 0.01}
"""


def test_a_particle_inside_a_loop_falls_off_where_cos_theta_is_closed_form(tmp_path):
    """Inside a vertical circle (the free side inside), from the bottom with speed v0: the
    track pushes with N = m v^2 / R + m g cos(phi) (phi from the bottom) and lets go where
    N = 0: -cos(phi_L) = (v0^2 - 2 g R) / (3 g R), with v^2 = v0^2 - 2 g R (1 - cos(phi))."""
    g, R, v0 = 9.81, 1.0, 6.264184
    traj = lagcli.load(_spec(tmp_path, "loop", LOOP)).simulate()
    rest, release = traj.events[:2]
    assert (rest.t, rest.action, release.action) == (0.0, "rest", "release")
    x, y, xd, yd = release.before
    assert -y / math.hypot(x, y) == pytest.approx(-(v0 ** 2 - 2 * g * R) / (3 * g * R), abs=1e-9)
    on = traj.t < release.t
    cos_phi = -traj["y"][on] / np.hypot(traj["x"][on], traj["y"][on])
    speed2 = v0 ** 2 - 2 * g * R * (1 - cos_phi)
    assert np.allclose(traj["force_track"][on], speed2 / R + g * cos_phi, rtol=0, atol=1e-7)


WALL = """coordinates: [theta]
parameters: {m: 1.0, l: 1.0, g: 9.81, alpha: 0.3, tau0: 5.0, c: 2.0}
inputs: [tau]
gravity: [0, -g]
particles:
  bob: {mass: m, position: [l*sin(theta), -l*cos(theta)]}
generalized_forces: {theta: tau}
events:
  - {name: wall, when: alpha - theta, action: impact, restitution: 0.5, rest: true}
initial: {theta: alpha}
simulate: {t_end: 2.0, dt: 0.01, inputs: {tau: tau0 - c*t}}
"""


def test_a_pendulum_pressed_against_a_wall_is_let_go_by_its_law(tmp_path):
    m, l, g, alpha, tau0, c = 1.0, 1.0, 9.81, 0.3, 5.0, 2.0
    traj = lagcli.load(_spec(tmp_path, "wall", WALL)).simulate()
    t_release = (tau0 - m * g * l * math.sin(alpha)) / c
    assert [r.action for r in traj.events][:2] == ["rest", "release"]
    assert traj.events[1].t == pytest.approx(t_release, rel=1e-9)
    on = traj.t < t_release
    assert np.allclose(traj["force_wall"][on], tau0 - c * traj.t[on] - m * g * l * math.sin(alpha), atol=1e-9)
    assert np.all(np.abs(traj["theta"][on] - alpha) < 1e-12)
    assert np.all(traj["theta"][traj.t > t_release] < alpha)                     # it swings away from the wall


CEILING = """coordinates: [y]
parameters: {m: 2.0, g: 9.81, k: 4.0}
inputs: [F]
gravity: [0, -g]
particles:
  block: {mass: m, position: [0, y]}
forces:
  - {at: block, force: [0, F]}
events:
  - {name: ceiling, when: y, direction: DIRECTION, action: impact, restitution: 0, rest: true}
initial: {y: 0}
simulate: {t_end: 7.0, dt: 0.01, inputs: {F: 2*m*g - k*t}}
"""


@pytest.mark.parametrize("direction", ["rising", "either"])
def test_a_block_pressed_against_a_ceiling_drops_where_the_push_no_longer_beats_gravity(tmp_path, direction):
    """The mirror of the lift-off: the free side of the gap is y < 0 (a rising event), the
    ceiling pushes down with N = F - m g = m g - k t, and lets go at m g / k."""
    m, g, k = 2.0, 9.81, 4.0
    traj = lagcli.load(_spec(tmp_path, "ceiling", CEILING.replace("DIRECTION", direction))).simulate()
    t_drop = m * g / k
    assert [(r.action, r.t) for r in traj.events] == [("rest", 0.0), ("release", pytest.approx(t_drop, rel=1e-9))]
    on, off = traj.t < t_drop, traj.t > t_drop
    assert np.allclose(traj["force_ceiling"][on], m * g - k * traj.t[on], rtol=0, atol=1e-9)
    assert np.allclose(traj["y"][off], -k * (traj.t[off] - t_drop) ** 3 / (6 * m), rtol=1e-8, atol=1e-12)


def test_a_pendulum_on_a_floor_rests_there_keeping_its_rod(tmp_path):
    text = (HYBRID / "cartesian_pendulum_floor.yaml").read_text()
    spec = tmp_path / "rest.yaml"
    spec.write_text(text.replace("restitution: e}", "restitution: e, rest: true}").replace("t_end: 3.0", "t_end: 6.0"))
    traj = lagcli.load(spec).simulate()
    assert traj.events[-1].action == "rest"
    last = traj.t > traj.events[-1].t + 1e-6
    assert last.sum() > 100
    assert np.allclose(traj["x"][last], math.sqrt(1.0 - 0.8 ** 2), atol=1e-9)
    assert np.allclose(traj["y"][last], -0.8, atol=1e-12)
    assert np.all(traj["constraint_residual"][last] < 1e-10)
    assert np.ptp(traj["energy"][last]) < 1e-10
    assert np.allclose(traj["force_floor"][last], 9.81, rtol=1e-9)            # the floor carries m g ...
    assert np.allclose(traj["lambda_rod"][last], 0.0, atol=1e-9)               # ... the rod nothing


def test_without_rest_the_run_ends_at_the_accumulation(tmp_path):
    spec = tmp_path / "ball.yaml"
    spec.write_text(SPEC.read_text().replace(", rest: true", ""))
    traj = lagcli.load(spec).simulate()
    assert traj.t[-1] == pytest.approx(math.sqrt(2 / 9.81) * 3, abs=1e-6) and "the run ends there" in traj.end_note
    assert "force_floor" not in traj.columns


@pytest.mark.parametrize("item, message", [
    ("{name: top, when: y - 2, action: reset, reset: {y: 0}, rest: true}", "'rest' belongs to an impact, not a reset"),
    ("{name: floor, when: y, action: impact, restitution: e, rest: 'yes'}", "expected true or false"),
])
def test_bad_rest_is_a_located_error(tmp_path, item, message):
    spec = tmp_path / "bad.yaml"
    text = SPEC.read_text()
    start = text.index("  - {name: floor")
    spec.write_text(text[:start] + f"  - {item}\n" + text[text.index("\n", start) + 1:])
    result = run("check", spec)
    assert result.exit_code == 2 and message in result.stderr and "bad.yaml:" in result.stderr, result.stderr


def test_a_coordinate_named_like_the_force_column_is_a_located_error(tmp_path):
    spec = tmp_path / "clash.yaml"
    spec.write_text(SPEC.read_text().replace("coordinates: [y]", "coordinates: [y, force_floor]"))
    result = run("check", spec)
    assert result.exit_code == 2 and "clash.yaml:" in result.stderr, result.stderr
    assert "events[0].name: a coordinate is called 'force_floor', the column of this event's contact force" \
        in result.stderr


def test_the_c_backend_refuses_a_held_contact_with_a_located_error():
    result = run("simulate", SPEC, "--backend", "c")
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    first = result.stderr.splitlines()[0]
    assert first.startswith(f"error: {SPEC}:") and "events[0].rest" in first, result.stderr
    assert "--backend python" in result.stderr


@pytest.mark.parametrize("lang", ["c", "python", "octave", "rust", "fmu", "casadi", "jax"])
def test_every_code_target_refuses_rest_clearly(lang, tmp_path):
    result = run("generate", SPEC, "--lang", lang, "-o", tmp_path / "out")
    assert result.exit_code == 2 and f"--lang {lang} does not implement " in result.stderr
    assert "an event's rest: true yet" in result.stderr and not (tmp_path / "out").exists()
    assert "`lagcli simulate` runs them (--backend python only)" in result.stderr   # C refuses a held contact


def test_the_plot_draws_the_contact_force_with_its_unit():
    pytest.importorskip("matplotlib")
    figure = lagcli.load(LIFT_OFF).simulate(t_end=1.0).plot()
    labels = [ax.get_ylabel() for ax in figure.axes]
    assert labels == ["y [m]", "force_floor [N]"]


def test_a_held_contact_that_cannot_be_solved_names_its_event_and_time():
    import dataclasses

    from lagcli.run.contact import Contacts
    from lagcli.runtime.event_loop_code import EventRunFailure

    hybrid = lagcli.load(SPEC).hybrid({})
    flat = dataclasses.replace(hybrid.events[0], G=lambda t, y: np.zeros(1))     # no direction to push along
    contacts = Contacts(dataclasses.replace(hybrid, events=(flat,)),
                        lambda t, y: (np.array([-9.81]), np.zeros(0)), 10.0, 10.0)
    contacts.held = 0
    with pytest.raises(EventRunFailure, match=r"^at t = 0.5: event 'floor' \(its contact held\): "):
        contacts.rhs(0.5, np.array([0.0, 0.0]))
