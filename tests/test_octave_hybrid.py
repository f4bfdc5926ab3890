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
    specs = {name: HYBRID / f"{name}.yaml" for name in SPECS} | {"oscillator": folder / "oscillator.yaml",
                                                                 "two_events": folder / "two_events.yaml"}
    script = []
    for name, path in specs.items():
        files = lagcli.load(path).generate("octave")
        out = folder / name
        out.mkdir()
        for file, text in files.items():
            (out / file).write_text(text)
        options = f"{{'t_end', {T_END[name]!r}}}" if name in T_END else "{}"
        events = f"events_file = '{out}/events.csv';" if name not in ("cart_pole_lqr", "oscillator") else ""
        script.append(f"cd('{out}'); clear options csv_file events_file; options = {options}; "
                      f"csv_file = '{out}/run.csv'; {events} {name}_run;")
    script.append(f"cd('{folder}/oscillator'); [h, r] = oscillator_simulate('u', @(t, y) -18 * y(1)); "
                  f"dlmwrite('{folder}/oscillator/handle.csv', r, 'precision', 17);")
    done = octave("\n".join(script), folder)
    assert done.returncode == 0 or "execution_exception" in done.stderr, done.stderr
    return folder, specs, done.stderr


@pytest.mark.parametrize("name", [*SPECS, "two_events"])
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
