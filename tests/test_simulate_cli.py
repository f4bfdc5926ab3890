"""`lagcli simulate` as a command: options, exit codes, messages, files.

Exit status 2 for bad invocations (unknown or malformed --set/--init, a state
that violates a constraint and cannot be repaired), 1 for run-time failures
(a blow-up), with the rows computed so far kept in a CSV that parses.
"""
from __future__ import annotations

import csv
import io
import math
import os
import shutil
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.runtime.run_rules import output_times
from lagcli.run.rows import parse_csv

import lagcli
from conftest import ROOT, spec_path

BLOWUP = """\
# x'' = 4 k x^3 / m: x reaches infinity in finite time (about t = 0.927 from x = 1)
name: blowup
coordinates: [x]
parameters: {m: 1.0, k: 1.0}
kinetic: m*x_dot**2/2
potential: -k*x**4
initial: {x: 1.0, x_dot: 0.0}
simulate: {t_end: 2.0, dt: 0.01}
"""


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def invoke(*args: str):
    return CliRunner().invoke(cli, ["simulate", *map(str, args)])


def columns(text: str) -> dict[str, np.ndarray]:
    header, rows = parse_csv(text)
    data = np.array(rows).reshape(len(rows), len(header))
    return {name: data[:, i] for i, name in enumerate(header)}


def test_help_lists_every_option():
    result = CliRunner().invoke(cli, ["simulate", "--help"])
    assert result.exit_code == 0
    for option in ("--t-end", "--dt", "--method", "--rtol", "--atol", "--set", "--init",
                   "--backend", "--baumgarte", "--output", "--plot"):
        assert option in result.stdout


def test_columns_and_output_times_follow_the_contract():
    result = invoke(spec_path("cartesian_pendulum"), "--t-end", "0.35", "--dt", "0.1")
    assert result.exit_code == 0, result.stderr
    header, rows = parse_csv(result.stdout)
    assert header == ["t", "x", "y", "x_dot", "y_dot", "lambda_rod", "energy", "jacobi",
                      "constraint_residual"]
    assert [r[0] for r in rows] == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.35], abs=1e-15)
    assert output_times(1.0, 0.1)[-1] == pytest.approx(1.0) and len(output_times(1.0, 0.1)) == 11
    first = result.stdout.splitlines()[1].split(",")
    assert first[:5] == ["0", "0.59999999999999998", "-0.80000000000000004",
                         "0.40000000000000002", "0.29999999999999999"]   # %.17g
    assert result.stderr == ""


def test_writes_file_atomically_and_nothing_on_stdout(tmp_path):
    out = tmp_path / "sub" / "traj.csv"
    out.parent.mkdir()                   # -o into a missing directory: tests/test_output_files.py
    result = invoke(spec_path("double_pendulum"), "--t-end", "0.1", "-o", out)
    assert result.exit_code == 0, result.stderr
    assert result.stdout == ""
    rows = list(csv.reader(io.StringIO(out.read_text())))
    assert rows[0][:3] == ["t", "theta1", "theta2"] and len(rows) == 12
    assert [p.name for p in out.parent.iterdir()] == ["traj.csv"]     # no temporary left


def test_set_and_init_take_constant_expressions():
    result = invoke(spec_path("double_pendulum"), "--t-end", "0", "--set", "l2=sqrt(4)",
                    "--init", "theta1=pi/4", "--init", "theta2_dot=-1e-1")
    assert result.exit_code == 0, result.stderr
    c = columns(result.stdout)
    assert c["theta1"][0] == math.pi / 4 and c["theta2_dot"][0] == -0.1
    assert c["theta2"][0] == 0.5                                      # from the spec's initial:
    kinetic = 0.5 * 1.0 * 2.0**2 * 0.1**2                            # m2 l2^2 theta2_dot^2 / 2
    potential = -9.81 * (2 * math.cos(math.pi / 4) + 2 * math.cos(0.5))
    assert c["energy"][0] == pytest.approx(kinetic + potential, rel=1e-12)


