"""A simulation's result as CSV text, and the output-time rule both backends share.

A `Trajectory` keeps the rows as already-formatted CSV lines (`%.17g`), so the C
backend can pass its driver's output through untouched and the Python backend
formats each row once.  A run that failed or was interrupted still yields a
`Trajectory`: the rows computed so far, plus `failure` (the reason, with the
time) or `interrupted`.

The output-time rule is `lagcli.numerics.output_times` (re-exported here).

This module is imported on the warm C path, so it needs neither numpy nor sympy.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from lagcli.numerics import output_times  # noqa: F401  (re-exported: the backends' times)


@dataclass
class Trajectory:
    header: list[str]
    lines: list[str] = field(default_factory=list)   # one CSV row each, no newline
    failure: str | None = None                       # "at t = ...: reason"
    interrupted: bool = False

    def csv_text(self) -> str:
        return "".join(line + "\n" for line in [",".join(self.header), *self.lines])

    @property
    def last_time(self) -> float | None:
        return float(self.lines[-1].split(",", 1)[0]) if self.lines else None


def format_row(values) -> str:
    return ",".join(format(float(v), ".17g") for v in values)


def parse_csv(text: str) -> tuple[list[str], list[list[float]]]:
    """Header and rows of a CSV written by `Trajectory.csv_text` (for plots and tests)."""
    lines = [line for line in text.splitlines() if line.strip()]
    header = lines[0].split(",") if lines else []
    return header, [[float(v) for v in line.split(",")] for line in lines[1:]]
