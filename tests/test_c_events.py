"""Events in the C runtime (lagcli/runtime/c/lagcli_events.c) against the Python backend's
event loop (lagcli/run/event_loop.py, scipy's DOP853 and brentq) and against the rules
both must keep.

The closed forms (bouncing ball, rimless wheel, pendulum at a wall, Cartesian pendulum on
a floor, projectile) run on both backends in tests/test_hybrid_events.py; here every
bundled spec of specs/hybrid/ runs on both and the two are compared event by event, and
the C side's own edges are checked: its rules equal the Python ones, plastic impacts and
the event budget end a run cleanly, the step budget counts every segment, bad input is
exit status 2, and the generated model's event functions serve an embedding program.
Skipped without a C compiler.
"""
from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest

import lagcli
from conftest import SPECS
from test_hybrid_events import HYBRID, run

pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc): the C backend cannot run")

ROOT = SPECS.parent
EVENT_SPECS = sorted(p.name for p in HYBRID.glob("*.yaml") if "rest: true" not in p.read_text())


def test_a_cut_off_log_line_is_left_out():
    from lagcli.run.records import read_event_log

    line = "event,floor,impact,0.5,0,-4.9,0,4.41,9.31\n"
    records, note = read_event_log(line + line[:20], 2)
    assert len(records) == 1 and records[0].after == (0.0, 4.41) and records[0].impulse == 9.31
    assert note is None


def test_the_c_rules_are_the_python_rules():
    from lagcli.interface import ACCUMULATION_GAP, EVENT_BUDGET, FIRST_STEP_SAMPLES, RESTING_SPEED

    header = (ROOT / "lagcli" / "runtime" / "c" / "lagcli_events.h").read_text()
    defined = dict(re.findall(r"#define (LAGCLI_EVENTS_\w+) ([\w.+-]+)", header))
    assert float(defined["LAGCLI_EVENTS_GAP"]) == ACCUMULATION_GAP
    assert float(defined["LAGCLI_EVENTS_RESTING"]) == RESTING_SPEED
    assert int(defined["LAGCLI_EVENTS_BUDGET"].rstrip("L")) == EVENT_BUDGET
    assert int(defined["LAGCLI_EVENTS_SAMPLES"]) == FIRST_STEP_SAMPLES


@pytest.mark.parametrize("name", EVENT_SPECS)
def test_every_bundled_hybrid_spec_runs_alike_on_both_backends(name):
    """Same events (names, actions), times to 1e-9 relative, states after each event and
    impulses to ~1e-9, the same end note and the same rows on the same grid."""
    system = lagcli.load(HYBRID / name)
    python, c = system.simulate(backend="python"), system.simulate(backend="c")
    assert c.failure is None and python.failure is None
    assert [(r.name, r.action) for r in c.events] == [(r.name, r.action) for r in python.events]
    for a, b in zip(c.events, python.events):
        assert a.t == pytest.approx(b.t, rel=1e-9, abs=0)
        scale = 1.0 + np.max(np.abs(b.after))
        assert np.max(np.abs(np.subtract(a.before, b.before))) < 1e-9 * scale
        assert np.max(np.abs(np.subtract(a.after, b.after))) < 1e-9 * scale
        assert (a.impulse is None) == (b.impulse is None)
        if b.impulse is not None:
            assert a.impulse == pytest.approx(b.impulse, rel=1e-9, abs=1e-12)
    assert c.end_note == python.end_note
    assert np.array_equal(c.t[:-1], python.t[:-1])         # the grid; the last row may be an event's
    assert c.t[-1] == pytest.approx(python.t[-1], rel=1e-9, abs=0)
    assert np.allclose(c.states, python.states, rtol=0, atol=1e-8)


