"""The summary of a sweep: one row per run, its journal while running, its file at the end.

Columns: `run` (the run id), the varied names, `status` (ok | failed), `failure` (the
reason, empty when ok), then the driver's metrics (lagcli/sweep/driver.py): t_last,
rows, steps, rejected, nfev, final_<column>..., min_<state>..., max_<state>...,
drift_<invariant>..., exceed_<NAME>...

While the sweep runs, every finished chunk is appended to the journal
`<output>.partial` (CSV under two header lines: the sweep's fingerprint and the
columns), flushed at once. An interrupted sweep leaves it; the same command again
reads it, skips the runs it holds and runs the others (`Journal.done`). At the end the
rows are sorted by run id and written in one go (`write_summary`: CSV, or Parquet when
the output ends in .parquet and pyarrow is installed), then the journal is removed.
Values keep the driver's text (%.17g), so the CSV has the same bytes whoever ran the
runs, in whatever order, in one go or resumed.
"""
from __future__ import annotations

import contextlib
import io
import os

from lagcli.errors import UsageError
from lagcli.render.output import write_output
from lagcli.sweep.driver import COUNTS, RunResult, number

JOURNAL_SUFFIX = ".partial"
FINGERPRINT_MARK = "# lagcli sweep "


def summary_header(varied, metrics) -> list[str]:
    header = ["run", *varied, "status", "failure", *metrics]
    for name in header:
        if header.count(name) > 1:
            raise UsageError(f"the summary would have two columns called {name!r}: "
                             "rename the parameter or give the runs another way")
    return header


def summary_line(result: RunResult, varied_values) -> str:
    status = "failed" if result.failure else "ok"
    cells = [str(result.run), *(number(v) for v in varied_values), status, _csv_text(result.failure),
             *result.values]
    return ",".join(cells) + "\n"


def _csv_text(text: str) -> str:
    if any(c in text for c in ',"\n\r'):
        return '"' + text.replace('"', '""').replace("\n", " ").replace("\r", " ") + '"'
    return text


class Journal:
    """`<output>.partial`: the rows finished so far, for a resumed sweep."""

    def __init__(self, output: str, fingerprint: str, header: list[str]):
        self.path = output + JOURNAL_SUFFIX
        self.first = [FINGERPRINT_MARK + fingerprint + "\n", ",".join(header) + "\n"]
        self.done: dict[int, str] = self._read()
        self._stream = None

    def _read(self) -> dict[int, str]:
        try:
            with open(self.path, encoding="utf-8", newline="") as handle:
                text = handle.read()
        except FileNotFoundError:
            return {}
        except OSError as exc:
            raise UsageError(f"cannot read {self.path}: {exc.strerror or exc}") from None
        lines = text.splitlines(keepends=True)
        if lines[:2] != self.first:
            raise UsageError(f"{self.path} is the journal of another sweep (another spec, options "
                             "or runs)\n  hint: rerun the sweep that made it to finish it, "
                             "or delete it to start this one")
        done = {}
        for line in lines[2:]:
            if line.endswith("\n"):            # a line cut off by a crash is run again
                done[int(line.split(",", 1)[0])] = line
        return done

    def add(self, lines: list[str]) -> None:
        if self._stream is None:
            fresh = not os.path.exists(self.path)
            self._stream = open(self.path, "a", encoding="utf-8", newline="")
            if fresh:
                self._stream.writelines(self.first)
        self._stream.writelines(lines)
        self._stream.flush()
        for line in lines:
            self.done[int(line.split(",", 1)[0])] = line

    def close(self) -> None:
        if self._stream is not None:
            self._stream.close()
            self._stream = None

    def remove(self) -> None:
        self.close()
        with contextlib.suppress(FileNotFoundError):
            os.remove(self.path)


def summary_csv(header: list[str], lines: dict[int, str]) -> str:
    return ",".join(header) + "\n" + "".join(lines[k] for k in sorted(lines))


def write_summary(path: str, header: list[str], lines: dict[int, str]) -> None:
    """The summary file: Parquet for a .parquet name (pyarrow needed), else CSV."""
    text = summary_csv(header, lines)
    if not str(path).endswith(".parquet"):
        write_output(path, text)
        return
    write_output(path, parquet_bytes(text, header))


def parquet_bytes(text: str, header: list[str]) -> bytes:
    try:
        import pyarrow as pa
        import pyarrow.csv as pacsv
        import pyarrow.parquet as pq
    except ImportError:
        raise UsageError("a .parquet summary needs pyarrow: pip install 'lagcli[sweep]' "
                         "(or give a .csv name)") from None
    types = {name: pa.float64() for name in header}
    types.update({"run": pa.int64(), "status": pa.string(), "failure": pa.string(),
                  **{name: pa.int64() for name in COUNTS}})
    options = pacsv.ConvertOptions(column_types=types, null_values=[], strings_can_be_null=False,
                                   quoted_strings_can_be_null=False)
    table = pacsv.read_csv(io.BytesIO(text.encode()), convert_options=options)
    buffer = io.BytesIO()
    pq.write_table(table, buffer)
    return buffer.getvalue()


def read_summary(path: str):
    """(header, rows as lists of str) of a CSV summary (tests, the API)."""
    import csv

    with open(path, newline="", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    return rows[0], rows[1:]
