"""Benchmark `lagcli simulate`: the double pendulum over 10 s, rtol = atol = 1e-9, dt = 0.01.

Run from the project root:

    PYTHONPATH=. .venv/bin/python bench/simulate.py [--repeat 5]

Prints the median wall time of each of

  1. C integration only       the cached driver binary run directly, asked for two output
                              rows only (--dt 10): process start + integration
  2. C driver, full CSV       the same binary printing all 1001 rows (%.17g, one flush
                              per row), as `simulate` runs it; the difference to (1) is
                              the cost of formatting the output
  3. lagcli simulate (warm)   the whole command in a fresh interpreter, driver already cached
  4. lagcli Python backend    integration only: generated module + scipy DOP853, in process
  5. lagcli --backend python  the whole command in a fresh interpreter (derivation included)
  6. scipy baseline           solve_ivp(DOP853, t_eval) on a sympy.lambdify(cse=True) RHS

side by side, with each one's speed-up over the scipy baseline.  Targets: (1) at
least 100x faster than (6); (3) under 0.3 s.  No assertions: this only reports.
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPEC = ROOT / "specs" / "double_pendulum.yaml"
OPTIONS = ["--t-end", "10", "--dt", "0.01", "--rtol", "1e-9", "--atol", "1e-9", "--method", "DOP853"]


def median_time(action, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def command(*extra: str) -> list[str]:
    return [sys.executable, "-m", "lagcli", "simulate", str(SPEC), *OPTIONS, *extra]


def run_quiet(argv: list[str], env: dict) -> None:
    subprocess.run(argv, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    repeat = parser.parse_args().repeat

    cache = tempfile.mkdtemp(prefix="lagcli-bench-")
    os.environ["XDG_CACHE_HOME"] = cache
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    sys.path.insert(0, str(ROOT))
    results = {}

    import numpy as np
    from scipy.integrate import solve_ivp

    from lagcli.api import derive_file
    from lagcli.simulate import c_backend
    from lagcli.simulate.options import Request, resolve_settings
    from lagcli.simulate.python_backend import integrate_module, load_module

    start = time.perf_counter()
    run_quiet(command("--backend", "c"), env)          # cold: derive, generate, compile
    cold = time.perf_counter() - start
    key = c_backend.cache_key(str(SPEC), SPEC.read_bytes(), c_backend.find_compiler())
    cached = c_backend.lookup(key)
    d = derive_file(SPEC)
    settings = resolve_settings(Request(str(SPEC), 10.0, 0.01, "DOP853", 1e-9, 1e-9),
                                {"t_end": 10.0, "dt": 0.01, "method": "DOP853", "rtol": 1e-9, "atol": 1e-9})
    y0 = [d.model.initial.get(s.name, 0.0) for s in d.model.q + d.model.qd]
    args = c_backend.driver_arguments(settings, {}, dict(zip(cached.meta["state"], y0)))
    two_rows = [*args, "--dt", "10"]                   # the last --dt wins

    results["C integration only (binary)"] = median_time(
        lambda: run_quiet([str(cached.binary), *two_rows], env), 4 * repeat)
    results["C driver, full CSV (binary)"] = median_time(
        lambda: subprocess.run([str(cached.binary), *args], env=env, check=True, capture_output=True),
        4 * repeat)
    results["lagcli simulate, warm cache"] = median_time(
        lambda: run_quiet(command("--backend", "c", "-o", os.devnull), env), repeat)

    module = load_module(d)
    p = [prm.value for prm in d.model.parameters]
    results["lagcli Python backend (integration)"] = median_time(
        lambda: integrate_module(module, p, y0, settings), repeat)
    results["lagcli simulate --backend python"] = median_time(
        lambda: run_quiet(command("--backend", "python", "-o", os.devnull), env), max(1, repeat // 2))

    rhs = scipy_baseline_rhs(d)
    times = np.arange(0, 1001) * 0.01
    results["scipy solve_ivp + lambdify(cse)"] = median_time(
        lambda: solve_ivp(rhs, (0.0, 10.0), y0, method="DOP853", t_eval=times, rtol=1e-9, atol=1e-9),
        repeat)
    report(results, cold, repeat)


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
    baseline = results["scipy solve_ivp + lambdify(cse)"]
    print(f"double pendulum, t_end = 10, dt = 0.01, DOP853, rtol = atol = 1e-9; "
          f"median of {repeat} runs")
    print(f"(cold first run with compilation: {cold:.2f} s)\n")
    print(f"{'':40s} {'wall time':>12s} {'vs scipy':>10s}")
    for name, seconds in results.items():
        print(f"{name:40s} {seconds * 1e3:9.1f} ms {baseline / seconds:9.1f}x")
    c_only = results["C integration only (binary)"]
    warm = results["lagcli simulate, warm cache"]
    print(f"\ntarget: C integration >= 100x faster than scipy: {baseline / c_only:.0f}x "
          f"({'met' if baseline / c_only >= 100 else 'NOT met'})")
    print(f"target: warm re-run < 0.3 s: {warm:.3f} s ({'met' if warm < 0.3 else 'NOT met'})")


if __name__ == "__main__":
    main()
