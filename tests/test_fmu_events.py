"""Events in the FMU (`--lang fmu` of a spec with `events:`, Model Exchange): FMPy's CVode
run of every bundled hybrid spec against `lagcli simulate`, and the rules they share.

What a Model Exchange importer (FMPy, Simulink) sees: numberOfEventIndicators = the
events, the event functions g_k as indicators, the actions in fmi2NewDiscreteStates
(valuesOfContinuousStatesChanged after an impact or a reset, terminateSimulation at a
stop or where events accumulate). Both sides run at rtol 1e-12 (lagcli: atol 1e-14), so
the event times agree to 1e-9 relative and the states before and after each event to
1e-8 (CVode and DOP853 are different integrators; observed ~1e-10 and ~5e-10). An event
is where FMPy's recorded rows repeat a time with other states (FMPy records a row before
and after every event iteration, also at the zero of an indicator that fires nothing).
"""
from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

import lagcli

from test_hybrid_events import HYBRID
from test_octave_hybrid import BAD_RESET, KICK_EVENTS, TIMED_KICK

fmpy = pytest.importorskip("fmpy")
pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc): the FMU cannot be built")

TIME_RTOL, STATE_TOL = 1e-9, 1e-8
# every bundled spec with events (bouncing_ball_rest's rest: true is refused: test_resting_contact.py)
SPECS = {"bouncing_ball": 3.0, "cartesian_pendulum_floor": 3.0, "pendulum_wall": 5.0, "projectile_landing": 5.0,
         "rimless_wheel": 6.0}


def build(system, folder, name):
    path = folder / f"{name}.fmu"
    (data,) = system.generate("fmu").values()
    path.write_bytes(data)
    return str(path)


def run_fmu(path, states, stop, **options):
    messages = []

    def logger(environment, instance, status, category, message):
        messages.append((status, category.decode(), message.decode()))

    result = fmpy.simulate_fmu(path, stop_time=stop, output_interval=0.01, solver="CVode",
                               relative_tolerance=1e-12, record_events=True, output=states, logger=logger,
                               **options)
    return result, messages


def jumps(result, states):
    """(t, y-, y+) of every event that changed the state, from FMPy's recorded rows."""
    t = result["time"]
    y = np.column_stack([result[s] for s in states])
    return [(t[i], y[i], y[i + 1]) for i in range(len(t) - 1) if t[i] == t[i + 1] and np.any(y[i] != y[i + 1])]


def assert_same_events(found, expected):
    assert len(found) == len(expected)
    for (t, before, after), record in zip(found, expected):
        assert t == pytest.approx(record.t, rel=TIME_RTOL, abs=0)
        assert np.allclose(before, record.before, rtol=0, atol=STATE_TOL)
        assert np.allclose(after, record.after, rtol=0, atol=STATE_TOL)


@pytest.mark.parametrize("name", sorted(SPECS))
def test_fmpy_agrees_with_lagcli_simulate(name, tmp_path):
    system = lagcli.load(HYBRID / f"{name}.yaml")
    states = [s.name for s in system.layout.states]
    stop = SPECS[name]
    result, _ = run_fmu(build(system, tmp_path, name), states, stop)
    expected = system.simulate(t_end=stop, rtol=1e-12, atol=1e-14)
    stops = [r for r in expected.events if r.action == "stop"]
    assert_same_events(jumps(result, states), [r for r in expected.events if r.action != "stop"])
    if stops:                                   # terminateSimulation: FMPy's last row is the stop
        assert result["time"][-1] == pytest.approx(stops[0].t, rel=TIME_RTOL, abs=0)
        final = np.array([result[s][-1] for s in states])
        assert np.allclose(final, stops[0].before, rtol=0, atol=STATE_TOL)
    else:
        assert result["time"][-1] == stop


def test_projectile_stops_at_the_closed_form_flight_time(tmp_path):
    """terminateSimulation at the stop event: flight time 2 v sin(a)/g, range v^2 sin(2a)/g."""
    system = lagcli.load(HYBRID / "projectile_landing.yaml")
    result, _ = run_fmu(build(system, tmp_path, "p"), ["x", "y"], 5.0)
    g, v, a = 9.81, 10.0, 0.7
    assert result["time"][-1] == pytest.approx(2 * v * math.sin(a) / g, rel=1e-10)
    assert result["x"][-1] == pytest.approx(v ** 2 * math.sin(2 * a) / g, rel=1e-10)


