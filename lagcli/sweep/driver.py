"""The batch interface of the compiled driver: many runs through one process.

`./sim --batch [--batch-rows] [--exceed NAME=VALUE]... [options]` reads one run per
line on stdin, `ID NAME=VALUE ...`, and answers (lagcli/runtime/c/lagcli_driver.c,
"batch mode"):

    #summary t_last,rows,steps,...           the metric names, once
    <CSV rows of the run>                     with --batch-rows only
    @ID<TAB>ok|failed<TAB>reason<TAB>values   one line per run

`run_batch` feeds a chunk of runs to one driver process and parses its answer into
`RunResult`s. A driver that dies (a signal, a crash) raises `DriverDied`: the chunk
is then run again (Dask retries it; locally the sweep stops, keeping what it
finished), never recorded as failed runs. This module imports neither numpy nor sympy:
Dask workers import it to run chunks.
"""
from __future__ import annotations

import subprocess
from dataclasses import dataclass, field

SUMMARY_MARK = "#summary "
RESULT_MARK = "@"
COUNTS = ("rows", "steps", "rejected", "nfev")      # integer metrics of the summary


class DriverDied(RuntimeError):
    """The driver process ended without answering every run of its chunk."""


@dataclass(frozen=True)
class RunResult:
    run: int
    failure: str                  # "" when the run reached t_end
    values: tuple[str, ...]       # the metrics, as the driver printed them (%.17g)
    rows: tuple[str, ...] = field(default=(), repr=False)   # CSV rows (with --batch-rows)


def batch_options(rows: bool, exceed: dict[str, float]) -> list[str]:
    options = ["--batch-rows" if rows else "--batch"]
    for name, value in exceed.items():
        options += ["--exceed", f"{name}={number(value)}"]
    return options


def run_line(run_id: int, values: dict[str, float]) -> str:
    return " ".join([str(run_id), *(f"{name}={number(v)}" for name, v in values.items())]) + "\n"


def number(value: float) -> str:
    return format(float(value), ".17g")


def run_batch(program: str, arguments: list[str], lines: list[str]) -> tuple[list[str], list[RunResult]]:
    """Run the lines of one chunk through one driver process: (metric names, results)."""
    done = subprocess.run([program, *arguments], input="".join(lines), capture_output=True, text=True)
    names, results = parse_answer(done.stdout)
    if done.returncode != 0 or len(results) != len(lines):
        reason = (f"killed by signal {-done.returncode}" if done.returncode < 0
                  else f"exit status {done.returncode}")
        message = done.stderr.strip().splitlines()[-1] if done.stderr.strip() else ""
        raise DriverDied(f"the compiled driver stopped after {len(results)} of {len(lines)} runs "
                         f"({reason}){': ' + message if message else ''}")
    return names, results


def parse_answer(text: str) -> tuple[list[str], list[RunResult]]:
    names: list[str] = []
    results, rows = [], []
    for line in text.splitlines():
        if line.startswith(SUMMARY_MARK):
            names = line[len(SUMMARY_MARK):].split(",")
        elif line.startswith(RESULT_MARK):
            run, status, reason, values = line[1:].split("\t")
            results.append(RunResult(int(run), reason if status == "failed" else "",
                                     tuple(_plain(v) for v in values.split(",")), tuple(rows)))
            rows = []
        elif line:
            rows.append(line)
    return names, results


def _plain(value: str) -> str:
    """One spelling of not-a-number whatever its sign bit ("-nan" on glibc)."""
    return "nan" if value.endswith("nan") else value