@pytest.mark.parametrize("option, item, expected", [
    ("--set", "mm1=2", "did you mean 'm1'?"),
    ("--set", "mm=2", "did you mean 'm2'?"),
    ("--init", "theta3=1", "did you mean 'theta2'?"),
    ("--init", "theta1_ddot=1", "unknown coordinate or velocity 'theta1_ddot'"),
    ("--set", "m1", "expected NAME=VALUE"),
    ("--set", "m1=", "expected NAME=VALUE"),
    ("--set", "m1=abc", "abc"),
    ("--set", "m1=__import__('os')", "m1"),
    ("--set", "m1=nan", "not a finite number"),
    ("--init", "theta1=1/0", "theta1"),
])
def test_bad_overrides_exit_2(option, item, expected):
    result = invoke(spec_path("double_pendulum"), "--t-end", "0.1", option, item)
    assert result.exit_code == 2, result.output
    assert expected in result.stderr
    assert result.stdout == "" and "Traceback" not in result.stderr


@pytest.mark.parametrize("args, expected", [
    (("--dt", "0"), "--dt"), (("--t-end", "-1"), "--t-end"), (("--rtol", "0"), "--rtol"),
    (("--method", "Euler"), "Euler"), (("--backend", "fortran"), "fortran"),
])
def test_bad_settings_exit_2(args, expected):
    result = invoke(spec_path("double_pendulum"), *args)
    assert result.exit_code == 2
    assert expected in result.stderr


def test_dependent_coordinates_and_velocities_are_solved_for():
    result = invoke(spec_path("cartesian_pendulum"), "--t-end", "0", "--init", "x=0.5",
                    "--init", "x_dot=0.2")
    assert result.exit_code == 0, result.stderr
    c = columns(result.stdout)
    assert c["y"][0] == pytest.approx(-math.sqrt(1 - 0.25), abs=1e-12)    # hangs down, l = 1
    assert c["x"][0] * c["x_dot"][0] + c["y"][0] * c["y_dot"][0] == pytest.approx(0, abs=1e-12)
    assert "solved for dependent coordinates: y = -0.866025403784" in result.stderr
    assert "solved for dependent velocities: y_dot = 0.11547005383" in result.stderr


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=pytest.mark.skipif(
    shutil.which("cc") is None, reason="no C compiler (cc)"))])
def test_init_keeps_the_spec_velocities_projected_onto_the_rod(backend):
    """--init x=0.5 alone: y is solved for (hanging down) and the spec's (x', y') =
    (0.4, 0.3) is changed as little as possible: projected onto the rod's tangent."""
    result = invoke(spec_path("cartesian_pendulum"), "--t-end", "0", "--init", "x=0.5", "--backend", backend)
    assert result.exit_code == 0, result.stderr
    c = columns(result.stdout)
    x, y = 0.5, -math.sqrt(1 - 0.25)                      # l = 1
    tangent = np.array([-y, x])                           # unit vector, perpendicular to (x, y)
    expected = tangent * (tangent @ [0.4, 0.3])           # least-norm change from (0.4, 0.3)
    assert c["y"][0] == pytest.approx(y, abs=1e-12)
    assert [c["x_dot"][0], c["y_dot"][0]] == pytest.approx(list(expected), abs=1e-12)
    assert expected[0] == pytest.approx(0.4299038105676658) and expected[1] > 0.2
    assert "solved for dependent velocities: x_dot = 0.429903810568, y_dot = 0.248205080757" in result.stderr


def test_unrepairable_state_exits_2_naming_the_constraint():
    result = invoke(spec_path("cartesian_pendulum"), "--init", "x=0.5", "--init", "y=0.5")
    assert result.exit_code == 2
    assert "constraint 'rod'" in result.stderr and "x**2 + y**2 - l**2" in result.stderr
    assert "residual -0.5" in result.stderr
    assert result.stdout == ""


def test_unrepairable_velocity_exits_2():
    result = invoke(spec_path("cartesian_pendulum"), "--init", "x_dot=1", "--init", "y_dot=1")
    assert result.exit_code == 2
    assert "velocity residual" in result.stderr


