"""The step budget in every runtime of generated code (issue 25): the Rust driver, the
MATLAB/Octave script and the FMU stop after a deterministic number of steps with a clear
message, as `lagcli simulate` and the C driver do (tests/test_step_budget.py). Each test
skips, with the reason, when its tool (cargo, octave-cli, a C compiler and FMPy) is missing.

The reference for "which step" is lagcli's own Python backend at the same budget: the
double pendulum needs ~40 steps up to t = 1, and a budget of 20 stops at t = 0.53001
(scipy's DOP853, which the Rust integrator follows step for step)."""
from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from lagcli.interface import STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT

ROOT = Path(__file__).resolve().parent.parent
DOUBLE_PENDULUM = ROOT / "specs" / "double_pendulum.yaml"


def test_the_rust_driver_states_the_default_budget_of_the_interface():
    text = (ROOT / "lagcli" / "runtime" / "rust" / "driver.rs").read_text()
    assert f"const STEP_BUDGET_BASE: u64 = {STEP_BUDGET_BASE};" in text
    assert f"const STEP_BUDGET_PER_OUTPUT: u64 = {STEP_BUDGET_PER_OUTPUT};" in text


@pytest.fixture(scope="module")
def rust_binary(tmp_path_factory):
    """The double pendulum whose spec asks for the variational method (the Rust driver
    implements RK45 and DOP853 only), built with cargo."""
    from test_codegen_rust import CARGO, build_workspace

    if CARGO is None:
        pytest.skip("no cargo (Rust toolchain): the Rust crate is not built")
    folder = tmp_path_factory.mktemp("rust_budget")
    spec = folder / "double_pendulum.yaml"
    spec.write_text(DOUBLE_PENDULUM.read_text().replace("method: DOP853", "method: variational"))
    assert "method: variational" in spec.read_text()
    return build_workspace({"double_pendulum": spec}, folder / "ws")["double_pendulum"]


def run(binary: Path, *args: str):
    import subprocess

    return subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=300)


def test_rust_driver_stops_at_its_step_budget(rust_binary):
    done = run(rust_binary, "--method", "DOP853", "--t-end", "1", "--max-steps", "20")
    assert done.returncode == 1, done.stderr
    assert "reached its bound of 20 steps before t_end" in done.stderr
    assert "--max-steps N" in done.stderr
    assert re.search(r"error: at t = 0\.53001", done.stderr), done.stderr
    assert len(done.stdout.splitlines()) == 1 + 54          # the rows so far, as the C driver keeps them
    whole = run(rust_binary, "--method", "DOP853", "--t-end", "1")
    assert whole.returncode == 0, whole.stderr               # the default budget: 20000 + 1000 * 100


@pytest.mark.parametrize("args", [["--max-steps", "0"], ["--max-steps", "2.5"], ["--max-steps", "x"]])
def test_rust_driver_refuses_a_bad_budget(rust_binary, args):
    done = run(rust_binary, "--method", "RK45", *args)
    assert done.returncode == 2
    assert "--max-steps: expected a whole number of steps" in done.stderr


def test_rust_driver_refuses_a_method_it_does_not_implement(rust_binary):
    # it used to run DOP853 silently instead of the spec's variational method
    done = run(rust_binary)
    assert done.returncode == 2
    assert done.stdout == ""
    assert "the spec's method 'variational' is not implemented by the Rust driver" in done.stderr
    assert "choose one with --method" in done.stderr
    assert run(rust_binary, "--method", "variational").returncode == 2
    assert run(rust_binary, "--method", "RK45", "--t-end", "0.05").returncode == 0


def octave_run(spec: Path, folder: Path, options: str):
    """Generate `spec` for MATLAB/Octave into `folder`, run its script with `options`."""
    import subprocess

    from lagcli import commands

    octave = shutil.which("octave-cli")
    if octave is None:
        pytest.skip("no octave-cli (Debian package `octave`)")
    commands.generate(str(spec), "octave", str(folder))
    name = next(folder.glob("*_run.m")).stem[:-len("_run")]
    return subprocess.run([octave, "--no-gui", "--norc", "--quiet", "--no-history", "--eval",
                           f"options = {{{options}}}; {name}_run"], cwd=folder, capture_output=True, text=True,
                          timeout=600)


@pytest.mark.parametrize("spec", [DOUBLE_PENDULUM, ROOT / "specs" / "hybrid" / "bouncing_ball.yaml"],
                         ids=["plain", "events"])
def test_octave_script_stops_at_its_step_budget(spec, tmp_path):
    done = octave_run(spec, tmp_path, "'t_end', 1, 'max_steps', 5")
    assert done.returncode == 1, done.stderr
    assert re.search(r"error: at t = [0-9.e-]+: the integration reached its bound of 5 steps before t_end",
                     done.stderr), done.stderr
    assert "'max_steps' option" in done.stderr
    assert done.stdout == ""


def test_octave_script_default_budget_lets_a_run_finish(tmp_path):
    done = octave_run(DOUBLE_PENDULUM, tmp_path, "'t_end', 0.5")
    assert done.returncode == 0, done.stderr
    assert len(done.stdout.splitlines()) == 1 + 51
    text = next(tmp_path.glob("*_simulate.m")).read_text()
    assert f"max_steps = {STEP_BUDGET_BASE} + {STEP_BUDGET_PER_OUTPUT} * ceil(t_end / dt" in text


STIFF_SPRING = """name: stiff_spring
coordinates: [x]
parameters: {m: 1.0, k: 1.0e15}
particles: {P: {mass: m, position: [x, 0]}}
potential: k*x**2/2
initial: {x: 1.0e-6}
simulate: {t_end: 0.02, dt: 0.01}
"""


def test_fmu_co_simulation_step_is_bounded(tmp_path):
    # omega = sqrt(k/m) = 3.2e7 rad/s: DOP853's stability needs h ~ 2e-7 s, ~50 000 steps per
    # communication step of 0.01 s, beyond the budget of one output interval (21 000)
    fmpy = pytest.importorskip("fmpy", reason="FMPy is not installed")
    if shutil.which("cc") is None:
        pytest.skip("--lang fmu needs a C compiler (cc)")
    import lagcli

    (data,) = lagcli.load(STIFF_SPRING).generate("fmu").values()
    fmu = tmp_path / "stiff_spring.fmu"
    fmu.write_bytes(data)
    messages = []
    with pytest.raises(Exception, match="fmi2"):
        fmpy.simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.02, output_interval=0.01,
                          logger=lambda *args: messages.append(args))
    logged = b" ".join(arg for message in messages for arg in message if isinstance(arg, bytes)).decode()
    budget = STEP_BUDGET_BASE + STEP_BUDGET_PER_OUTPUT
    assert f"reached its bound of {budget} steps in one communication step" in logged, logged
    assert "use shorter communication steps" in logged
