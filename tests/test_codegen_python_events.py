"""The generated Python module runs the spec's events (`lagcli generate --lang python`).

Every bundled spec of specs/hybrid/ without `rest: true` is generated into a temporary
folder, imported from there (numpy and scipy only: the module imports nothing of lagcli),
and its `simulate()` is checked against

- `lagcli simulate` on both backends (the C driver's event loop is a separate
  implementation, lagcli/runtime/c/lagcli_events.c): the same events, times to 1e-9
  relative, the same end note;
- closed forms: the bouncing ball's impact times and apex heights h_k = e^(2k) h0 and its
  accumulation time; the projectile's flight time and range; the rimless wheel's limit
  speed cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma)); the pendulum's energy ratio e^2 at
  the wall; the Cartesian pendulum's rod across impacts on the floor;
- the budgets: a step budget hit is a RuntimeError naming it, the event budget a note.
"""
from __future__ import annotations

import ast
import importlib.util
import math
import shutil

import numpy as np
import pytest

import lagcli

from conftest import SPECS

HYBRID = SPECS / "hybrid"
EVENT_SPECS = ["bouncing_ball", "cartesian_pendulum_floor", "pendulum_wall", "projectile_landing", "rimless_wheel"]


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """name -> the generated module, written to a temporary folder and imported from there."""
    folder, modules = tmp_path_factory.mktemp("generated"), {}

    def get(name):
        if name not in modules:
            (text,) = lagcli.load(HYBRID / f"{name}.yaml").generate("python").values()
            path = folder / f"{name}.py"
            path.write_text(text)
            spec = importlib.util.spec_from_file_location(f"generated_{name}", path)
            modules[name] = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(modules[name])
        return modules[name]
    return get


@pytest.fixture(scope="module")
def runs(generated):
    """name -> (header, rows, events, note) of the generated module's simulate()."""
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = generated(name).simulate()
        return cache[name]
    return get


def column(header, rows, name):
    return rows[:, header.index(name)]


def test_the_generated_module_imports_nothing_of_lagcli(generated):
    path = generated("bouncing_ball").__file__
    imported = set()
    for node in ast.walk(ast.parse(open(path).read())):
        if isinstance(node, ast.Import):
            imported.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            imported.add(node.module.split(".")[0])
    assert imported <= {"math", "numpy", "scipy", "dataclasses", "types"}, imported


@pytest.mark.parametrize("backend", ["python", "c"])
@pytest.mark.parametrize("name", EVENT_SPECS)
def test_events_agree_with_lagcli_simulate(name, backend, runs):
    if backend == "c" and shutil.which("cc") is None:
        pytest.skip("no C compiler (cc): the C backend cannot run")
    header, rows, events, note = runs(name)
    expected = lagcli.load(HYBRID / f"{name}.yaml").simulate(backend=backend)
    assert header == list(expected.columns)
    assert [(r.name, r.action) for r in events] == [(r.name, r.action) for r in expected.events]
    for got, want in zip(events, expected.events):
        assert got.t == pytest.approx(want.t, rel=1e-9, abs=0)
        scale = 1.0 + np.max(np.abs(want.after))
        assert np.max(np.abs(np.subtract(got.after, want.after))) < 1e-9 * scale
        assert (got.impulse is None) == (want.impulse is None)
    assert note == expected.end_note
    assert rows[-1, 0] == pytest.approx(expected.t[-1], rel=1e-9, abs=0)
    assert np.allclose(rows[:, 1:1 + len(events[0].after)], expected.states, rtol=0, atol=1e-8)


def test_bouncing_ball_impact_times_apex_heights_and_accumulation(runs):
    header, rows, events, note = runs("bouncing_ball")
    g, e, h0 = 9.81, 0.9, 1.0
    t1 = math.sqrt(2 * h0 / g)
    expected_t = [t1 * (1 + 2 * sum(e ** j for j in range(1, k + 1))) for k in range(40)]
    assert np.allclose([r.t for r in events[:40]], expected_t, rtol=0, atol=1e-8)
    for k, r in enumerate(events[:40], start=1):          # the apex after the k-th impact
        assert r.after[1] ** 2 / (2 * g) == pytest.approx(e ** (2 * k) * h0, rel=1e-8, abs=1e-12)
        assert r.impulse == pytest.approx(-(1 + e) * r.before[1], rel=1e-12)     # P = m (v+ - v-)
    assert rows[-1, 0] == pytest.approx(t1 * (1 + e) / (1 - e), abs=1e-6)
    assert rows[-1, 0] == events[-1].t                     # the last row is at the last event
    assert "accumulation" in note and "the run ends there" in note
    assert np.all(column(header, rows, "y") > -1e-9)


def test_projectile_flight_time_and_range(runs):
    header, rows, events, note = runs("projectile_landing")
    g, v, a = 9.81, 10.0, 0.7
    assert [r.action for r in events] == ["stop"] and note is None
    assert rows[-1, 0] == pytest.approx(2 * v * math.sin(a) / g, rel=1e-12)
    assert column(header, rows, "x")[-1] == pytest.approx(v ** 2 * math.sin(2 * a) / g, rel=1e-12)