def test_accumulating_bounces_terminate_the_simulation(tmp_path):
    """The ball's bounces accumulate at t1 (1 + e)/(1 - e): the FMU terminates the
    simulation there with a warning saying why (lagcli simulate ends its run there), and
    never keeps FMPy stepping ever closer bounces; the first 40 impacts are lagcli's."""
    system = lagcli.load(HYBRID / "bouncing_ball.yaml")
    result, messages = run_fmu(build(system, tmp_path, "ball"), ["y", "y_dot"], 10.0)
    expected = system.simulate(rtol=1e-12, atol=1e-14)
    assert_same_events(jumps(result, ["y", "y_dot"])[:40], expected.events[:40])
    t_inf = math.sqrt(2 / 9.81) * 1.9 / 0.1
    assert result["time"][-1] == pytest.approx(t_inf, abs=1e-4) and result["time"][-1] <= t_inf
    (warning,) = [m for status, category, m in messages if category == "logEvents" and status == 1]
    assert "event 'floor' recurred after" in warning and "the simulation terminates there" in warning


def test_a_reset_that_leaves_g_at_its_root_does_not_fire_again(tmp_path):
    """The cart-pole kicked as its pole passes upright (g = theta untouched by the reset),
    and a spring kicked at t = 1 (g = t - 1): g sits at its root after the event; it has
    crossed, and the run goes on as lagcli simulate's (x = cos 2t + sin(2(t - 1))/2)."""
    kick = tmp_path / "kick.yaml"
    kick.write_text((HYBRID / "cart_pole_lqr.yaml").read_text().replace("initial: {theta: 0.2}", KICK_EVENTS))
    system = lagcli.load(kick)
    states = [s.name for s in system.layout.states]
    result, _ = run_fmu(build(system, tmp_path, "kick"), states, 10.0)
    expected = system.simulate(rtol=1e-12, atol=1e-14)
    assert [r.name for r in expected.events] == ["upright", "far"]
    assert_same_events(jumps(result, states), expected.events[:1])
    assert result["time"][-1] == pytest.approx(expected.events[1].t, rel=TIME_RTOL, abs=0)

    timed = tmp_path / "timed_kick.yaml"
    timed.write_text(TIMED_KICK)
    result, _ = run_fmu(build(lagcli.load(timed), tmp_path, "timed"), ["x", "x_dot"], 3.0)
    (event,) = jumps(result, ["x", "x_dot"])
    assert event[0] == pytest.approx(1.0, abs=1e-12) and event[2][1] == event[1][1] + 1
    t = result["time"]
    assert np.allclose(result["x"], np.cos(2 * t) + np.where(t >= 1, np.sin(2 * (t - 1)) / 2, 0.0), atol=1e-9)


def test_a_reset_that_breaks_a_constraint_is_an_fmi_error_naming_the_event(tmp_path):
    """fmi2NewDiscreteStates returns fmi2Error and logs lagcli simulate's message."""
    spec = tmp_path / "bad_reset.yaml"
    spec.write_text((HYBRID / "cartesian_pendulum_floor.yaml").read_text().replace(*BAD_RESET))
    system = lagcli.load(spec)
    expected = system.simulate(backend="python").failure
    failure, messages = failing_run(build(system, tmp_path, "bad"), start_values={})
    assert "fmi2NewDiscreteStates failed" in failure
    (error,) = [m for status, category, m in messages if category == "logStatusError"]
    assert error.split(": ", 1)[1] == expected.split(": ", 1)[1]
    assert float(error[7:error.index(":")]) == pytest.approx(float(expected[7:expected.index(":")]), rel=1e-9)


def failing_run(path, **options):
    """(the exception's text, the FMU's log) of a run that must fail."""
    messages = []

    def logger(environment, instance, status, category, message):
        messages.append((status, category.decode(), message.decode()))

    with pytest.raises(Exception) as failure:
        fmpy.simulate_fmu(path, stop_time=3.0, solver="CVode", relative_tolerance=1e-12, logger=logger, **options)
    return str(failure.value), messages


def test_a_restitution_outside_0_1_is_an_fmi_error(tmp_path):
    """As `lagcli simulate --set e=1.5` (exit 2): checked as initialization ends."""
    path = build(lagcli.load(HYBRID / "bouncing_ball.yaml"), tmp_path, "ball")
    failure, messages = failing_run(path, start_values={"e": 1.5})
    assert "fmi2ExitInitializationMode failed" in failure
    assert ("logStatusError", "event 'floor': restitution = 1.5 with these parameter values; it must be in [0, 1]") \
        in [(category, m) for _, category, m in messages]


def test_the_model_description_of_an_fmu_with_events(tmp_path):
    """FMPy's validation passes; one event indicator per event, Model Exchange only (its
    integrator does not locate events), and the log category of the events."""
    system = lagcli.load(HYBRID / "cartesian_pendulum_floor.yaml")
    path = build(system, tmp_path, "floor")
    assert fmpy.validation.validate_fmu(path) == []
    description = fmpy.read_model_description(path)
    assert description.numberOfEventIndicators == len(system.derivation.events) == 1
    assert description.modelExchange is not None and description.coSimulation is None
    assert "logEvents" in [getattr(c, "name", c) for c in description.logCategories]