@pytest.mark.parametrize("backend", ["python", "c"])
def test_blow_up_exits_1_with_a_valid_partial_csv(tmp_path, backend):
    if backend == "c" and not __import__("shutil").which("cc"):
        pytest.skip("no C compiler")
    spec = tmp_path / "blowup.yaml"
    spec.write_text(BLOWUP)
    out = tmp_path / "blowup.csv"
    result = invoke(spec, "--backend", backend, "-o", out)
    assert result.exit_code == 1
    assert "integration failed at t = 0.92" in result.stderr
    assert "kept in" in result.stderr
    c = columns(out.read_text())
    assert 0.9 <= c["t"][-1] < 0.93 and len(c["t"]) == round(c["t"][-1] / 0.01) + 1
    assert np.all(np.isfinite(c["x"])) and c["x"][-1] > 10


def test_missing_spec_exits_2(tmp_path):
    result = invoke(tmp_path / "nope.yaml")
    assert result.exit_code == 2


def test_python_backend_supports_implicit_methods(derived):
    from lagcli.interface import RunSettings
    from lagcli.run.python_backend import integrate_module
    from lagcli.system import System

    d = derived("double_pendulum")
    module = System(d, Path(d.model.source).read_bytes()).program("python").module
    p = [prm.value for prm in d.model.parameters]
    e0 = -9.81 * (2 * math.cos(1.0) + math.cos(0.5))        # E(0), conserved
    for method in ("Radau", "BDF", "LSODA", "RK45", "DOP853"):
        settings = RunSettings(0.2, 0.1, method, 1e-8, 1e-10, 10.0, 10.0)
        traj = integrate_module(module, p, [1.0, 0.5, 0.0, 0.0], settings)
        assert traj.failure is None and len(traj.lines) == 3
        energy = columns(traj.csv_text())["energy"]
        assert energy[0] == pytest.approx(e0, rel=1e-14) and abs(energy[-1] - e0) < 1e-5


def test_c_backend_rejects_implicit_methods_but_default_falls_back():
    explicit = invoke(spec_path("double_pendulum"), "--t-end", "0.1", "--method", "Radau", "--backend", "c")
    assert explicit.exit_code == 2 and "--backend python" in explicit.stderr
    default = invoke(spec_path("double_pendulum"), "--t-end", "0.1", "--method", "Radau")
    assert default.exit_code == 0, default.stderr


def test_plot_is_written(tmp_path):
    png = tmp_path / "traj.png"
    result = invoke(spec_path("cartesian_pendulum"), "--t-end", "2", "-o", tmp_path / "t.csv", "--plot", png)
    assert result.exit_code == 0, result.stderr
    data = png.read_bytes()
    assert data.startswith(b"\x89PNG\r\n\x1a\n") and len(data) > 20_000


def test_plot_without_matplotlib_exits_1_after_the_csv(tmp_path, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_matplotlib(name, *args, **kwargs):
        if name.startswith("matplotlib"):
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_matplotlib)
    out = tmp_path / "t.csv"
    result = invoke(spec_path("double_pendulum"), "--t-end", "0.1", "-o", out, "--plot", tmp_path / "p.png")
    assert result.exit_code == 1
    assert "lagcli[plot]" in result.stderr
    assert out.exists() and not (tmp_path / "p.png").exists()


def test_drift_panel_shows_only_conserved_columns():
    from lagcli.viz.plot import drift_series

    kinds = {"t": "time", "q1": "coordinate", "q1_dot": "velocity", "energy": "energy", "jacobi": "jacobi",
             "p_phi": "momentum", "constraint_residual": "residual"}
    assert drift_series(kinds, energy_conserved=True) == [
        ("jacobi", "jacobi = energy"), ("p_phi", "p_phi"), ("constraint_residual", "constraint_residual")]
    assert drift_series({"t": "time", "q": "coordinate", "q_dot": "velocity", "energy": "energy"},
                        energy_conserved=False) == []
    # by kind, not by name: a coordinate called p_x is drawn with the coordinates
    assert drift_series({"t": "time", "p_x": "coordinate", "p_x_dot": "velocity"}, True) == []