def test_rimless_wheel_converges_to_its_limit_speed(runs):
    header, rows, events, note = runs("rimless_wheel")
    g, l, alpha, gamma = 9.81, 1.0, 0.4, 0.1
    limit = math.sqrt(4 * (g / l) * math.sin(alpha) * math.sin(gamma)) / math.tan(2 * alpha)
    assert len(events) > 30 and {r.action for r in events} == {"reset"}
    assert events[-1].before[0] == pytest.approx(-alpha, abs=1e-10)
    assert events[-1].after[0] == pytest.approx(alpha, abs=1e-10)
    assert abs(events[-1].after[1]) == pytest.approx(limit, rel=1e-8)


def test_pendulum_wall_loses_all_but_e_squared_of_its_energy(runs):
    header, rows, events, note = runs("pendulum_wall")
    m, l, g, e = 1.0, 1.0, 9.81, 0.8

    def energy(state):                       # from the bottom: T + V + m g l
        theta, theta_dot = state
        return m * l ** 2 * theta_dot ** 2 / 2 + m * g * l * (1 - math.cos(theta))

    assert len(events) >= 4
    for r in events:
        assert energy(r.after) == pytest.approx(e ** 2 * energy(r.before), rel=1e-10)


def test_cartesian_pendulum_keeps_its_rod_across_impacts(runs):
    header, rows, events, note = runs("cartesian_pendulum_floor")
    h, e = 0.8, 0.7
    assert len(events) >= 3
    assert np.max(column(header, rows, "constraint_residual")) < 1e-10
    for r in events:
        x, y, xd, yd = r.before
        xp, yp, xdp, ydp = r.after
        assert y == pytest.approx(-h, abs=1e-10)
        assert ydp == pytest.approx(-e * yd, rel=1e-10)                  # G v+ = -e G v-
        assert abs(xp ** 2 + yp ** 2 - 1.0) < 1e-10 and abs(xp * xdp + yp * ydp) < 1e-10


def test_cart_pole_law_without_events_returns_upright(generated):
    """The spec of specs/hybrid/ with a law and no event: (header, rows) as for any smooth spec."""
    header, rows = generated("cart_pole_lqr").simulate()
    theta = column(header, rows, "theta")
    assert theta[0] == pytest.approx(0.2) and abs(theta[-1]) < 1e-4 and np.max(np.abs(rows[-1, 1:5])) < 2e-3
    expected = lagcli.load(HYBRID / "cart_pole_lqr.yaml").simulate(backend="python")
    assert np.allclose(rows[:, 1:5], expected.states, rtol=0, atol=1e-8)


def test_a_step_budget_hit_says_so(generated):
    with pytest.raises(RuntimeError, match=r"bound of 40 steps before t_end.*simulate\(\.\.\., max_steps=N\)"):
        generated("bouncing_ball").simulate(max_steps=40)


def test_the_event_budget_ends_the_run_with_a_note(generated):
    module = generated("pendulum_wall")
    budget = module.EVENT_BUDGET
    module.EVENT_BUDGET = 3                 # the module's own rule, read when the run counts events
    try:
        header, rows, events, note = module.simulate()
    finally:
        module.EVENT_BUDGET = budget
    assert len(events) == 3 and rows[-1, 0] == events[-1].t
    assert note.startswith("3 events (the budget of one run) by t = ")


def test_events_csv_is_the_events_file_of_lagcli_simulate(generated, runs, tmp_path):
    from click.testing import CliRunner

    from lagcli.cli import cli

    out = tmp_path / "bounces.csv"
    result = CliRunner().invoke(cli, ["simulate", str(HYBRID / "projectile_landing.yaml"), "--backend", "python",
                                      "--events", str(out), "-o", str(tmp_path / "rows.csv")])
    assert result.exit_code == 0, result.output
    module = generated("projectile_landing")
    text = module.events_csv(runs("projectile_landing")[2], module.STATE)
    got, want = text.splitlines(), out.read_text().splitlines()
    assert got[0] == want[0] == "t,event,action,x-,y-,x_dot-,y_dot-,x+,y+,x_dot+,y_dot+,impulse"
    assert np.allclose([float(v) for v in got[1].split(",")[3:-1]], [float(v) for v in want[1].split(",")[3:-1]],
                       rtol=1e-9, atol=1e-12)


def test_a_held_contact_is_still_refused_clearly(tmp_path):
    from click.testing import CliRunner

    from lagcli.cli import cli

    result = CliRunner().invoke(cli, ["generate", str(HYBRID / "bouncing_ball_rest.yaml"), "--lang", "python",
                                      "-o", str(tmp_path / "rest.py")])
    assert result.exit_code == 2
    assert "--lang python does not implement an event's rest: true yet" in result.output
    assert not (tmp_path / "rest.py").exists()
