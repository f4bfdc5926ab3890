"""Where a simulation's rows go as they are computed, and the output-time rule.

A backend calls `sink.begin(header)` once, then `sink.add_row(values)` (the Python
backend: t, the state, the multipliers, the invariants) or `sink.add_csv(block)`
(the C backend: complete CSV lines of its driver, passed through untouched) for
each row or block of rows, and sets `sink.failure` ("at t = ...: reason") or
`sink.interrupted` when the run ends early: the rows so far are already in the sink.
Nothing in a backend grows with the number of rows.  A block of rows is written
and counted whole (`lagcli.render.interrupts.uninterruptible`), so the count reported
after an interruption is the number of rows in the output.

    RowSink     the base: counts the rows and keeps the last time
    CsvSink     writes the CSV to a text stream (the CLI: a file, a FIFO, stdout)
    Trajectory  keeps every row in memory as a CSV line (`%.17g`): tests, the API
    Decimated   keeps a bounded, evenly thinned copy (at most 2 x `limit` rows, plus
                the last one): the data of `--plot` for a run of any length
    Tee         passes everything to several sinks

The output-time rule is `lagcli.interface.output_times` (re-exported here).

This module is imported on the warm C path, so it needs neither numpy nor sympy.
"""
from __future__ import annotations

from lagcli.render.interrupts import uninterruptible


class RowSink:
    """The rows of a run, as they come; subclasses keep or write them (`_begin`, `_write`)."""

    def __init__(self):
        self.header: list[str] = []
        self.rows = 0
        self.last_time: float | None = None
        self.failure: str | None = None          # "at t = ...: reason"
        self.interrupted = False
        self.events: list = []                   # lagcli.run.records.EventRecord, as they happen
        self.end_note: str | None = None         # why a run with events ended before t_end

    def begin(self, header) -> None:
        self.header = list(header)
        self._begin(self.header)

    def add_row(self, values) -> None:
        self.add_csv(format_row(values) + "\n")

    def add_csv(self, block: str) -> None:
        """One or more complete CSV rows, each ending with a newline."""
        if not block:
            return
        end = len(block) - 1
        last = block[block.rfind("\n", 0, end) + 1:end]
        with uninterruptible:                  # written and counted whole, or not at all
            self._write(block)
            self.rows += block.count("\n")
            self.last_time = float(last.split(",", 1)[0])

    def _begin(self, header: list[str]) -> None:
        pass

    def _write(self, block: str) -> None:
        pass


class CsvSink(RowSink):
    def __init__(self, stream):
        super().__init__()
        self.stream = stream

    def _begin(self, header: list[str]) -> None:
        self.stream.write(",".join(header) + "\n")

    def _write(self, block: str) -> None:
        self.stream.write(block)


class Trajectory(RowSink):
    """Every row in memory, as CSV lines without their newline."""

    def __init__(self, header=(), lines=()):
        super().__init__()
        self.header, self.lines = list(header), []
        self.add_csv("".join(line + "\n" for line in lines))

    def _write(self, block: str) -> None:
        self.lines.extend(block[:-1].split("\n"))

    def csv_text(self) -> str:
        return "".join(line + "\n" for line in [",".join(self.header), *self.lines])


class Decimated(Trajectory):
    """Rows 0, k, 2k, ... and the last row, where the stride k doubles whenever more
    than 2 `limit` rows are kept: memory bounded, the same rows for the same run."""

    def __init__(self, limit: int):
        super().__init__()
        self.limit, self.stride, self._last = limit, 1, None

    def _write(self, block: str) -> None:
        lines = block[:-1].split("\n")
        self.lines.extend(lines[-self.rows % self.stride::self.stride])
        while len(self.lines) > 2 * self.limit:
            self.lines, self.stride = self.lines[::2], 2 * self.stride
        self._last = (self.rows + len(lines) - 1, lines[-1])

    def trajectory(self) -> Trajectory:
        """The kept rows, with the last row of the run appended when it was thinned out."""
        lines = list(self.lines)
        if self._last is not None and self._last[0] % self.stride:
            lines.append(self._last[1])
        return Trajectory(self.header, lines)


class Tee(RowSink):
    def __init__(self, *sinks: RowSink):
        super().__init__()
        self.sinks = sinks

    def _begin(self, header: list[str]) -> None:
        for sink in self.sinks:
            sink.begin(header)

    def _write(self, block: str) -> None:
        for sink in self.sinks:
            sink.add_csv(block)


def format_row(values) -> str:
    return ",".join(format(float(v), ".17g") for v in values)


def parse_csv(text: str) -> tuple[list[str], list[list[float]]]:
    """Header and rows of a CSV written by a `CsvSink` or `Trajectory.csv_text` (for plots and tests)."""
    lines = [line for line in text.splitlines() if line.strip()]
    header = lines[0].split(",") if lines else []
    return header, [[float(v) for v in line.split(",")] for line in lines[1:]]