def test_plot_figure_has_two_labelled_panels_and_a_log_scale(tmp_path):
    from lagcli.viz.plot import PlotOptions, build_figure
    from lagcli.run.rows import Trajectory

    result = invoke(spec_path("cartesian_pendulum"), "--t-end", "1", "--dt", "0.1")
    assert result.exit_code == 0, result.stderr
    header, *lines = result.stdout.splitlines()
    kinds = lagcli.load(spec_path("cartesian_pendulum")).layout.kinds
    figure = build_figure(Trajectory(header.split(","), lines), ["x", "y"], True, "cartesian",
                          PlotOptions(kinds=kinds))
    top, bottom = figure.axes
    assert top.get_ylabel() == "coordinates" and bottom.get_xlabel() == "t" and bottom.get_ylabel()
    assert [t.get_text() for t in top.get_legend().get_texts()] == ["x", "y"]
    assert [t.get_text() for t in bottom.get_legend().get_texts()] == [
        "jacobi = energy: relative drift", "constraint_residual (absolute)"]
    assert top.get_yscale() == "linear" and bottom.get_yscale() == "log"
    assert top.get_title() == "cartesian"
    unconserved = build_figure(Trajectory(["t", "q", "q_dot", "energy"], ["0,1,0,2", "1,2,0,3"]),
                               ["q"], False, "driven")
    assert len(unconserved.axes) == 1 and unconserved.axes[0].get_xlabel() == "t"


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("tty", [True, False])
def test_progress_bar_only_on_a_terminal(monkeypatch, tty):
    from lagcli import cli as cli_module

    stream = _Terminal() if tty else io.StringIO()
    monkeypatch.setattr(sys, "stderr", stream)
    with cli_module._progress_bar(2.0) as update:
        assert (update is not None) == tty
        if update:
            for t in (0.5, 1.0, 2.0):
                update(t)
    text = stream.getvalue()
    assert ("simulating" in text and "100%" in text) if tty else text == ""


def test_interrupt_while_deriving_exits_1(monkeypatch):
    import lagcli.derive

    def interrupted(model):
        raise KeyboardInterrupt

    monkeypatch.setattr(lagcli.derive, "derive", interrupted)
    result = invoke(spec_path("double_pendulum"), "--backend", "python", "--t-end", "0.1")
    assert result.exit_code == 1
    assert "interrupted before the integration started" in result.stderr
    assert "Aborted" not in result.output and result.stdout == ""


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
def test_interrupt_while_compiling_exits_1_and_leaves_no_cache_entry(tmp_path, monkeypatch):
    from lagcli.run import c_backend

    def interrupted(*args):
        raise KeyboardInterrupt

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(c_backend.toolchain, "compile_program", interrupted)
    out = tmp_path / "run.csv"
    result = invoke(spec_path("double_pendulum"), "--backend", "c", "--t-end", "0.1", "-o", out)
    assert result.exit_code == 1
    assert "interrupted before the integration started" in result.stderr and "Aborted" not in result.output
    assert not out.exists() and list((tmp_path / "cache" / "lagcli").iterdir()) == []


def _read_all(fd: int, sink: list) -> None:
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:                    # EIO: the child closed the terminal
            return
        if not chunk:
            return
        sink.append(chunk)


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=pytest.mark.skipif(
    shutil.which("cc") is None, reason="no C compiler (cc)"))])
