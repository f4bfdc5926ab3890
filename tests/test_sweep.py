"""`lagcli sweep` / `System.sweep`: plans, the batch driver, summaries, resume, failures.

Summaries are checked against independent results: the single-run path
(`lagcli simulate`'s CSV of the same run: final row, extrema, first flip time), a
closed form (the rolling disc's stability boundary spin^2 = g / (3 r), docs/analysis.md)
and the same sweep run another way (one worker vs two, interrupted and resumed, CSV vs
Parquet). The Dask cluster test is in tests/test_sweep_dask.py.
"""
from __future__ import annotations

import csv
import io
import math
import shutil

import numpy as np
import pytest
from click.testing import CliRunner

import lagcli
from lagcli.cli import cli
from lagcli.errors import SimulationError, UsageError
from lagcli.sweep.plan import make_plan

from conftest import spec_path

# sweeps run the compiled driver: without a C compiler they cannot (the planning tests still run)
needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc): lagcli sweep runs the compiled driver")

DP = spec_path("double_pendulum")


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


@pytest.fixture(scope="module")
def pendulum():
    return lagcli.load(DP)


def rows_of(text: str) -> list[dict]:
    return list(csv.DictReader(io.StringIO(text)))


def sweep_cli(*args):
    return CliRunner().invoke(cli, ["sweep", *map(str, args)])


# --- plans ----------------------------------------------------------------------------

def test_grid_is_the_product_first_option_slowest():
    plan = make_plan(grids=("a=0:1:2", "b=-1:1:3"))
    assert plan.names == ("a", "b")
    assert plan.values == ((0, -1), (0, 0), (0, 1), (1, -1), (1, 0), (1, 1))


def test_samples_follow_numpy_generator_with_the_seed():
    plan = make_plan(samples=("m=uniform(1,2)", "g=normal(9.81,0.1)"), count=4, seed=3)
    rng = np.random.default_rng(3)
    m, g = rng.uniform(1, 2, 4), rng.normal(9.81, 0.1, 4)
    assert plan.values == tuple(zip(m.tolist(), g.tolist()))
    assert make_plan(samples=("m=uniform(1,2)",), count=4, seed=3).values != \
        make_plan(samples=("m=uniform(1,2)",), count=4, seed=4).values


def test_runs_table_and_constant_expressions(tmp_path):
    table = tmp_path / "runs.csv"
    table.write_text("theta1,m2\npi/2,1\n0.5,2\n")
    plan = make_plan(runs=str(table))
    assert plan.names == ("theta1", "m2") and plan.values == ((math.pi / 2, 1.0), (0.5, 2.0))


@pytest.mark.parametrize("args, expected", [
    ({"grids": ("a=0:1",)}, "NAME=START:STOP:COUNT"),
    ({"grids": ("a=0:1:0",)}, "COUNT must be"),
    ({"samples": ("a=beta(1,2)",), "count": 3}, "uniform(A,B)"),
    ({"samples": ("a=uniform(1,2)",)}, "--count"),
    ({"grids": ("a=0:1:2",), "samples": ("b=uniform(0,1)",), "count": 2}, "one kind of sweep"),
    ({}, "one kind of sweep"),
])
def test_bad_plans_are_usage_errors(args, expected):
    with pytest.raises(UsageError, match=expected.replace("(", r"\(").replace(")", r"\)")):
        make_plan(**args)


def test_unknown_name_exits_2_with_a_hint(tmp_path):
    result = sweep_cli(DP, "--grid", "thta1=0:1:2", "-o", tmp_path / "s.csv")
    assert result.exit_code == 2
    assert "unknown name 'thta1'" in result.output and "did you mean 'theta1'" in result.output
    assert not (tmp_path / "s.csv").exists()


# --- the summary against single runs ----------------------------------------------------

