"""Events (spec `events:`): impacts, resets and stops against closed forms.

Each bundled spec of `specs/hybrid/` opens with its sketch and the result checked here:
the bouncing ball's impact times, apex heights h_k = e^(2k) h0 and accumulation time; the
rimless wheel's limit speed cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma)); the energy
ratio e^2 of a pendulum striking a wall; a constrained pendulum keeping its rod through
impacts on a floor; a projectile stopping where it lands. Each on both backends: the
Python backend's event loop (lagcli/run/event_loop.py) and the C driver's
(lagcli/runtime/c/lagcli_events.c; skipped without a C compiler).
"""
from __future__ import annotations

import math
import shutil

import numpy as np
import pytest
from click.testing import CliRunner

import lagcli
from lagcli.cli import cli

from conftest import SPECS

HYBRID = SPECS / "hybrid"


def run(*args):
    try:
        runner = CliRunner(mix_stderr=False)
    except TypeError:
        runner = CliRunner()
    return runner.invoke(cli, [str(a) for a in args])


@pytest.fixture(scope="module", params=["python", "c"])
def backend(request):
    if request.param == "c" and shutil.which("cc") is None:
        pytest.skip("no C compiler (cc): the C backend cannot run")
    return request.param


@pytest.fixture(scope="module")
def ball(backend):
    return lagcli.load(HYBRID / "bouncing_ball.yaml").simulate(backend=backend)


def test_bouncing_ball_impact_times_and_apex_heights(ball):
    g, e, h0 = 9.81, 0.9, 1.0
    t1 = math.sqrt(2 * h0 / g)
    expected_t = [t1 + sum(2 * e ** j * g * t1 / g for j in range(1, k + 1)) for k in range(40)]
    times = [r.t for r in ball.events[:40]]
    assert np.allclose(times, expected_t, rtol=0, atol=1e-8)
    for k, r in enumerate(ball.events[:40], start=1):          # apex after the k-th impact
        apex = r.after[1] ** 2 / (2 * g)
        assert apex == pytest.approx(e ** (2 * k) * h0, rel=1e-8, abs=1e-12)
        assert r.impulse == pytest.approx(-(1 + e) * r.before[1], rel=1e-12)   # P = m (v+ - v-)


def test_bouncing_ball_ends_at_the_accumulation_time(ball):
    g, e, h0 = 9.81, 0.9, 1.0
    t_inf = math.sqrt(2 * h0 / g) * (1 + e) / (1 - e)
    assert ball.failure is None
    assert ball.t[-1] == pytest.approx(t_inf, abs=1e-6)
    assert ball.t[-1] == ball.events[-1].t                       # the last row is at the last event
    assert "accumulation" in ball.end_note
    assert np.all(np.diff(ball.t) > 0)
    assert np.all(ball["y"] > -1e-9)                             # never through the floor


def test_grid_rows_never_mix_before_and_after(ball):
    """Every row on the grid is the exact flight arc of its own bounce (no row blends two)."""
    g, t, y = 9.81, ball.t[:-1], ball["y"][:-1]
    starts = [0.0] + [r.t for r in ball.events]
    states = [(1.0, 0.0)] + [(r.after[0], r.after[1]) for r in ball.events]
    k = np.searchsorted(starts, t, side="right") - 1
    arc = [states[i][0] + states[i][1] * (tk - starts[i]) - g * (tk - starts[i]) ** 2 / 2 for tk, i in zip(t, k)]
    assert np.allclose(y, arc, atol=1e-9)
    assert np.allclose(t, np.round(t / 0.01) * 0.01, atol=1e-12)     # the grid is kept


def test_rimless_wheel_converges_to_its_limit_speed(backend):
    traj = lagcli.load(HYBRID / "rimless_wheel.yaml").simulate(backend=backend)
    g, l, alpha, gamma = 9.81, 1.0, 0.4, 0.1
    limit = math.sqrt(4 * (g / l) * math.sin(alpha) * math.sin(gamma)) / math.tan(2 * alpha)
    last = traj.events[-1]
    assert last.name == "heel_strike" and last.action == "reset"
    assert last.before[0] == pytest.approx(-alpha, abs=1e-10)
    assert last.after[0] == pytest.approx(alpha, abs=1e-10)
    assert abs(last.after[1]) == pytest.approx(limit, rel=1e-8)
    assert len(traj.events) > 30


def test_pendulum_wall_energy_after_each_impact_is_e_squared_times_before(backend):
    traj = lagcli.load(HYBRID / "pendulum_wall.yaml").simulate(backend=backend)
    m, l, g, e = 1.0, 1.0, 9.81, 0.8

    def energy(state):                       # from the bottom: T + V + m g l
        theta, theta_dot = state
        return m * l ** 2 * theta_dot ** 2 / 2 + m * g * l * (1 - math.cos(theta))

    assert len(traj.events) >= 4
    for r in traj.events:
        assert energy(r.after) == pytest.approx(e ** 2 * energy(r.before), rel=1e-10)
    first = traj.events[0]
    assert energy(first.before) == pytest.approx(m * g * l * (1 - math.cos(1.0)), rel=1e-9)


