"""Benchmark `simulate --method variational` against DOP853 (both in the compiled driver).

Run from the project root:

    PYTHONPATH=. .venv/bin/python bench/variational.py --energy   # bench/variational_energy.png
    PYTHONPATH=. .venv/bin/python bench/variational.py --cost     # CPU per step, bench/README.md

--energy: Kepler's orbit of eccentricity 0.6 (tests/data/kepler.yaml) and the spherical
pendulum, 10^6 steps of dt = 0.05, the variational integrator against DOP853 at the
rtol = atol (10^(-k/2)) whose right-hand-side evaluations are closest to the
variational run's model evaluations (3 per step + 2 per Newton iteration, as
tests/test_variational.py counts them): |E(t) - E(0)| of both, on log axes.

--cost: the double pendulum and the planar 10-link chain (bench/nlink.py), 10 s, CPU time
of the integration only (the driver's `--bench-integration N`: clock(), no rows, no
start-up): the variational integrator at dt = 0.01 and 0.001 (one row per step), DOP853 at
rtol = atol = 1e-9 and 1e-12; per step, per evaluation and per run, and the largest energy
error of each run (from the rows of one printed run).
"""
from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import lagcli  # noqa: E402
from lagcli.run import c_backend  # noqa: E402


def driver(system) -> str:
    return c_backend.driver(system, shutil.which("cc")).binary


def bench(binary: str, runs: int, *args) -> dict[str, float]:
    done = subprocess.run([binary, *args, "--max-steps", "1000000000", "--bench-integration", str(runs)],
                          capture_output=True, text=True,
                          check=True)
    return {k: float(v) for k, v in re.findall(r"(\w+) ([0-9.e+-]+)", done.stderr)}


def energy_error(system, **options) -> tuple[np.ndarray, np.ndarray]:
    traj = system.simulate(backend="c", **options)
    E = traj["jacobi"]
    return traj.t, np.abs(E - E[0])


def matching_tolerance(binary: str, t_end: float, evaluations: float) -> float:
    def nfev(r):
        return bench(binary, 1, "--method", "DOP853", "--rtol", repr(r), "--atol", repr(r), "--t-end", repr(t_end),
                     "--dt", repr(t_end))["nfev"]
    return min((10 ** (-k / 2) for k in range(6, 29)), key=lambda r: abs(np.log(nfev(r) / evaluations)))


def energy_picture(path: Path, steps: int, dt: float, per_row: int) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases = [("Kepler, e = 0.6", ROOT / "tests" / "data" / "kepler.yaml"),
             ("spherical pendulum", ROOT / "specs" / "spherical_pendulum.yaml")]
    fig, axes = plt.subplots(1, len(cases), figsize=(11, 4.2))
    t_end = steps * dt
    for ax, (title, spec) in zip(axes, cases):
        system = lagcli.load(spec)
        binary = driver(system)
        b = bench(binary, 1, "--method", "variational", "--t-end", repr(t_end), "--dt", repr(dt))
        evaluations = 2 * b["iterations"] + 3 * b["steps"]
        rtol = matching_tolerance(binary, t_end, evaluations)
        t, var = energy_error(system, t_end=t_end, dt=dt * per_row, method="variational", steps_per_row=per_row)
        _, dop = energy_error(system, t_end=t_end, dt=dt * per_row, method="DOP853", rtol=rtol, atol=rtol)
        ax.loglog(t[1:], var[1:], lw=0.6, label=f"variational, dt = {dt:g} ({evaluations:.3g} evaluations)")
        ax.loglog(t[1:], dop[1:], lw=0.6, label=f"DOP853, rtol = atol = {rtol:.2g} (as many)")
        ax.set_title(f"{title}: {steps:.0e} steps")
        ax.set_xlabel("t")
        ax.set_ylabel("|E(t) - E(0)|")
        ax.legend(loc="lower right", fontsize=8)
        print(f"{title}: variational max {var.max():.3g} (first tenth {var[:len(var) // 10].max():.3g}), "
              f"DOP853 rtol {rtol:.2g} max {dop.max():.3g} (first tenth {dop[:len(dop) // 10].max():.3g})")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def cost_table(runs: int) -> None:
    from nlink import nlink_spec_text

    cases = [("double pendulum", lagcli.load(ROOT / "specs" / "double_pendulum.yaml")),
             ("10-link chain", lagcli.load(nlink_spec_text(10)))]
    print(f"{'system':16} {'method':26} {'steps':>8} {'evals':>8} {'us/step':>9} {'us/eval':>8} "
          f"{'ms/run':>8} {'max |dE|':>9}")
    for name, system in cases:
        binary = driver(system)
        for label, args, options in [
                ("variational dt=0.01", ["--method", "variational", "--dt", "0.01"], dict(method="variational", dt=0.01)),
                ("variational dt=0.001", ["--method", "variational", "--dt", "0.001"],
                 dict(method="variational", dt=0.001)),
                ("DOP853 rtol=1e-9", ["--method", "DOP853", "--rtol", "1e-9", "--atol", "1e-9"],
                 dict(method="DOP853", rtol=1e-9, atol=1e-9)),
                ("DOP853 rtol=1e-12", ["--method", "DOP853", "--rtol", "1e-12", "--atol", "1e-12"],
                 dict(method="DOP853", rtol=1e-12, atol=1e-12))]:
            b = bench(binary, runs, "--t-end", "10", *args)
            steps = b["steps"]
            evals = 2 * b["iterations"] + 3 * steps if "iterations" in b else b["nfev"]
            _, error = energy_error(system, t_end=10.0, **options)
            print(f"{name:16} {label:26} {steps:8.0f} {evals:8.0f} {1e6 * b['min_s'] / steps:9.3f} "
                  f"{1e6 * b['min_s'] / evals:8.4f} {1e3 * b['min_s']:8.3f} {error.max():9.2e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--energy", action="store_true", help="draw bench/variational_energy.png")
    parser.add_argument("--cost", action="store_true", help="print the cost per step")
    parser.add_argument("--steps", type=int, default=1_000_000)
    parser.add_argument("--runs", type=int, default=20, help="--bench-integration runs (the minimum is shown)")
    parser.add_argument("--png", default=str(ROOT / "bench" / "variational_energy.png"))
    options = parser.parse_args()
    if options.energy:
        energy_picture(Path(options.png), options.steps, 0.05, max(1, options.steps // 10_000))
    if options.cost:
        cost_table(options.runs)


if __name__ == "__main__":
    main()
