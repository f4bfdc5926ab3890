"""A simulation's result for Python users: numpy arrays with named, typed columns.

`Trajectory.data` holds one row per output time and one column per entry of
`layout.columns` (the CSV columns, each with its kind: docs/design.md, "CSV
columns"). Columns are read by name (`traj["theta"]`) or by kind
(`traj.of_kind("momentum")`), never by guessing from a name pattern.

Built, for now, from the backends' CSV-formatted rows (`lagcli.run.rows`,
the row source `lagcli simulate` writes): `from_rows` is the one adapter.
"""
from __future__ import annotations

import io
from dataclasses import dataclass

import numpy as np

from lagcli.interface import Column, Layout


@dataclass(frozen=True, eq=False)
class Trajectory:
    layout: Layout
    data: np.ndarray                   # (rows, len(layout.columns)), float
    notes: tuple[str, ...] = ()        # what was solved for in the initial state
    failure: str | None = None         # "at t = ...: reason" when the integration stopped early
    energy_is_jacobi: bool = False     # the energy column is conserved (plots show its drift)
    events: tuple = ()                 # lagcli.hybrid.records.EventRecord per event, in time order
    end_note: str | None = None        # why a run with events ended before t_end (accumulation, ...)

    @property
    def columns(self) -> tuple[Column, ...]:
        return self.layout.columns

    @property
    def names(self) -> tuple[str, ...]:
        return self.layout.header

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.data[:, self.names.index(name)]
        except ValueError:
            raise KeyError(f"no column {name!r}; columns are: {', '.join(self.names)}") from None

    def __len__(self) -> int:
        return len(self.data)

    @property
    def t(self) -> np.ndarray:
        return self["t"]

    @property
    def states(self) -> np.ndarray:
        """(rows, nstate): y = [q..., q'...] at each output time."""
        return self._kinds("coordinate", "velocity")

    def of_kind(self, kind: str) -> dict[str, np.ndarray]:
        """{name: column} of every column of `kind` (lagcli.interface.COLUMN_KINDS)."""
        return {c.name: self.data[:, i] for i, c in enumerate(self.columns) if c.kind == kind}

    def _kinds(self, *kinds: str) -> np.ndarray:
        return self.data[:, [i for i, c in enumerate(self.columns) if c.kind in kinds]]

    def to_csv(self) -> str:
        """The CSV of `lagcli simulate` (header, then `%.17g` values)."""
        lines = [",".join(self.names)]
        lines += [",".join(format(float(v), ".17g") for v in row) for row in self.data]
        return "".join(line + "\n" for line in lines)

    def to_pandas(self):
        """A pandas DataFrame with one column per CSV column (needs pandas)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Trajectory.to_pandas needs pandas: pip install pandas") from None
        return pd.DataFrame(self.data, columns=list(self.names))

    def plot(self, path: str | None = None):
        """The figure of `lagcli simulate --plot` (needs matplotlib); written as a PNG to
        `path` when given."""
        from lagcli.viz import plot
        from lagcli.run.rows import Trajectory as Rows

        rows = Rows(list(self.names), self.to_csv().splitlines()[1:])
        conserved = any(c.kind == "jacobi" for c in self.columns) and self.energy_is_jacobi
        if path is not None:
            plot.plot_png(rows, self.layout.coordinates, conserved, path, self.layout.name)
        return plot.build_figure(rows, self.layout.coordinates, conserved, self.layout.name)

    def _repr_html_(self) -> str:
        head = "".join(f"<th>{name}</th>" for name in self.names)
        shown = self.data if len(self) <= 10 else np.concatenate([self.data[:5], self.data[-5:]])
        body = "".join("<tr>" + "".join(f"<td>{v:.6g}</td>" for v in row) + "</tr>" for row in shown)
        more = f"<p>{len(self)} rows{'; ' + self.failure if self.failure else ''}</p>"
        return f"<table><tr>{head}</tr>{body}</table>{more}"


def from_rows(layout: Layout, rows, notes=(), energy_is_jacobi: bool = False) -> Trajectory:
    """The adapter from a backend's rows (`lagcli.run.rows.Trajectory`: CSV
    lines under a header that must be the layout's)."""
    if tuple(rows.header) != layout.header:
        raise ValueError(f"backend header {rows.header} is not the layout's {layout.header}")
    text = "".join(line + "\n" for line in rows.lines)
    data = (np.loadtxt(io.StringIO(text), delimiter=",", ndmin=2) if rows.lines
            else np.empty((0, len(layout.columns))))
    return Trajectory(layout, data, tuple(notes), rows.failure, energy_is_jacobi, tuple(rows.events),
                      rows.end_note)
