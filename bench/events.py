"""Benchmark the event machinery: a run with 1 000 impacts against the same run without events.

Run from the project root:

    PYTHONPATH=. .venv/bin/python bench/events.py [--repeat 3] [--clock cpu|wall] [--backend python|c|both]

The elastic bouncing ball (specs/hybrid/bouncing_ball.yaml with e = 1) over exactly
1 000 bounces (t_end = 2000 t1, t1 = sqrt(2/g)), DOP853, rtol 1e-9, atol 1e-12, on the
Python backend (`System.simulate`, in process, the generated module cached), and the same
spec with its `events:` removed over the same span and output grid (the ball then falls
freely). Two output grids: dt = 0.01 (90 000 rows: the rows dominate both runs) and
dt = 100 (10 rows: the integration and the events alone). Prints the medians of `repeat`
runs of the chosen clock (default: CPU time of this process) and their ratio.

The C backend (lagcli/runtime/c/lagcli_events.c): the compiled drivers of both specs
(built into the cache first), run as `lagcli simulate` runs them, the clock that of the
driver process (CPU: its user + system time, from the children's rusage); and the
integration alone, the driver's own `--bench-integration` timer (processor time, no
rows, no process start-up), the median of `repeat` integrations.
"""
from __future__ import annotations

import argparse
import math
import re
import resource
import statistics
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPEC = ROOT / "specs" / "hybrid" / "bouncing_ball.yaml"
T_END = 2000 * math.sqrt(2 / 9.81)          # 1 000 impacts of the elastic ball dropped from 1 m


def timed(action, repeat: int, clock) -> float:
    times = []
    for _ in range(repeat):
        start = clock()
        action()
        times.append(clock() - start)
    return statistics.median(times)


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def driver_run(binary: str, dt: float, repeat: int, wall: bool) -> float:
    """The median time of the compiled driver printing its rows (to /dev/null)."""
    args = [binary, "--t-end", repr(T_END), "--dt", repr(dt), "--set", "e=1"]
    clock = time.perf_counter if wall else children_cpu

    def once():
        subprocess.run(args, stdout=subprocess.DEVNULL, check=True)
    return timed(once, repeat, clock)


def driver_integration(binary: str, dt: float, repeat: int) -> float:
    """The median processor time of one integration, by the driver's --bench-integration."""
    done = subprocess.run([binary, "--t-end", repr(T_END), "--dt", repr(dt), "--set", "e=1",
                           "--bench-integration", str(repeat)], capture_output=True, text=True, check=True)
    return float(re.search(r"mean_s ([0-9.e+-]+)", done.stderr).group(1))


def python_backend(with_events, without, dt: float, repeat: int, clock) -> tuple[float, float]:
    return (timed(lambda: with_events.simulate(t_end=T_END, dt=dt, parameters={"e": 1.0}), repeat, clock),
            timed(lambda: without.simulate(t_end=T_END, dt=dt), repeat, clock))


def main() -> None:
    import lagcli

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--clock", choices=("cpu", "wall"), default="cpu")
    parser.add_argument("--backend", choices=("python", "c", "both"), default="both")
    args = parser.parse_args()
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    text = SPEC.read_text()
    with_events = lagcli.load(text)
    without = lagcli.load(text.split("events:")[0] + "initial: {y: 1.0}\n")
    backends = ("python", "c") if args.backend == "both" else (args.backend,)
    for backend in backends:
        check = with_events.simulate(t_end=T_END, dt=100.0, parameters={"e": 1.0}, backend=backend)
        assert len(check.events) == 1000 and check.end_note is None, (len(check.events), check.end_note)
    print(f"bouncing ball, e = 1, t_end = {T_END:.4f} s, 1000 impacts, DOP853, "
          f"{args.clock} time, median of {args.repeat}")
    if "c" in backends:
        binaries = [system.program("c").binary for system in (with_events, without)]
    for backend in backends:
        for dt in (0.01, 100.0):
            rows = len(without.simulate(t_end=T_END, dt=dt))
            if backend == "python":
                t_events, t_plain = python_backend(with_events, without, dt, args.repeat, clock)
            else:
                t_events, t_plain = (driver_run(b, dt, args.repeat, args.clock == "wall") for b in binaries)
            print(f"  {backend:<6} dt = {dt:<6g} ({rows:>6} rows): with events {t_events:8.3f} s, "
                  f"without {t_plain:8.3f} s, ratio {t_events / t_plain:6.2f}")
        if backend == "c":
            for dt in (0.01, 100.0):
                t_events, t_plain = (driver_integration(b, dt, args.repeat) for b in binaries)
                print(f"  c integration alone (--bench-integration), dt = {dt:<6g}: with events "
                      f"{t_events * 1e3:8.3f} ms, without {t_plain * 1e3:8.3f} ms, ratio {t_events / t_plain:6.2f}")


if __name__ == "__main__":
    main()