def test_constrained_pendulum_keeps_its_rod_across_impacts(backend):
    traj = lagcli.load(HYBRID / "cartesian_pendulum_floor.yaml").simulate(backend=backend)
    h, e = 0.8, 0.7
    assert len(traj.events) >= 3
    assert np.max(traj["constraint_residual"]) < 1e-10
    for r in traj.events:
        x, y, xd, yd = r.before
        xp, yp, xdp, ydp = r.after
        assert y == pytest.approx(-h, abs=1e-10)
        assert ydp == pytest.approx(-e * yd, rel=1e-10)                 # G v+ = -e G v-
        assert abs(xp * xdp + yp * ydp) < 1e-10                        # A v+ = 0: still on the circle
        assert math.hypot(xdp, ydp) == pytest.approx(e * math.hypot(xd, yd), rel=1e-9)


def test_projectile_stops_where_it_lands(backend):
    traj = lagcli.load(HYBRID / "projectile_landing.yaml").simulate(backend=backend)
    g, v, a = 9.81, 10.0, 0.7
    flight = 2 * v * math.sin(a) / g
    assert [r.action for r in traj.events] == ["stop"]
    assert traj.t[-1] == pytest.approx(flight, rel=1e-12)
    assert traj["x"][-1] == pytest.approx(v ** 2 * math.sin(2 * a) / g, rel=1e-12)
    assert abs(traj["y"][-1]) < 1e-12
    assert traj.end_note is None and traj.failure is None


def test_cli_events_file_and_summary(backend, tmp_path):
    events, out = tmp_path / "bounces.csv", tmp_path / "ball.csv"
    result = run("simulate", HYBRID / "bouncing_ball.yaml", "--t-end", "2", "--events", events, "-o", out,
                 "--backend", backend)
    assert result.exit_code == 0, result.stderr
    assert "3 events: floor \u00d73, first at t = 0.451523641 s" in result.stderr
    lines = events.read_text().splitlines()
    assert lines[0] == "t,event,action,y-,y_dot-,y+,y_dot+,impulse"
    assert len(lines) == 4 and lines[1].split(",")[1:3] == ["floor", "impact"]
    assert out.read_text().splitlines()[-1].startswith("2,")


def test_a_reset_that_breaks_a_constraint_is_an_error_naming_the_event(backend, tmp_path):
    spec = tmp_path / "bad_reset.yaml"
    spec.write_text((HYBRID / "cartesian_pendulum_floor.yaml").read_text().replace(
        "- {name: floor, when: y + h, direction: falling, action: impact, restitution: e}",
        "- {name: jump, when: y + h, action: reset, reset: {x: 2*x}}"))
    result = run("simulate", spec, "-o", tmp_path / "out.csv", "--backend", backend)
    assert result.exit_code == 1
    assert "event 'jump' (reset) gives a state that violates the constraints" in result.stderr
    assert (tmp_path / "out.csv").read_text().count("\n") > 10        # the rows so far are kept


def test_bouncing_ball_fmu_in_fmpy_agrees_with_simulate(ball, tmp_path):
    """The FMU's event indicators and fmi2NewDiscreteStates, run by FMPy's CVode (Model
    Exchange), give the same motion and impact times as lagcli simulate."""
    import shutil

    fmpy = pytest.importorskip("fmpy")
    if shutil.which("cc") is None:
        pytest.skip("no C compiler (cc): the FMU's binary cannot be built")
    system = lagcli.load(HYBRID / "bouncing_ball.yaml")
    path = tmp_path / "bouncing_ball.fmu"
    (data,) = system.generate("fmu").values()
    path.write_bytes(data)
    result = fmpy.simulate_fmu(str(path), stop_time=3.0, output_interval=0.01, solver="CVode",
                               relative_tolerance=1e-12, record_events=True, output=["y", "y_dot"])
    t = result["time"]
    expected = system.simulate(t_end=3.0)
    last = [np.flatnonzero(np.isclose(t, tk, rtol=0, atol=1e-12))[-1] for tk in expected.t]   # after any event
    assert np.allclose(result["y"][last], expected["y"], atol=1e-9)
    assert np.allclose(result["y_dot"][last], expected["y_dot"], atol=1e-8)
    event_times = sorted(set(t[:-1][t[:-1] == t[1:]]))              # FMPy records each event twice
    merged = [tk for k, tk in enumerate(event_times) if k == 0 or tk - event_times[k - 1] > 1e-9]
    assert np.allclose(merged, [r.t for r in expected.events], rtol=1e-9, atol=0)


@pytest.mark.parametrize("lang", ["rust", "casadi", "jax"])
def test_code_targets_refuse_events_clearly(lang, tmp_path):
    result = run("generate", HYBRID / "bouncing_ball.yaml", "--lang", lang, "-o", tmp_path / "out")
    assert result.exit_code == 2
    assert f"--lang {lang} does not implement events: yet" in result.stderr
    assert "`lagcli simulate` runs them (--backend python or c)" in result.stderr   # both run events
