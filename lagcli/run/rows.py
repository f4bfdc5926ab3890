"""Where a simulation's rows go as they are computed, and the output-time rule.

A backend calls `sink.begin(header)` once, then for each row or block of rows either
`sink.add_row(values)` (the Python backends: floats, t, the state, the multipliers, the
invariants) or `sink.add_csv(block)` (the C backend: complete CSV lines of its driver,
`%.17g`), and sets `sink.failure` ("at t = ...: reason") or `sink.interrupted` when the
run ends early: the rows so far are already in the sink. Nothing in a backend grows
with the number of rows. A row or block of rows is written and counted whole
(`lagcli.runtime.interrupts.uninterruptible`), so the count reported after an
interruption is the number of rows in the output.

    RowSink     the base: counts the rows and keeps the last time
    CsvSink     writes the CSV to a text stream (the CLI: a file, a FIFO, stdout); the
                driver's lines pass through untouched, floats are printed `%.17g`
    Trajectory  keeps every row in memory as floats (`data`, an array): the API, tests.
                Floats from a Python backend are kept as they are (no text on the way);
                the driver's lines are read once by numpy's parser (`parse_block`),
                which gives back each double exactly (`%.17g` identifies a double)
    Decimated   keeps a bounded, evenly thinned copy (at most 2 x `limit` rows, plus
                the last one): the data of `--plot` for a run of any length; of the
                driver's lines only the kept ones are read
    Tee         passes everything to several sinks

The output-time rule is `lagcli.interface.output_times` (re-exported here).

This module is imported on the warm C path, so it imports neither numpy nor sympy at
the top (an in-memory sink imports numpy when it first needs it).
"""
from __future__ import annotations

from lagcli.runtime.interrupts import uninterruptible


class RowSink:
    """The rows of a run, as they come; subclasses keep or write them (`_begin`, `_row`
    for a row of floats, `_write` for CSV lines)."""

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
        """One row of floats, in the header's order."""
        with uninterruptible:                  # written and counted whole, or not at all
            self._row(values)
            self.rows += 1
            self.last_time = float(values[0])

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

    def _row(self, values) -> None:
        self._write(format_row(values) + "\n")

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
    """Every row in memory as floats: `data` is the (rows, columns) array. `lines` (CSV
    text) builds such a trajectory from a CSV's rows, `data` from an array."""

    def __init__(self, header=(), lines=(), data=None):
        super().__init__()
        self.header = list(header)
        self._chunks: list = []                  # 2-D float arrays, in row order
        self._pending: list = []                 # rows given one at a time, not yet in a chunk
        if data is not None and len(data):
            import numpy as np

            self._chunks.append(np.asarray(data, dtype=float))
            self.rows, self.last_time = len(data), float(data[-1][0])
        self.add_csv("".join(line + "\n" for line in lines))

    def _row(self, values) -> None:
        self._pending.append(values)

    def _write(self, block: str) -> None:
        self._flush()
        self._chunks.append(parse_block(block, len(self.header)))

    def _flush(self) -> None:
        if self._pending:
            import numpy as np

            self._chunks.append(np.array(self._pending, dtype=float).reshape(len(self._pending), -1))
            self._pending = []

    @property
    def data(self):
        """The rows as a (rows, columns) float array."""
        import numpy as np

        self._flush()
        if not self._chunks:
            return np.empty((0, len(self.header)))
        if len(self._chunks) > 1:
            self._chunks = [np.concatenate(self._chunks)]
        return self._chunks[0]

    @property
    def lines(self) -> list[str]:
        """The rows as CSV lines (`%.17g`), without their newline."""
        return [format_row(row) for row in self.data.tolist()]

    def csv_text(self) -> str:
        return "".join(line + "\n" for line in [",".join(self.header), *self.lines])


class Decimated(Trajectory):
    """Rows 0, k, 2k, ... and the last row, where the stride k doubles whenever more
    than 2 `limit` rows are kept: memory bounded, the same rows for the same run."""

    def __init__(self, limit: int):
        super().__init__()
        self.limit, self.stride, self._last = limit, 1, None
        self._kept: list = []                    # the kept rows: lists of floats

    def _row(self, values) -> None:
        self._keep([values] if self.rows % self.stride == 0 else [], self.rows, values)

    def _write(self, block: str) -> None:
        lines = block[:-1].split("\n")
        kept = lines[-self.rows % self.stride::self.stride]          # indices that are multiples of k
        self._keep([_floats(line) for line in kept], self.rows + len(lines) - 1, lines[-1])

    def _keep(self, rows: list, last_index: int, last) -> None:
        """Keep `rows` (the new rows whose index is a multiple of the stride); `last`: the
        newest row (index `last_index`), floats or a CSV line."""
        self._kept.extend(rows)
        while len(self._kept) > 2 * self.limit:
            self._kept, self.stride = self._kept[::2], 2 * self.stride
        self._last = (last_index, last)

    def trajectory(self) -> Trajectory:
        """The kept rows, with the last row of the run appended when it was thinned out."""
        import numpy as np

        rows = list(self._kept)
        if self._last is not None and self._last[0] % self.stride:
            last = self._last[1]
            rows.append(_floats(last) if isinstance(last, str) else last)
        data = np.array(rows, dtype=float).reshape(len(rows), -1) if rows else np.empty((0, len(self.header)))
        return Trajectory(self.header, data=data)


class Tee(RowSink):
    def __init__(self, *sinks: RowSink):
        super().__init__()
        self.sinks = sinks

    def _begin(self, header: list[str]) -> None:
        for sink in self.sinks:
            sink.begin(header)

    def _row(self, values) -> None:
        for sink in self.sinks:
            sink.add_row(values)

    def _write(self, block: str) -> None:
        for sink in self.sinks:
            sink.add_csv(block)


def format_row(values) -> str:
    return ",".join(format(float(v), ".17g") for v in values)


def _floats(line: str) -> list[float]:
    return [float(v) for v in line.split(",")]


def parse_block(block: str, columns: int):
    """Complete CSV lines of numbers (the driver's `%.17g`) as a (rows, columns) float
    array, each value the double it was printed from: numpy's parser in one pass
    (`float` per value where numpy refuses a spelling, as C's `-nan`)."""
    import numpy as np

    columns = columns or block.count(",", 0, block.index("\n")) + 1      # no header: the first row says
    flat = block.replace("\n", ",")
    try:
        values = np.fromstring(flat, sep=",")
    except ValueError:
        values = np.array([float(v) for v in flat.split(",") if v], dtype=float)
    return values.reshape(-1, columns)


def parse_csv(text: str) -> tuple[list[str], list[list[float]]]:
    """Header and rows of a CSV written by a `CsvSink` or `Trajectory.csv_text` (for plots and tests)."""
    lines = [line for line in text.splitlines() if line.strip()]
    header = lines[0].split(",") if lines else []
    return header, [[float(v) for v in line.split(",")] for line in lines[1:]]