def test_ctrl_c_keeps_the_rows_and_exits_1(tmp_path, backend):
    """A real SIGINT, with stderr a terminal (so the progress bar is drawn: we wait for it
    to know the integration has started); the rows so far are kept in a CSV that parses."""
    master, slave = os.openpty()
    out = tmp_path / "run.csv"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp_path / "cache")}
    proc = subprocess.Popen([sys.executable, "-m", "lagcli", "simulate", str(spec_path("double_pendulum")),
                             "--backend", backend, "--t-end", "1e6", "--dt", "0.5", "-o", str(out)],
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave, env=env)
    os.close(slave)
    chunks: list[bytes] = []
    reader = threading.Thread(target=_read_all, args=(master, chunks), daemon=True)
    reader.start()
    try:
        deadline = time.monotonic() + 120
        while b"simulating" not in b"".join(chunks) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert b"simulating" in b"".join(chunks), b"".join(chunks).decode(errors="replace")
        time.sleep(0.5)
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=60) == 1
    finally:
        if proc.poll() is None:
            proc.kill()
        reader.join(timeout=10)
        os.close(master)
    stderr = b"".join(chunks).decode(errors="replace")
    assert "interrupted (" in stderr and f"kept in {out}" in stderr
    assert "Traceback" not in stderr and "Aborted" not in stderr
    c = columns(out.read_text())
    assert len(c["t"]) >= 2 and np.all(np.diff(c["t"]) == pytest.approx(0.5))
    assert f"{len(c['t'])} rows up to t = {c['t'][-1]:.10g}" in stderr


# Streaming: rows reach the output as they are computed, memory stays flat, and
# SIGTERM/SIGHUP end a run like Ctrl-C (lagcli/render/output.py, lagcli/run/rows.py).

BACKENDS = ["python", pytest.param("c", marks=pytest.mark.skipif(shutil.which("cc") is None,
                                                                 reason="no C compiler (cc)"))]


