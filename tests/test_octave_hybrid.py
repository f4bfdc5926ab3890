"""Input laws and events in the MATLAB/Octave files (`lagcli generate --lang octave`), run
under `octave-cli` (one process for all), against `lagcli simulate` and closed forms.

Tolerance. Both sides integrate at the spec's own tolerances (rtol 1e-9, atol 1e-12; the
Cartesian pendulum 1e-11, 1e-13), Octave with ode45 (Dormand-Prince 5(4)) and lagcli with
DOP853: two correct integrators at rtol 1e-9 differ by up to ~1e-7 of the state after a
few seconds (each step's error is held below rtol, and the errors add up over hundreds of
steps). An event time differs by that state error over the approach speed, so event
times, states before and after each event and the rows are compared to 1e-6 (relative to
1 + |value|), as the smooth specs are in tests/test_codegen_octave.py. Where the motion is
a polynomial in t (the bouncing ball, the projectile) both integrators are exact and the
event times agree to ~1e-13. The closed forms (apex heights e^(2k) h0, the spring made by
a law) are met to 1e-8.
"""
from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

import lagcli

from test_codegen_octave import OCTAVE_ONLY, octave
from test_hybrid_events import HYBRID
from test_hybrid_laws import OSCILLATOR

pytestmark = pytest.mark.skipif(shutil.which("octave-cli") is None, reason="no octave-cli (Debian package `octave`)")

SPECS = ["bouncing_ball", "cart_pole_lqr", "cartesian_pendulum_floor", "pendulum_wall", "projectile_landing",
         "rimless_wheel"]
T_END = {"bouncing_ball": 10.0, "rimless_wheel": 6.0}        # the others: their spec's t_end
TOL = 1e-6
# Two stop events crossing in the same ode45 step: ode45 reports the lower index
# (landed, at 1.31339 s); the earlier one (far, at 1.31269 s) is the event.
TWO_EVENTS = """
name: two_events
coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, v: 10.0, a: 0.7}
gravity: [0, -g]
particles:
  P: {mass: m, position: [x, y]}
events:
  - {name: landed, when: y, direction: falling, action: stop}
  - {name: far, when: x - 10.04, direction: rising, action: stop}
initial: {x: 0.0, y: 0.0, x_dot: v*cos(a), y_dot: v*sin(a)}
simulate: {t_end: 5.0, dt: 0.01}
"""

# The cart-pole of cart_pole_lqr.yaml kicked as its pole passes upright: the reset halves
# x_dot and leaves g = theta at its root (tests/test_c_events.py has the same kick).
KICK_EVENTS = ("events:\n  - {name: upright, when: theta, direction: falling, action: reset, reset: {x_dot: 0.5*x_dot}}\n"
               "  - {name: far, when: x - 0.3, direction: rising, action: stop}\ninitial: {theta: 0.2}")
