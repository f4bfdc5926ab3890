"""Which runs a sweep makes: a grid, random samples or a table, as one `Plan`.

    --grid NAME=START:STOP:COUNT      COUNT evenly spaced values (numpy.linspace);
                                      several --grid options make their product, the
                                      first one varying slowest
    --sample NAME=uniform(A,B)        --count N values drawn from numpy's default
    --sample NAME=normal(MU,SIGMA)    Generator seeded with --seed (the draws follow the
                                      order of the --sample options: same seed, same runs)
    --runs table.csv                  one run per row; the header names the columns

Run ids are 0, 1, 2, ... in this order. Values are numbers or constant expressions
(`pi/2`), read by `lagcli.run.options.parse_value` (never eval). Which names
may be varied (parameters, inputs, initial values) is checked by the caller against
the system's layout.
"""
from __future__ import annotations

import csv
import itertools
import re
from dataclasses import dataclass

from lagcli.errors import UsageError
from lagcli.run.options import parse_range, parse_value

DISTRIBUTIONS = {"uniform": ("A", "B"), "normal": ("MU", "SIGMA")}
_CALL = re.compile(r"\s*([a-z]+)\s*\((.*)\)\s*")


@dataclass(frozen=True)
class Plan:
    names: tuple[str, ...]                      # the varied names, in option order
    values: tuple[tuple[float, ...], ...]       # one tuple per run, in run-id order

    def __len__(self) -> int:
        return len(self.values)

    def run(self, run_id: int) -> dict[str, float]:
        return dict(zip(self.names, self.values[run_id]))


def make_plan(grids=(), samples=(), count: int | None = None, seed: int | None = None,
              runs: str | None = None) -> Plan:
    """The Plan of exactly one kind of sweep: grids, samples (with count) or a runs table."""
    kinds = [k for k, given in (("--grid", grids), ("--sample", samples), ("--runs", runs)) if given]
    if len(kinds) != 1:
        raise UsageError("give one kind of sweep: --grid (repeatable), --sample with --count, "
                         f"or --runs table.csv{'; not ' + ' and '.join(kinds) if kinds else ''}")
    if count is not None and not samples:
        raise UsageError("--count goes with --sample")
    if grids:
        return grid_plan(grids)
    if samples:
        if count is None or count < 1:
            raise UsageError("--sample needs --count N (N >= 1)")
        return sample_plan(samples, count, 0 if seed is None else seed)
    return table_plan(runs)


def grid_plan(items) -> Plan:
    import numpy as np

    axes = [_grid_axis(item) for item in items]
    _unique([name for name, _ in axes], "--grid")
    names = tuple(name for name, _ in axes)
    values = itertools.product(*[np.linspace(start, stop, n).tolist() for _, (start, stop, n) in axes])
    return Plan(names, tuple(tuple(v) for v in values))


def _grid_axis(item: str) -> tuple[str, tuple[float, float, int]]:
    name, start, stop, n = parse_range(item, "--grid")
    return name, (start, stop, n)


def sample_plan(items, count: int, seed: int) -> Plan:
    import numpy as np

    draws = [_distribution(item) for item in items]
    _unique([name for name, _, _ in draws], "--sample")
    rng = np.random.default_rng(seed)
    columns = [getattr(rng, kind)(*args, size=count).tolist() for _, kind, args in draws]
    return Plan(tuple(name for name, _, _ in draws), tuple(zip(*columns)))


def _distribution(item: str) -> tuple[str, str, tuple[float, float]]:
    name, text = _split(item, "--sample", "NAME=uniform(A,B) or NAME=normal(MU,SIGMA)")
    call = _CALL.fullmatch(text)
    kind = call.group(1) if call else None
    if kind not in DISTRIBUTIONS:
        raise UsageError(f"--sample {item!r}: expected NAME=uniform(A,B) or NAME=normal(MU,SIGMA)")
    args = [a for a in call.group(2).split(",")]
    if len(args) != 2:
        raise UsageError(f"--sample {item!r}: {kind} takes two numbers ({', '.join(DISTRIBUTIONS[kind])})")
    a, b = (parse_value(arg, f"--sample {name}") for arg in args)
    if (kind == "uniform" and not a <= b) or (kind == "normal" and not b >= 0):
        need = "A <= B" if kind == "uniform" else "SIGMA >= 0"
        raise UsageError(f"--sample {item!r}: {kind} needs {need}")
    return name, kind, (a, b)


def table_plan(path: str) -> Plan:
    """One run per row of a CSV file whose header names the varied columns."""
    try:
        with open(path, newline="", encoding="utf-8") as handle:
            rows = [row for row in csv.reader(handle) if any(cell.strip() for cell in row)]
    except OSError as exc:
        raise UsageError(f"--runs {path}: cannot read it ({exc.strerror or exc})") from None
    if len(rows) < 2:
        raise UsageError(f"--runs {path}: expected a header naming the columns and at least one run")
    names = tuple(cell.strip() for cell in rows[0])
    _unique(list(names), f"--runs {path}: column")
    values = []
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(names):
            raise UsageError(f"{path}:{line}: {len(row)} values for the {len(names)} columns of the header")
        values.append(tuple(parse_value(cell, f"{path}:{line}: {name}") for name, cell in zip(names, row)))
    return Plan(names, tuple(values))


def _split(item: str, option: str, form: str) -> tuple[str, str]:
    name, sep, text = item.partition("=")
    if not sep or not name.strip() or not text.strip():
        raise UsageError(f"{option} {item!r}: expected {form}")
    return name.strip(), text.strip()


def _unique(names: list[str], what: str) -> None:
    for name in names:
        if names.count(name) > 1:
            raise UsageError(f"{what} {name!r} is given twice")
