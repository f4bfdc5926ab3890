"""`lagcli report -o page.html` against `lagcli derive --latex`, whole commands in fresh processes.

Run:  python bench/page.py [--spec specs/benchmark_bicycle.yaml] [--repeats 3]

Child CPU seconds (imports included) of each command, medians of --repeats runs, and the
ratio page / LaTeX (issue 21's target: within 2x). Three commands: the LaTeX report, the
page without pictures (equations and linearization), the whole page (also the spec's own
run, its plot and its animation). Nothing here is asserted in tests (machines are noisy).
"""
from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

COMMANDS = {
    "derive --latex": ["derive", "{spec}", "--latex", "-o", "{out}/out.tex"],
    "report --no-pictures": ["report", "{spec}", "--no-pictures", "-o", "{out}/page.html"],
    "report": ["report", "{spec}", "-o", "{out}/page.html"],
}


def cpu_seconds(args: list[str]) -> float:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "lagcli", *args], check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spec", default="specs/benchmark_bicycle.yaml")
    parser.add_argument("--repeats", type=int, default=3)
    options = parser.parse_args()
    medians = {}
    with tempfile.TemporaryDirectory() as out:
        for name, template in COMMANDS.items():
            args = [a.format(spec=options.spec, out=out) for a in template]
            medians[name] = statistics.median(cpu_seconds(args) for _ in range(options.repeats))
            print(f"{name:24s} {medians[name]:7.2f} s CPU", flush=True)
    base = medians["derive --latex"]
    for name in ("report --no-pictures", "report"):
        print(f"{name} / derive --latex = {medians[name] / base:.2f}")


if __name__ == "__main__":
    main()