# An oscillator (omega = 2) kicked at t = 1: g = t - 1 is exactly 0 at the event and the
# reset leaves it so; x = cos(2 t), then cos(2 t) + sin(2 (t - 1))/2.
TIMED_KICK = """
name: timed_kick
coordinates: [x]
parameters: {m: 1.0, k: 4.0}
particles:
  P: {mass: m, position: [x, 0]}
potential: k*x**2/2
events:
  - {name: kick, when: t - 1, direction: rising, action: reset, reset: {x_dot: x_dot + 1}}
initial: {x: 1.0}
simulate: {t_end: 3.0, dt: 0.01}
"""
# The Cartesian pendulum whose floor event doubles x: the rod constraint breaks.
BAD_RESET = ("- {name: floor, when: y + h, direction: falling, action: impact, restitution: e}",
             "- {name: jump, when: y + h, action: reset, reset: {x: 2*x}}")


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    return header, rows


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Every hybrid spec and the oscillator generated and run in one octave process:
    <folder>/<spec>/run.csv, events.csv and the standard error of each run."""
    folder = tmp_path_factory.mktemp("octave_hybrid")
    (folder / "oscillator.yaml").write_text(OSCILLATOR.replace("coordinates:", "name: oscillator\ncoordinates:"))
    (folder / "two_events.yaml").write_text(TWO_EVENTS)
    (folder / "kick.yaml").write_text((HYBRID / "cart_pole_lqr.yaml").read_text()
                                      .replace("name: cart_pole_lqr", "name: kick")
                                      .replace("initial: {theta: 0.2}", KICK_EVENTS))
    (folder / "timed_kick.yaml").write_text(TIMED_KICK)
    (folder / "bad_reset.yaml").write_text((HYBRID / "cartesian_pendulum_floor.yaml").read_text()
                                           .replace("name: cartesian_pendulum_floor", "name: bad_reset")
                                           .replace(*BAD_RESET))
    specs = {name: HYBRID / f"{name}.yaml" for name in SPECS} | {
        name: folder / f"{name}.yaml" for name in ("oscillator", "two_events", "kick", "timed_kick", "bad_reset")}
    script = []
    for name, path in specs.items():
        files = lagcli.load(path).generate("octave")
        out = folder / name
        out.mkdir()
        for file, text in files.items():
            (out / file).write_text(text)
        options = f"{{'t_end', {T_END[name]!r}}}" if name in T_END else "{}"
        events = f"events_file = '{out}/events.csv';" if name not in ("cart_pole_lqr", "oscillator") else ""
        run = (f"cd('{out}'); clear options csv_file events_file; options = {options}; "
               f"csv_file = '{out}/run.csv'; {events} {name}_run;")
        if name == "bad_reset":           # the error ends this run only: its message to error.txt
            run = (f"try, {run} catch failure, fid = fopen('{out}/error.txt', 'w'); "
                   f"fprintf(fid, '%s', failure.message); fclose(fid); end")
        script.append(run)
    script.append(f"cd('{folder}/oscillator'); [h, r] = oscillator_simulate('u', @(t, y) -18 * y(1)); "
                  f"dlmwrite('{folder}/oscillator/handle.csv', r, 'precision', 17);")
    done = octave("\n".join(script), folder)
    assert done.returncode == 0 or "execution_exception" in done.stderr, done.stderr
    return folder, specs, done.stderr


@pytest.mark.parametrize("name", [*SPECS, "two_events", "kick", "timed_kick"])
def test_rows_and_events_agree_with_lagcli_simulate(runs, name):
    folder, specs, _ = runs
    expected = lagcli.load(specs[name]).simulate(t_end=T_END.get(name), backend="python")
    header, rows = read_csv(folder / name / "run.csv")
    assert header == list(expected.columns)
    got = np.array(rows, dtype=float)
    want = np.column_stack([expected[c] for c in expected.columns])
    assert got.shape == want.shape
    assert np.all(np.abs(got - want) <= TOL * (1 + np.abs(want)))
    if name == "cart_pole_lqr":
        return
    _, events = read_csv(folder / name / "events.csv")
    assert [row[1:3] for row in events] == [[r.name, r.action] for r in expected.events]
    for row, record in zip(events, expected.events):
        values = np.array([float(row[0]), *map(float, row[3:-1])])
        reference = np.array([record.t, *record.before, *record.after])
        assert np.all(np.abs(values - reference) <= TOL * (1 + np.abs(reference))), (row, record)
        if record.impulse is not None:
            assert float(row[-1]) == pytest.approx(record.impulse, rel=TOL, abs=TOL)


def test_bouncing_ball_apex_heights_and_accumulation(runs):
    """Closed form: the speed after impact k is e^k sqrt(2 g h0), so the apex heights are
    h_k = e^(2k) h0; the run ends at the accumulation time t1 (1 + e)/(1 - e) with a note."""
    folder, _, stderr = runs
    e, g, h0 = 0.9, 9.81, 1.0
    _, events = read_csv(folder / "bouncing_ball" / "events.csv")
    speeds = np.array([float(row[6]) for row in events])                 # y_dot+
    k = np.arange(1, len(speeds) + 1)
    heights = speeds ** 2 / (2 * g)
    few = k <= 20
    assert np.allclose(heights[few], e ** (2 * k[few]) * h0, rtol=0, atol=1e-8)
    t1 = math.sqrt(2 * h0 / g)
    assert float(events[-1][0]) == pytest.approx(t1 * (1 + e) / (1 - e), abs=1e-6)
    assert "177 events: floor \u00d7177, first at t = 0.451523641 s" in stderr
    assert "note: event 'floor' recurred after" in stderr and "the run ends there" in stderr


def test_laws_closed_form_and_a_function_handle(runs):
    """The oscillator's law F = -k x makes x = cos(2 t); the 'u' option as a handle
    u(t, y) = -18 x replaces it (x = cos(3 t))."""
    folder, _, _ = runs
    _, rows = read_csv(folder / "oscillator" / "run.csv")
    data = np.array(rows, dtype=float)
    assert np.allclose(data[:, 1], np.cos(2 * data[:, 0]), atol=1e-8)
    handle = np.loadtxt(folder / "oscillator" / "handle.csv", delimiter=",")
    assert np.allclose(handle[:, 1], np.cos(3 * handle[:, 0]), atol=1e-8)


def test_hybrid_files_are_matlab_too(runs):
    import re

    folder, _, _ = runs
    for path in (folder / "bouncing_ball").glob("*.m"):
        text = "\n".join(line.split("%")[0] for line in path.read_text().splitlines())
        for pattern, what in OCTAVE_ONLY:
            assert not re.search(pattern, text, re.M), f"{path.name}: {what}"


def test_a_reset_that_leaves_g_at_its_root_does_not_fire_again(runs):
    """The kick (x_dot halved as theta falls through 0, theta untouched) leaves g = theta at
    its root, on either side by round-off: it has crossed, and the run goes on to the stop
    at x = 0.3, as `lagcli simulate` does on both backends (not an "accumulation")."""
    folder, _, stderr = runs
    _, events = read_csv(folder / "kick" / "events.csv")
    assert [row[1] for row in events] == ["upright", "far"]
    before, after = np.array(events[0][3:7], dtype=float), np.array(events[0][7:11], dtype=float)
    assert np.array_equal(after[:2], before[:2]) and after[2] == 0.5 * before[2] and after[3] == before[3]
    assert float(events[1][3]) == pytest.approx(0.3, abs=1e-12)               # x- at the stop
    assert "2 events: upright \u00d71, far \u00d71" in stderr
    assert "note: event 'upright'" not in stderr



def test_a_timed_kick_closed_form(runs):
    """g = t - 1 sits exactly at 0 after the kick (the reset does not touch t): the run goes
    on (before, ode45 saw g leave 0 as a crossing it could not locate) and meets the
    closed form x = cos(2 t) + [t > 1] sin(2 (t - 1))/2 to 1e-8."""
    folder, _, _ = runs
    _, events = read_csv(folder / "timed_kick" / "events.csv")
    assert [(row[1], float(row[0])) for row in events] == [("kick", 1.0)]
    _, rows = read_csv(folder / "timed_kick" / "run.csv")
    t, x = np.array(rows, dtype=float)[:, :2].T
    assert t[-1] == 3.0
    assert np.allclose(x, np.cos(2 * t) + np.where(t >= 1, np.sin(2 * (t - 1)) / 2, 0.0), rtol=0, atol=1e-8)


def test_a_reset_that_breaks_a_constraint_is_an_error_naming_the_event(runs):
    """As `lagcli simulate`: the new state of a reset must keep the rod x^2 + y^2 = l^2."""
    folder, specs, _ = runs
    expected = lagcli.load(specs["bad_reset"]).simulate(backend="python").failure
    message = (folder / "bad_reset" / "error.txt").read_text()
    t, rest = message.split(": ", 1)
    t_expected, rest_expected = expected.split(": ", 1)
    assert t.startswith("at t = ") and float(t[7:]) == pytest.approx(float(t_expected[7:]), rel=1e-6)
    assert rest == rest_expected
    assert "event 'jump' (reset) gives a state that violates the constraints" in rest
    assert not (folder / "bad_reset" / "run.csv").exists()