@needs_cc
def test_summary_matches_single_runs_of_simulate(tmp_path):
    out, trajectories = tmp_path / "s.csv", tmp_path / "runs"
    result = sweep_cli(DP, "--grid", "theta1=2:3:2", "--grid", "theta2=-2.5:2.5:2", "--t-end", 4,
                       "--exceed", "theta1=pi", "--exceed", "theta2=pi", "--trajectories", trajectories,
                       "-o", out)
    assert result.exit_code == 0, result.output
    rows = rows_of(out.read_text())
    assert [r["run"] for r in rows] == ["0", "1", "2", "3"]
    for r in rows:
        single = CliRunner().invoke(cli, ["simulate", str(DP), "--t-end", "4", "--init", f"theta1={r['theta1']}",
                                          "--init", f"theta2={r['theta2']}"])
        assert single.exit_code == 0
        header, *lines = single.stdout.splitlines()
        data = np.array([[float(v) for v in line.split(",")] for line in lines])
        col = {name: data[:, k] for k, name in enumerate(header.split(","))}
        assert r["status"] == "ok" and float(r["t_last"]) == 4 and int(r["rows"]) == len(lines)
        for name in ("theta1", "theta2", "theta1_dot", "theta2_dot", "energy"):
            assert float(r[f"final_{name}"]) == col[name][-1]           # same driver: same bits
        for name in ("theta1", "theta2_dot"):
            assert float(r[f"min_{name}"]) == col[name].min() and float(r[f"max_{name}"]) == col[name].max()
        drift = np.abs(col["energy"] - col["energy"][0]).max() / abs(col["energy"][0])
        assert float(r["drift_energy"]) == pytest.approx(drift, rel=1e-12) and drift < 1e-6
        for name in ("theta1", "theta2"):
            flipped = np.nonzero(np.abs(col[name]) > math.pi)[0]
            expected = col["t"][flipped[0]] if len(flipped) else math.nan
            assert float(r[f"exceed_{name}"]) == pytest.approx(expected, nan_ok=True)
        kept = (trajectories / f"run_{r['run']}.csv").read_text()
        assert kept == single.stdout


@needs_cc
def test_worker_count_does_not_change_the_bytes(tmp_path, pendulum):
    grid = {"theta1": (-3, 3, 4), "theta2": (0.5, 2.5, 3)}
    one = pendulum.sweep(grid=grid, t_end=2.0, workers=1, output=str(tmp_path / "one.csv"))
    two = pendulum.sweep(grid=grid, t_end=2.0, workers=3, output=str(tmp_path / "two.csv"))
    assert (tmp_path / "one.csv").read_bytes() == (tmp_path / "two.csv").read_bytes()
    assert one.csv == two.csv and len(one.column("run")) == 12


@needs_cc
def test_interrupted_sweep_resumes_to_the_same_bytes(tmp_path, pendulum):
    grid = {"theta1": (-3, 3, 6), "theta2": (1, 2, 2)}
    whole = pendulum.sweep(grid=grid, t_end=1.0, workers=1, output=str(tmp_path / "whole.csv"))
    out = tmp_path / "part.csv"
    calls = []

    @__import__("contextlib").contextmanager
    def stop_after_first_chunk(total):
        def update(done):
            calls.append(done)
            raise KeyboardInterrupt
        yield update

    from lagcli.sweep import SweepOptions, make_plan, sweep
    from lagcli.sweep.driver import number

    plan = make_plan([f"{k}={number(a)}:{number(b)}:{n}" for k, (a, b, n) in grid.items()])
    with pytest.raises(SimulationError, match="interrupted after .* of 12 runs.*resume"):
        sweep(pendulum, plan, SweepOptions(t_end=1.0, workers=1, output=str(out)),
              progress=stop_after_first_chunk)
    journal = tmp_path / "part.csv.partial"
    assert journal.exists() and not out.exists() and 0 < calls[0] < 12
    notes = []
    resumed = sweep(pendulum, plan, SweepOptions(t_end=1.0, workers=2, output=str(out)), note=notes.append)
    assert notes and notes[0].startswith(f"resuming: {calls[0]} of 12 runs")
    assert out.read_bytes() == (tmp_path / "whole.csv").read_bytes() and resumed.csv == whole.csv
    assert not journal.exists()


@needs_cc
def test_journal_of_another_sweep_is_refused(tmp_path, pendulum):
    out = tmp_path / "s.csv"
    (tmp_path / "s.csv.partial").write_text("# lagcli sweep 00\nrun\n")
    with pytest.raises(UsageError, match="journal of another sweep"):
        pendulum.sweep(grid={"theta1": (0, 1, 2)}, t_end=0.1, output=str(out))


@needs_cc
def test_failed_runs_are_recorded_not_fatal(tmp_path, pendulum):
    # l1 = 0 makes the mass matrix singular; the other runs go on.
    result = pendulum.sweep(runs=[{"l1": 1.0}, {"l1": 0.0}, {"l1": 2.0}], t_end=0.5,
                            output=str(tmp_path / "s.csv"))
    status, failure = result.column("status"), result.column("failure")
    assert list(status) == ["ok", "failed", "ok"]
    assert "singular" in failure[1] and failure[0] == ""
    assert np.isnan(result.column("final_theta1")[1]) or result.column("t_last")[1] < 0.5