def _start_long_run(tmp_path, backend: str, *extra: str) -> tuple[subprocess.Popen, "os.PathLike"]:
    """`lagcli simulate` of the double pendulum up to t = 1e6 (1e8 rows at dt 0.01) in a
    subprocess, returned once its rows are streaming into the temporary output file."""
    out = tmp_path / "traj.csv"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp_path.parent / "stream-cache")}
    proc = subprocess.Popen([sys.executable, "-m", "lagcli", "simulate", str(spec_path("double_pendulum")),
                             "--backend", backend, "--t-end", "1e6", "--dt", "0.01", "-o", str(out), *extra],
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    deadline = time.monotonic() + 300
    while proc.poll() is None and time.monotonic() < deadline:
        if any(p.stat().st_size > 20_000 for p in tmp_path.glob(".traj.csv.*.lagcli.tmp")):
            return proc, out
        time.sleep(0.05)
    proc.kill()
    raise AssertionError(f"no rows streamed: {proc.communicate()[1].decode(errors='replace')}")


def _stop(proc: subprocess.Popen, number: int) -> tuple[int, str]:
    proc.send_signal(number)
    try:
        _, stderr = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    return proc.returncode, stderr.decode(errors="replace")


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("number", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_sigterm_and_sighup_keep_the_rows_like_ctrl_c(tmp_path, backend, number):
    proc, out = _start_long_run(tmp_path, backend)
    drivers = _descendants(proc.pid)
    assert len(drivers) == (backend == "c")
    code, stderr = _stop(proc, number)
    assert code == 1, stderr
    assert "interrupted (" in stderr and f"kept in {out}" in stderr and "Traceback" not in stderr
    c = columns(out.read_text())
    assert len(c["t"]) > 10 and np.all(np.diff(c["t"]) == pytest.approx(0.01))
    assert f"{len(c['t'])} rows up to t = {c['t'][-1]:.10g}" in stderr
    assert [p.name for p in tmp_path.iterdir()] == ["traj.csv"]          # no temporary file left
    assert not [pid for pid in drivers if os.path.exists(f"/proc/{pid}")]   # the driver was stopped


def _children(pid: int) -> list[int]:
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as handle:
                    fields = handle.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.append(int(entry))
    return found


def _descendants(pid: int) -> list[int]:
    children = _children(pid)
    return children + [grandchild for child in children for grandchild in _descendants(child)]


def _tree_rss_kb(pid: int) -> int:
    """VmRSS of `pid` and its descendants (the C driver), in kB."""
    total = 0
    for member in [pid, *_descendants(pid)]:
        try:
            with open(f"/proc/{member}/status") as handle:
                total += next(int(line.split()[1]) for line in handle if line.startswith("VmRSS:"))
        except (OSError, StopIteration):
            pass                               # exited meanwhile
    return total


@pytest.mark.slow
@pytest.mark.parametrize("backend", BACKENDS)
def test_a_1e8_row_run_streams_in_flat_memory(tmp_path, backend):
    """The issue's run: --t-end 1e6 --dt 0.01 (1e8 rows) under 200 MB for the whole process
    tree while it streams (sampled for a few seconds, with --plot's bounded copy too),
    then SIGTERM: the rows written so far are a valid CSV."""
    proc, out = _start_long_run(tmp_path, backend, "--plot", str(tmp_path / "traj.png"))
    samples, sizes = [], []
    for _ in range(40):
        samples.append(_tree_rss_kb(proc.pid))
        sizes.append(sum(p.stat().st_size for p in tmp_path.glob(".traj.csv.*")))
        time.sleep(0.1)
    code, stderr = _stop(proc, signal.SIGTERM)
    assert code == 1, stderr
    assert max(samples) < 200 * 1024, samples
    assert sizes[-1] > sizes[0] > 0                                      # written as computed
    c = columns(out.read_text())
    assert len(c["t"]) > 1000 and np.all(np.diff(c["t"]) > 0)


def test_output_time_windows_do_not_change_the_python_backend_rows(derived, monkeypatch):
    """Output times made 7 at a time give the very same rows as one window: the solver
    runs on across windows (no restart)."""
    import functools

    from lagcli.runtime.run_rules import output_time_windows
    from lagcli.interface import RunSettings
    from lagcli.run import python_backend
    from lagcli.system import System

    d = derived("double_pendulum")
    module = System(d, Path(d.model.source).read_bytes()).program("python").module
    p = [prm.value for prm in d.model.parameters]
    settings = RunSettings(0.55, 0.01, "DOP853", 1e-9, 1e-12, 10.0, 10.0)
    whole = python_backend.integrate_module(module, p, [1.0, 0.5, 0.0, 0.0], settings)
    monkeypatch.setattr(python_backend, "output_time_windows", functools.partial(output_time_windows, size=7))
    windowed = python_backend.integrate_module(module, p, [1.0, 0.5, 0.0, 0.0], settings)
    assert windowed.lines == whole.lines and len(whole.lines) == 56 and windowed.last_time == 0.55


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
def test_the_c_driver_runs_on_across_its_output_time_windows(tmp_path):
    """The driver makes 65536 output times at a time, restarting from the last row's state:
    a run over that boundary keeps every output time t_k = k dt and the energy."""
    out = tmp_path / "long.csv"
    result = invoke(spec_path("double_pendulum"), "--backend", "c", "--t-end", "700", "--dt", "0.01", "-o", out)
    assert result.exit_code == 0, result.stderr
    c = columns(out.read_text())
    assert len(c["t"]) == 70001 and np.array_equal(c["t"], np.arange(70001) * 0.01)
    energy = c["energy"]
    assert np.max(np.abs(energy - energy[0])) < 1e-6
    jumps = np.abs(np.diff(c["theta1"]))
    assert jumps[65535] < 2 * max(jumps[65530:65535].max(), jumps[65536:65541].max())   # smooth at the seam


def test_t_end_just_below_the_last_output_time_works_on_both_backends():
    """--t-end 0.3 --dt 0.1: the last t_k is 3 * 0.1 = 0.30000000000000004 > 0.3."""
    rows = {}
    for backend in ("python", "c") if shutil.which("cc") else ("python",):
        result = invoke(spec_path("double_pendulum"), "--t-end", "0.3", "--dt", "0.1", "--backend", backend)
        assert result.exit_code == 0, result.stderr
        rows[backend] = np.array(parse_csv(result.stdout)[1])
    assert [r[0] for r in rows["python"]] == [0.0, 0.1, 0.2, 3 * 0.1]
    if "c" in rows:
        assert np.allclose(rows["c"], rows["python"], rtol=1e-9, atol=1e-12)
