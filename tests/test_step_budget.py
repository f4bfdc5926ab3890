"""A run never goes on forever: a deterministic bound on integrator steps (`--max-steps`,
default 20000 + 1000 per output interval) on the Python backend, the C driver and the
generated driver alike, with exit status 1 and a message naming the bound (issue 25)."""
from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.interface import STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT, default_max_steps

ROOT = Path(__file__).resolve().parent.parent
DRIVER = ROOT / "lagcli" / "runtime" / "c" / "lagcli_driver.c"
BACKENDS = ["python", pytest.param("c", marks=pytest.mark.skipif(shutil.which("cc") is None,
                                                                 reason="no C compiler (cc)"))]


def test_the_default_budget_is_the_same_rule_in_python_and_c():
    text = DRIVER.read_text()
    assert f"#define LAGCLI_STEP_BUDGET_BASE {STEP_BUDGET_BASE} " in text
    assert f"#define LAGCLI_STEP_BUDGET_PER_OUTPUT {STEP_BUDGET_PER_OUTPUT} " in text
    assert default_max_steps(10.0, 0.01) == 20_000 + 1_000 * 1000
    assert default_max_steps(0.02, 0.01) == 22_000


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_run_beyond_its_step_budget_stops_with_a_clear_error(backend, tmp_path):
    # the double pendulum needs ~40 steps up to t = 1: a budget of 20 stops it at the same
    # step on both backends (the same algorithm, the same step sizes)
    out = tmp_path / "rows.csv"
    result = CliRunner().invoke(cli, ["simulate", str(ROOT / "specs" / "double_pendulum.yaml"), "--t-end", "1",
                                      "--max-steps", "20", "--backend", backend, "-o", str(out)])
    assert result.exit_code == 1, result.output
    assert "reached its bound of 20 steps before t_end" in result.output
    assert "--max-steps N" in result.output
    assert re.search(r"at t = 0\.53001", result.output), result.output
    assert len(out.read_text().splitlines()) == 1 + 54      # the rows so far are kept


# the Python backend takes ~25 s to walk 22 000 tiny steps: it runs with `pytest -m slow`; the
# bound itself is checked on both backends by the test above, the runaway on C by default
RUNAWAY_BACKENDS = [pytest.param("python", marks=pytest.mark.slow), *BACKENDS[1:]]


@pytest.mark.parametrize("backend", RUNAWAY_BACKENDS)
def test_a_runaway_state_ends_within_the_default_budget(backend, tmp_path):
    # a wheel on an incline started with a garbage spin rate (what an ill-conditioned
    # repair used to produce: psi_dot ~ 6.7e10): the steps shrink to nothing; the run used to
    # go on for ever on both backends, now it stops after 22000 steps (t_end 0.02, dt 0.01)
    spec = tmp_path / "wheel.yaml"
    spec.write_text(WHEEL_ON_INCLINE.replace("INITIAL", "{z: 0.3, theta: 1e-10, x_dot: 1.0, y_dot: 0.003, "
                                             "phi_dot: -3.33, psi_dot: 66633332953.7, theta_dot: -0.01}"))
    result = CliRunner().invoke(cli, ["simulate", str(spec), "--t-end", "0.02", "--backend", backend,
                                      "-o", str(tmp_path / "rows.csv")])
    assert result.exit_code == 1, result.output
    assert "reached its bound of 22000 steps" in result.output


WHEEL_ON_INCLINE = """coordinates: [x, y, z, psi, theta, phi]
parameters: {m: 1.0, r: 0.3, g: 9.81, a: 0.2}
gravity: [0, 0, -g]
frames: {D: {rotations: [[z, psi], [x, theta], [y, phi]]}}
bodies:
  disc: {mass: m, inertia: [m*r**2/4, m*r**2/2, m*r**2/4], position: [x, y, z], frame: D}
rolling: [{body: disc, wheel: {radius: r, axis: y}, surface: {normal: [0, -sin(a), cos(a)]}}]
initial: INITIAL
"""


def test_a_run_with_events_keeps_the_step_budget_too(tmp_path):
    result = CliRunner().invoke(cli, ["simulate", str(ROOT / "specs" / "hybrid" / "bouncing_ball.yaml"),
                                      "--max-steps", "5", "--backend", "python", "-o", str(tmp_path / "rows.csv")])
    assert result.exit_code == 1, result.output
    assert "reached its bound of 5 steps before t_end" in result.output
