"""Benchmark `lagcli simulate`: the double pendulum over 10 s, rtol = atol = 1e-9, dt = 0.01.

Run from the project root:

    PYTHONPATH=. .venv/bin/python bench/simulate.py [--repeat 5] [--clock wall|cpu]

`--clock cpu` times (2)-(7) in CPU seconds (this process and its children: user +
system), which a machine shared with other work disturbs far less than wall time.

Prints the wall time of each of

  1. C integration only, RK45 and DOP853: the cached driver's hidden option
     `--bench-integration N` integrates N times in-process with the same steps and
     dense output at the 1001 output times, but computes and prints no rows, and
     reports its own clock() timing on stderr (no process start-up, no output);
     the mean of N = 40 * repeat runs
  2. C driver start-up        the same binary with --t-end 0 (one row): process start,
                              dynamic loading, one row; what (1) leaves out
  3. C driver, full CSV       the binary printing all 1001 rows (%.17g, one flush per
                              row), as `simulate` runs it
  4. lagcli simulate (warm)   the whole command in a fresh interpreter, driver already cached
  5. lagcli Python backend    integration only: generated module + scipy DOP853, in process
  6. lagcli --backend python  the whole command in a fresh interpreter (derivation included)
  7. scipy baselines          solve_ivp(RK45 / DOP853, t_eval) on a sympy.lambdify(cse=True)
                              RHS with numpy.linalg.solve

(2)-(7) are medians of `repeat` runs (4 * repeat for the binaries).  Each row's
speed-up is over the scipy baseline of the same method (DOP853 unless the row says
RK45).  Targets: C DOP853 integration at least 100x faster than its baseline;
(4) under 0.3 s.  No assertions: this only reports.
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPEC = ROOT / "specs" / "double_pendulum.yaml"
OPTIONS = ["--t-end", "10", "--dt", "0.01", "--rtol", "1e-9", "--atol", "1e-9", "--method", "DOP853"]


CLOCK = "wall"


def now() -> float:
    """Wall seconds, or (--clock cpu) the CPU seconds of this process and its finished children."""
    if CLOCK == "wall":
        return time.perf_counter()
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


def median_time(action, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = now()
        action()
        times.append(now() - start)
    return statistics.median(times)


def command(*extra: str) -> list[str]:
    return [sys.executable, "-m", "lagcli", "simulate", str(SPEC), *OPTIONS, *extra]


def run_quiet(argv: list[str], env: dict) -> None:
    subprocess.run(argv, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall time, or CPU time of this process and its children (steadier under load)")
    arguments = parser.parse_args()
    repeat = arguments.repeat
    global CLOCK
    CLOCK = arguments.clock

    cache = tempfile.mkdtemp(prefix="lagcli-bench-")
    os.environ["XDG_CACHE_HOME"] = cache
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    sys.path.insert(0, str(ROOT))
    results = {}

    import numpy as np
    from scipy.integrate import solve_ivp

    from lagcli.derive.pipeline import derive_file
    from lagcli.run import c_backend
    from lagcli.run.options import Request, resolve_settings
    from lagcli.run.python_backend import integrate_module
    from lagcli.system import System

    start = time.perf_counter()
    run_quiet(command("--backend", "c"), env)          # cold: derive, generate, compile
    cold = time.perf_counter() - start
    key = c_backend.cache_key(str(SPEC), SPEC.read_bytes(), c_backend.find_compiler())
    cached = c_backend.lookup(key)
    d = derive_file(SPEC)
    settings = resolve_settings(Request(str(SPEC), 10.0, 0.01, "DOP853", 1e-9, 1e-9),
                                {"t_end": 10.0, "dt": 0.01, "method": "DOP853", "rtol": 1e-9, "atol": 1e-9})
    y0 = [d.model.initial.get(s.name, 0.0) for s in d.model.q + d.model.qd]
    args = c_backend.driver_arguments(settings, {}, dict(zip(cached.layout.state_names, y0)))

    for method in ("RK45", "DOP853"):
        results[f"C integration only, {method}"] = (
            driver_integration_time(cached.binary, [*args, "--method", method], 40 * repeat), method)
    results["C driver start-up (--t-end 0)"] = (median_time(
        lambda: run_quiet([str(cached.binary), *args, "--t-end", "0"], env), 4 * repeat), "DOP853")
    results["C driver, full CSV (binary)"] = (median_time(
        lambda: subprocess.run([str(cached.binary), *args], env=env, check=True, capture_output=True),
        4 * repeat), "DOP853")
    results["lagcli simulate, warm cache"] = (median_time(
        lambda: run_quiet(command("--backend", "c", "-o", os.devnull), env), repeat), "DOP853")

    module = System(d, SPEC.read_bytes()).program("python").module
    p = [prm.value for prm in d.model.parameters]
    results["lagcli Python backend (integration)"] = (median_time(
        lambda: integrate_module(module, p, y0, settings), repeat), "DOP853")
    results["lagcli simulate --backend python"] = (median_time(
        lambda: run_quiet(command("--backend", "python", "-o", os.devnull), env), max(1, repeat // 2)),
        "DOP853")

    rhs = scipy_baseline_rhs(d)
    times = np.arange(0, 1001) * 0.01
    for method in ("RK45", "DOP853"):
        results[f"scipy solve_ivp {method} + lambdify(cse)"] = (median_time(
            lambda: solve_ivp(rhs, (0.0, 10.0), y0, method=method, t_eval=times, rtol=1e-9, atol=1e-9),
            repeat), method)
    report(results, cold, repeat)


def driver_integration_time(binary, args: list[str], runs: int) -> float:
    """Mean seconds per integration, as timed inside the driver (--bench-integration)."""
    done = subprocess.run([str(binary), *args, "--bench-integration", str(runs)], check=True,
                          capture_output=True, text=True)
    fields = dict(item.strip().split(" ", 1) for item in done.stderr.split(":", 1)[1].split(","))
    return float(fields["mean_s"])


def scipy_baseline_rhs(d):
    """The textbook route: lambdify M and F (cse=True), solve M q'' = F with numpy."""
    import numpy as np
    import sympy as sp

    model = d.model
    subs = {prm.symbol: prm.value for prm in model.parameters}
    args = [model.t, *model.q, *model.qd]
    mass = sp.lambdify(args, d.mass_matrix.xreplace(subs), "numpy", cse=True)
    force = sp.lambdify(args, d.forcing.xreplace(subs), "numpy", cse=True)
    n = len(model.q)

    def rhs(t, y):
        qdd = np.linalg.solve(np.asarray(mass(t, *y), float), np.asarray(force(t, *y), float).ravel())
        return np.concatenate([y[n:], qdd])

    return rhs


def report(results: dict, cold: float, repeat: int) -> None:
    baselines = {method: results[f"scipy solve_ivp {method} + lambdify(cse)"][0] for method in ("RK45", "DOP853")}
    print(f"double pendulum, t_end = 10, dt = 0.01, rtol = atol = 1e-9; medians of {repeat} runs "
          "(C integration: mean of the driver's own timings)")
    print(f"(cold first run with compilation: {cold:.2f} s)\n")
    print(f"{'':42s} {CLOCK + ' time':>12s} {'vs scipy':>10s}")
    for name, (seconds, method) in results.items():
        print(f"{name:42s} {seconds * 1e3:9.3f} ms {baselines[method] / seconds:9.1f}x")
    c_only = results["C integration only, DOP853"][0]
    warm = results["lagcli simulate, warm cache"][0]
    speedup = baselines["DOP853"] / c_only
    print(f"\ntarget: C integration (DOP853) >= 100x faster than scipy: {speedup:.0f}x "
          f"({'met' if speedup >= 100 else 'NOT met'})")
    print(f"target: warm re-run < 0.3 s: {warm:.3f} s ({'met' if warm < 0.3 else 'NOT met'})")


if __name__ == "__main__":
    main()
