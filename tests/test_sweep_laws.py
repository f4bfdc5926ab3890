"""`lagcli sweep` with input laws (spec `simulate: inputs:`, `--input NAME=EXPR`) and
events: every point against the single-run results (`lagcli simulate` of the same run:
the same driver, the same bytes) and against closed forms (a mass on a spring made by
the law F = -k x; the bouncing ball's accumulation time)."""
from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest

import lagcli
from lagcli.errors import UsageError

from test_hybrid_events import HYBRID, run
from test_hybrid_laws import OSCILLATOR

pytestmark = pytest.mark.skipif(__import__("shutil").which("cc") is None,
                                reason="lagcli sweep runs the compiled driver: no C compiler (cc)")


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


@pytest.fixture()
def oscillator(tmp_path):
    spec = tmp_path / "osc.yaml"
    spec.write_text(OSCILLATOR)
    return spec


def summary(path) -> list[dict]:
    return list(csv.DictReader(io.StringIO(path.read_text())))


def test_each_point_of_a_law_sweep_is_the_single_run(tmp_path):
    """The LQR cart-pole from three tilts: each run's trajectory is, byte for byte, what
    `lagcli simulate --backend c` prints for that run, and the Python backend (scipy,
    the law evaluated by numpy) agrees to 1e-7."""
    spec, out, runs = HYBRID / "cart_pole_lqr.yaml", tmp_path / "s.csv", tmp_path / "runs"
    result = run("sweep", spec, "--grid", "theta=0.1:0.3:3", "--t-end", 1, "--trajectories", runs, "-o", out)
    assert result.exit_code == 0, result.stderr
    rows = summary(out)
    assert [r["status"] for r in rows] == ["ok"] * 3
    system = lagcli.load(spec)
    for r in rows:
        single = run("simulate", spec, "--backend", "c", "--t-end", 1, "--init", f"theta={r['theta']}")
        assert single.exit_code == 0, single.stderr
        assert (runs / f"run_{r['run']}.csv").read_text() == single.stdout
        python = system.simulate(t_end=1.0, initial={"theta": float(r["theta"])}, backend="python")
        for name in ("x", "theta", "x_dot", "theta_dot"):
            assert float(r[f"final_{name}"]) == pytest.approx(python[name][-1], abs=1e-7)
        assert abs(float(r["final_theta"])) < 0.5 * float(r["theta"])       # on its way back upright


def test_law_sweep_against_the_closed_form(oscillator, tmp_path):
    """F = -k x (the spec's law) and F = -2 k x (--input): x = cos(sqrt(k/m) t) at every k;
    a swept input is held at its value instead (x = 1 + F t^2 / (2 m))."""
    for law, factor in ((None, 1.0), ("F=-2*k*x", 2.0)):
        out = tmp_path / f"s{factor}.csv"
        args = ["--input", law] if law else []
        result = run("sweep", oscillator, "--grid", "k=2:18:3", *args, "-o", out)
        assert result.exit_code == 0, result.stderr
        for r in summary(out):
            w = math.sqrt(factor * float(r["k"]) / 2.0)
            assert float(r["final_x"]) == pytest.approx(math.cos(3 * w), abs=1e-8)
            assert float(r["final_x_dot"]) == pytest.approx(-w * math.sin(3 * w), abs=1e-8)
    out = tmp_path / "held.csv"
    result = run("sweep", oscillator, "--grid", "F=0:4:2", "-o", out)
    assert result.exit_code == 0, result.stderr
    assert [float(r["final_x"]) for r in summary(out)] == pytest.approx([1.0, 1.0 + 4 * 9 / 4], abs=1e-9)


def test_api_sweep_takes_laws_as_text_not_callables(oscillator, tmp_path):
    system = lagcli.load(oscillator)
    out = tmp_path / "cli.csv"
    assert run("sweep", oscillator, "--grid", "k=2:8:2", "--input", "F=-2*k*x", "-o", out).exit_code == 0
    api = system.sweep(grid={"k": (2, 8, 2)}, inputs={"F": "-2*k*x"})
    assert api.csv == out.read_text()
    with pytest.raises(UsageError, match="not a Python callable"):
        system.sweep(grid={"k": (2, 8, 2)}, inputs={"F": lambda t, y: -y[0]})


@pytest.mark.parametrize("law, message", [
    ("F=x_ddot", "an input law cannot use accelerations"),
    ("G=x", "unknown input 'G'"),
    ("F=__import__('os')", "is not allowed"),
])
def test_bad_sweep_laws_are_exit_2(oscillator, tmp_path, law, message):
    result = run("sweep", oscillator, "--grid", "k=2:8:2", "--input", law, "-o", tmp_path / "s.csv")
    assert result.exit_code == 2 and message in result.stderr, result.stderr
    assert not (tmp_path / "s.csv").exists()


def test_each_point_of_an_event_sweep_is_the_single_run(tmp_path):
    """The bouncing ball over three restitutions: each trajectory is, byte for byte, the
    single run of `lagcli simulate --backend c`; t_last is the closed-form accumulation
    time t1 (1 + e)/(1 - e) where it comes before t_end, and the Python backend's run ends
    in the same state (1e-7)."""
    spec, out, runs = HYBRID / "bouncing_ball.yaml", tmp_path / "s.csv", tmp_path / "runs"
    result = run("sweep", spec, "--grid", "e=0.5:0.9:3", "--t-end", 3, "--trajectories", runs, "-o", out)
    assert result.exit_code == 0, result.stderr
    system = lagcli.load(spec)
    t1 = math.sqrt(2 / 9.81)
    for r in summary(out):
        e = float(r["e"])
        single = run("simulate", spec, "--backend", "c", "--t-end", 3, "--set", f"e={r['e']}")
        assert single.exit_code == 0, single.stderr
        assert (runs / f"run_{r['run']}.csv").read_text() == single.stdout
        assert r["status"] == "ok"
        assert float(r["t_last"]) == pytest.approx(min(3.0, t1 * (1 + e) / (1 - e)), abs=1e-6)
        python = system.simulate(t_end=3.0, parameters={"e": e}, backend="python")
        assert float(r["final_y"]) == pytest.approx(python["y"][-1], abs=1e-7)
        assert float(r["final_y_dot"]) == pytest.approx(python["y_dot"][-1], abs=1e-7)


def test_a_held_contact_is_refused_clearly(tmp_path):
    result = run("sweep", HYBRID / "bouncing_ball_rest.yaml", "--grid", "e=0.5:0.9:2", "-o", tmp_path / "s.csv")
    assert result.exit_code == 2, result.stderr
    assert "lagcli sweep runs the compiled C driver, which cannot run this spec" in result.stderr
    assert "rest: true" in result.stderr and not (tmp_path / "s.csv").exists()
