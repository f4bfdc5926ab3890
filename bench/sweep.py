"""Benchmark `lagcli sweep`: 10 000 double-pendulum runs against their bare C cost,
and the flip-time picture from the sweep's summary.

Run from the project root:

    PYTHONPATH=. .venv/bin/python bench/sweep.py [--n 100] [--repeat 1] [--png bench/flip_time.png]

The runs: an n x n grid of initial angles theta1, theta2 in [-3, 3] (n = 100: 10 000
runs), released at rest, 10 s each with the spec's tolerances (DOP853, rtol 1e-10,
atol 1e-12, dt 0.01); the summary has exceed_theta1 and exceed_theta2, the first
output time with |theta| > pi (a flip of that rod).

Prints the wall time (median of `repeat`) of

  1. bare C integration   the same compiled driver, one process, no Python: its batch
                          mode with the hidden --bench-integration integrates every
                          run with the same steps and dense output but no rows and
                          no summary, and reports the summed clock() time
  2. driver batch alone   the same driver, one process, computing and printing every
                          summary from a file of run lines (no Python)
  3. System.sweep         the sweep from Python, every core, system loaded and driver
                          cached: initial states, chunks, driver processes, summary
  4. lagcli sweep         the whole command in a fresh process (derivation included)

each with its CPU time (this process and its children), and the ratios to (1) (target:
(3) within 2x of (1)). On a shared machine the wall times depend on the load; the CPU
ratio is the overhead the sweep adds to the integrations. Then renders the flip-time
picture: log10 of the time until either rod flips, over the grid of initial angles
(white: no flip within 10 s), from the summary written by (4).
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPEC = ROOT / "specs" / "double_pendulum.yaml"
PI = "3.141592653589793"


def median_time(action, repeat: int) -> tuple[float, float]:
    """Median (wall, CPU) seconds of `action`; CPU: this process and its waited-for children."""
    walls, cpus = [], []
    for _ in range(repeat):
        start, cpu = time.perf_counter(), _cpu()
        action()
        walls.append(time.perf_counter() - start)
        cpus.append(_cpu() - cpu)
    return statistics.median(walls), statistics.median(cpus)


def _cpu() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100, help="grid points per angle (n*n runs)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--png", default=str(ROOT / "bench" / "flip_time.png"))
    args = parser.parse_args()
    os.environ.setdefault("XDG_CACHE_HOME", tempfile.mkdtemp(prefix="lagcli-bench-"))

    import lagcli
    from lagcli.sweep import SweepOptions, make_plan, sweep
    from lagcli.sweep import run as sweep_run

    grid = [f"theta1=-3:3:{args.n}", f"theta2=-3:3:{args.n}"]
    system = lagcli.load(SPEC)
    plan = make_plan(grid)
    options = SweepOptions(exceed={"theta1": math.pi, "theta2": math.pi})
    program, _ = sweep_run._driver(system)
    settings = sweep_run._settings(system, options)
    lines, _ = sweep_run._run_lines(system, plan, options, sweep_run._kinds(system.layout, plan, options))
    text = "".join(lines[k] for k in sorted(lines))
    base = sweep_run._arguments(settings, options.exceed, False)
    runs = len(plan)

    bare = []

    def bare_c():
        done = subprocess.run([program, *base, "--bench-integration", "1"], input=text, text=True,
                              capture_output=True, check=True)
        bare.append(float(done.stderr.split("total_s")[1]))

    wall_bare = median_time(bare_c, args.repeat)
    t_bare = statistics.median(bare)
    t_batch = median_time(lambda: subprocess.run([program, *base], input=text, text=True, check=True,
                                                 stdout=subprocess.DEVNULL), args.repeat)
    t_api = median_time(lambda: sweep(system, plan, options), args.repeat)
    with tempfile.TemporaryDirectory() as work:
        summary = Path(work) / "flip.csv"
        command = [sys.executable, "-m", "lagcli", "sweep", str(SPEC), *sum((["--grid", g] for g in grid), []),
                   "--exceed", f"theta1={PI}", "--exceed", f"theta2={PI}", "-o", str(summary)]
        t_cli = median_time(lambda: subprocess.run(command, check=True, stderr=subprocess.DEVNULL), args.repeat)
        render(summary, args.n, args.png)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"double pendulum, {runs} runs of 10 s, {cores} cores, load average {os.getloadavg()[0]:.1f}")
    print(f"bare C integration: {t_bare:.2f} s of clock() in the driver ({1e3 * t_bare / runs:.3f} ms/run)")
    print(f"{'':28} {'wall s':>8} {'/ bare':>7} {'CPU s':>8} {'/ bare':>7}")
    for label, (wall, cpu) in (("1. bare C integration", wall_bare), ("2. driver batch alone", t_batch),
                               ("3. System.sweep", t_api), ("4. lagcli sweep (command)", t_cli)):
        print(f"{label:28} {wall:8.2f} {wall / wall_bare[0]:7.2f} {cpu:8.2f} {cpu / wall_bare[1]:7.2f}")
    print(f"flip-time picture: {args.png}")


def render(summary: Path, n: int, png: str) -> None:
    """log10(time to the first flip of either rod) over (theta1, theta2) at t = 0."""
    import numpy as np
    from matplotlib.figure import Figure

    with summary.open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    flip = np.fmin(np.array([float(r["exceed_theta1"]) for r in rows]),
                   np.array([float(r["exceed_theta2"]) for r in rows]))
    image = np.log10(flip).reshape(n, n)           # row = theta1 (the first --grid), column = theta2
    fig = Figure(figsize=(6.4, 5.4), constrained_layout=True)
    ax = fig.subplots()
    shown = ax.imshow(image.T, origin="lower", extent=(-3, 3, -3, 3), cmap="viridis", interpolation="nearest")
    ax.set_xlabel("initial theta1 (rad)")
    ax.set_ylabel("initial theta2 (rad)")
    ax.set_title("double pendulum: time until a rod flips (white: not within 10 s)")
    fig.colorbar(shown, ax=ax, label="log10(flip time / s)")
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
