"""Benchmark the event machinery: a run with 1 000 impacts against the same run without events.

Run from the project root:

    PYTHONPATH=. .venv/bin/python bench/events.py [--repeat 3] [--clock cpu|wall]

The elastic bouncing ball (specs/hybrid/bouncing_ball.yaml with e = 1) over exactly
1 000 bounces (t_end = 2000 t1, t1 = sqrt(2/g)), DOP853, rtol 1e-9, atol 1e-12, on the
Python backend (`System.simulate`, in process, the generated module cached), and the same
spec with its `events:` removed over the same span and output grid (the ball then falls
freely). Two output grids: dt = 0.01 (90 000 rows: the rows dominate both runs) and
dt = 100 (10 rows: the integration and the events alone). Prints the medians of `repeat`
runs of the chosen clock (default: CPU time of this process) and their ratio.
"""
from __future__ import annotations

import argparse
import math
import statistics
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


def main() -> None:
    import lagcli

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--clock", choices=("cpu", "wall"), default="cpu")
    args = parser.parse_args()
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    text = SPEC.read_text()
    with_events = lagcli.load(text)
    without = lagcli.load(text.split("events:")[0] + "initial: {y: 1.0}\n")
    check = with_events.simulate(t_end=T_END, dt=100.0, parameters={"e": 1.0})
    assert len(check.events) == 1000 and check.end_note is None, (len(check.events), check.end_note)
    print(f"bouncing ball, e = 1, t_end = {T_END:.4f} s, {len(check.events)} impacts, DOP853, "
          f"{args.clock} time, median of {args.repeat}")
    for dt in (0.01, 100.0):
        t_events = timed(lambda: with_events.simulate(t_end=T_END, dt=dt, parameters={"e": 1.0}),
                         args.repeat, clock)
        t_plain = timed(lambda: without.simulate(t_end=T_END, dt=dt), args.repeat, clock)
        rows = len(without.simulate(t_end=T_END, dt=dt))
        print(f"  dt = {dt:<6g} ({rows:>6} rows): with events {t_events:8.3f} s, without {t_plain:8.3f} s, "
              f"ratio {t_events / t_plain:6.2f}")


if __name__ == "__main__":
    main()