def test_the_cli_prints_the_same_events_file_and_words_from_both_backends(tmp_path):
    outputs = {}
    for backend in ("python", "c", "c"):          # the second C run: the cached driver (the warm path)
        events = tmp_path / f"{backend}.csv"
        result = run("simulate", HYBRID / "bouncing_ball.yaml", "--backend", backend, "--events", events,
                     "-o", tmp_path / f"rows_{backend}.csv")
        assert result.exit_code == 0, result.stderr
        assert outputs.get(backend, (result.stderr,))[0] == result.stderr
        outputs[backend] = (result.stderr, events.read_text().splitlines())
    (py_err, py_rows), (c_err, c_rows) = outputs["python"], outputs["c"]
    assert c_err == py_err          # the summary and the accumulation note: formatted once, in Python
    assert "177 events: floor \u00d7177, first at t = 0.451523641 s" in c_err
    assert "recurred after 7.99e-09 s at t = 8.578949107" in c_err
    assert c_rows[0] == py_rows[0] and len(c_rows) == len(py_rows) == 178
    for a, b in zip(c_rows[1:], py_rows[1:]):
        x, y = a.split(","), b.split(",")
        assert x[1:3] == y[1:3] and float(x[0]) == pytest.approx(float(y[0]), rel=1e-12)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_a_reset_that_leaves_g_at_its_root_does_not_fire_again(method, tmp_path):
    """A kick that halves the cart's speed as the balanced pole passes upright (g = theta,
    untouched by the reset): g sits at its root after the event, on either side by
    round-off; it has crossed, and the run goes on to the stop at x = 0.3 on both backends
    (before, a round-off sign could make it fire again at once: an "accumulation")."""
    spec = tmp_path / "kick.yaml"
    spec.write_text((HYBRID / "cart_pole_lqr.yaml").read_text().replace(
        "initial: {theta: 0.2}",
        "events:\n  - {name: upright, when: theta, direction: falling, action: reset, reset: {x_dot: 0.5*x_dot}}\n"
        "  - {name: far, when: x - 0.3, direction: rising, action: stop}\ninitial: {theta: 0.2}"))
    system = lagcli.load(spec)
    for backend in ("python", "c"):
        traj = system.simulate(backend=backend, method=method)
        assert [r.name for r in traj.events] == ["upright", "far"] and traj.end_note is None
        upright = traj.events[0]
        assert upright.after[2] == 0.5 * upright.before[2] and upright.after[:2] == upright.before[:2]
        assert traj["x"][-1] == pytest.approx(0.3, abs=1e-12)


def test_a_plastic_impact_ends_the_run_at_rest():
    ball = lagcli.load(HYBRID / "bouncing_ball.yaml").simulate(backend="c", parameters={"e": 0.0})
    t1 = (2 * 1.0 / 9.81) ** 0.5
    assert len(ball.events) == 1 and ball.events[0].t == pytest.approx(t1, rel=1e-12)
    assert ball.failure is None and "the contact has come to rest" in ball.end_note
    assert ball.t[-1] == ball.events[0].t and ball["y_dot"][-1] == 0.0


def test_the_event_budget_ends_a_run_cleanly():
    """100 000 events (an elastic ball, e = 1, bouncing 0.1 mm high: one impact every
    2 sqrt(2 h / g) = 9.03 ms, the last at 903.04 s): the run ends at the budget with a note, exit status 0."""
    ball = lagcli.load(HYBRID / "bouncing_ball.yaml")
    traj = ball.simulate(backend="c", parameters={"e": 1.0}, initial={"y": 1e-4}, t_end=1000.0, dt=1.0)
    period = 2 * (2 * 1e-4 / 9.81) ** 0.5
    assert traj.failure is None and len(traj.events) == 100_000
    assert traj.end_note.startswith("100000 events (the budget of one run) by t = 903.04")
    assert traj.t[-1] == traj.events[-1].t == pytest.approx((100_000 - 0.5) * period, rel=1e-6)


def test_the_step_budget_counts_the_steps_between_events(tmp_path):
    """--max-steps bounds the steps of the whole run, every segment between events: the
    pendulum at its wall runs out after its first impacts, on both backends at the same
    step (their steps are scipy's; the ball's polynomial flight would not do, its error
    estimates are round-off)."""
    stops = {}
    for backend in ("python", "c"):
        result = run("simulate", HYBRID / "pendulum_wall.yaml", "--backend", backend, "--max-steps", "50",
                     "-o", tmp_path / f"{backend}.csv")
        assert result.exit_code == 1
        assert "the integration reached its bound of 50 steps before t_end" in result.stderr
        stops[backend] = float(re.search(r"failed at t = ([0-9.e+-]+)", result.stderr).group(1))
    assert stops["c"] == pytest.approx(stops["python"], rel=1e-9)
    assert stops["c"] > lagcli.load(HYBRID / "pendulum_wall.yaml").simulate(backend="c").events[1].t