@needs_cc
def test_inconsistent_initial_state_is_a_failed_run(tmp_path):
    system = lagcli.load(spec_path("cartesian_pendulum"))
    # x = 2 is off a rod of length 1 whatever y is: that run fails, the others are repaired
    result = system.sweep(grid={"x": (0.5, 2.0, 2)}, t_end=0.2, output=str(tmp_path / "s.csv"))
    assert list(result.column("status")) == ["ok", "failed"]
    assert result.column("failure")[1].startswith("initial state:")
    assert result.column("drift_constraint_residual")[0] < 1e-8


@needs_cc
def test_parquet_summary_has_the_csv_values(tmp_path, pendulum):
    pq = pytest.importorskip("pyarrow.parquet")
    grid = {"theta1": (0, 1, 3)}
    text = pendulum.sweep(grid=grid, t_end=0.5, exceed={"theta1": 10.0}, output=str(tmp_path / "s.csv")).csv
    pendulum.sweep(grid=grid, t_end=0.5, exceed={"theta1": 10.0}, output=str(tmp_path / "s.parquet"))
    table = pq.read_table(tmp_path / "s.parquet").to_pydict()
    rows = rows_of(text)
    assert table["run"] == [0, 1, 2] and table["status"] == ["ok"] * 3
    assert table["final_theta2"] == [float(r["final_theta2"]) for r in rows]
    assert all(math.isnan(v) for v in table["exceed_theta1"])


@needs_cc
def test_rolling_disc_sweep_shows_the_stability_boundary(tmp_path):
    """Upright rolling is stable iff spin^2 > g / (3 r) (docs/analysis.md): a lean of 0.01
    stays below 0.1 on the stable side, grows past 0.3 on the other."""
    system = lagcli.load(spec_path("rolling_disc"))
    p = system.layout.parameter_defaults
    critical = math.sqrt(p["g"] / (3 * p["r"]))
    spins = [critical - 1.3, critical - 0.8, critical - 0.3, critical + 0.7, critical + 1.2, critical + 1.7]
    result = system.sweep(runs=[{"phi_dot": w} for w in spins], initial={"theta": 0.01, "theta_dot": 0.0},
                          t_end=5.0, output=str(tmp_path / "disc.csv"))
    lean = result.column("max_theta")
    assert list(result.column("status")) == ["ok"] * 6
    assert all(lean[:3] > 0.3) and all(lean[3:] < 0.1), lean
    assert all(result.column("drift_energy") < 1e-8)


@needs_cc
def test_no_flip_where_energy_forbids_it(pendulum):
    """Released at rest, the double pendulum (unit masses and rods) has energy
    E = V(start) = -g (2 cos(theta1) + cos(theta2)); any configuration with a rod at
    |theta| = pi has V >= -g (2 - 1) = -g. So no rod can flip when
    2 cos(theta1) + cos(theta2) > 1."""
    result = pendulum.sweep(grid={"theta1": (-2.5, 2.5, 6), "theta2": (-3, 3, 6)}, t_end=3.0,
                            exceed={"theta1": math.pi, "theta2": math.pi})
    th1, th2 = result.column("theta1"), result.column("theta2")
    flip = np.fmin(result.column("exceed_theta1"), result.column("exceed_theta2"))
    forbidden = 2 * np.cos(th1) + np.cos(th2) > 1
    assert forbidden.any() and (~forbidden).any()
    assert np.all(np.isnan(flip[forbidden]))
    assert np.any(~np.isnan(flip[~forbidden]))


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("tty", [True, False])
def test_progress_bar_counts_runs_only_on_a_terminal(monkeypatch, tty):
    import sys

    from lagcli import cli as cli_module

    stream = _Terminal() if tty else io.StringIO()
    monkeypatch.setattr(sys, "stderr", stream)
    with cli_module._count_bar(8) as update:
        assert (update is not None) == tty
        if update:
            for done in (3, 8):
                update(done)
    text = stream.getvalue()
    assert ("runs" in text and "100%" in text) if tty else text == ""


@needs_cc
def test_sample_sweep_from_the_command_line_matches_the_api(tmp_path, pendulum):
    out = tmp_path / "mc.csv"
    result = sweep_cli(DP, "--sample", "m2=uniform(0.5,2)", "--sample", "theta1=normal(1,0.2)", "--count", 5,
                       "--seed", 7, "--t-end", 0.5, "-o", out)
    assert result.exit_code == 0, result.output
    assert "5 runs: 5 ok, 0 failed" in result.stderr
    api = pendulum.sweep(sample={"m2": ("uniform", 0.5, 2), "theta1": ("normal", 1, 0.2)}, count=5, seed=7,
                         t_end=0.5)
    assert out.read_text() == api.csv