def test_a_restitution_out_of_range_is_exit_status_2(tmp_path):
    result = run("simulate", HYBRID / "bouncing_ball.yaml", "--backend", "c", "--set", "e=2",
                 "-o", tmp_path / "out.csv")
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    assert "event 'floor': restitution = 2 with these parameter values; it must be in [0, 1]" in result.stderr
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.parametrize("name", ["event_impact_uses_velocity", "event_reset_unknown_state",
                                  "event_restitution_outside", "event_unknown_action",
                                  "event_unknown_direction", "law_uses_acceleration"])
def test_bad_event_specs_are_exit_status_2_on_the_c_backend(name, tmp_path):
    result = run("simulate", ROOT / "tests" / "data" / "bad" / f"{name}.yaml", "--backend", "c",
                 "-o", tmp_path / "out.csv")
    expected = (ROOT / "tests" / "data" / "bad" / f"{name}.expected").read_text().strip().splitlines()[0]
    assert result.exit_code == 2 and "Traceback" not in result.stderr
    assert expected.split(": ", 1)[-1] in result.stderr


def test_an_embedding_program_runs_the_generated_event_functions(tmp_path):
    """The generated model's functions, compiled with a user's program: g at a state, and
    the impact law of lagcli_events_impact against the closed form y_dot+ = -e y_dot-."""
    result = run("generate", HYBRID / "bouncing_ball.yaml", "--lang", "c", "-o", tmp_path)
    assert result.exit_code == 0, result.stderr
    (tmp_path / "bouncing_ball_main.c").unlink()
    (tmp_path / "use.c").write_text(r"""
#include <stdio.h>
#include "bouncing_ball.h"
#include "lagcli_events.h"

int main(void)
{
    const double *p = bouncing_ball_parameter_defaults;
    double y[BOUNCING_BALL_NSTATE] = {0.25, -3.0}, g[BOUNCING_BALL_NEVENT], qd[BOUNCING_BALL_NQ], P;
    bouncing_ball_event_functions(0.0, y, p, g);
    if (lagcli_events_impact(&bouncing_ball_model, BOUNCING_BALL_E_floor, 0.0, y, p, qd, &P) != 0)
        return 1;
    printf("%.17g %.17g %.17g %s %d\n", g[0], qd[0], P, bouncing_ball_event_names[0],
           bouncing_ball_event_actions[0]);
    return 0;
}
""")
    sources = sorted(str(p.name) for p in tmp_path.glob("*.c"))
    done = subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", *sources,
                           "-o", "use", "-lm"], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    out = subprocess.run(["./use"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout.split()
    assert float(out[0]) == 0.25                                   # g = y
    assert float(out[1]) == pytest.approx(0.9 * 3.0, rel=1e-15)    # y_dot+ = -e y_dot-
    assert float(out[2]) == pytest.approx(1.0 * 1.9 * 3.0, rel=1e-15)   # P = m (1 + e) |y_dot-|
    assert out[3:] == ["floor", "0"]


def test_the_generated_driver_alone_says_why_its_run_ended_early(tmp_path):
    """The driver of `generate --lang c` run by hand (no --events log for lagcli to read)
    prints the note of `lagcli simulate` on stderr where the bounces accumulate, at the
    closed-form time t1 (1 + e)/(1 - e); with --events the log carries it instead."""
    from test_codegen_c import RUNTIME_SOURCES, compile_c

    assert run("generate", HYBRID / "bouncing_ball.yaml", "--lang", "c", "-o", tmp_path).exit_code == 0
    compile_c(["bouncing_ball.c", "bouncing_ball_main.c", *RUNTIME_SOURCES, "-o", "driver"], tmp_path)
    alone = subprocess.run(["./driver"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    expected = lagcli.load(HYBRID / "bouncing_ball.yaml").simulate(backend="python").end_note
    assert alone.returncode == 0 and alone.stderr == f"note: {expected}\n"
    t_last = float(alone.stdout.splitlines()[-1].split(",")[0])
    assert t_last == pytest.approx((2 / 9.81) ** 0.5 * 1.9 / 0.1, abs=1e-6)     # as test_hybrid_events
    logged = subprocess.run(["./driver", "--events", "log.txt"], cwd=tmp_path, capture_output=True, text=True,
                            timeout=120)
    assert logged.returncode == 0 and logged.stderr == ""
    assert (tmp_path / "log.txt").read_text().splitlines()[-1].startswith("end,recurred,floor,")
