"""A simulation's result for Python users: numpy arrays with named, typed columns.

`Trajectory.data` holds one row per output time and one column per entry of
`layout.columns` (the CSV columns, each with its kind: docs/design.md, "CSV
columns"). `traj.columns` are the column names, each read by `traj[name]`;
`traj.column_info` says what each is (`lagcli.interface.Column`: its kind), and
`traj.of_kind("momentum")` reads the columns of one kind, never by guessing from a
name pattern. In a notebook a trajectory shows its first and last rows.

Built from the in-memory sink of a run (`lagcli.run.rows.Trajectory`, whose rows are
floats: those of the Python backends as computed, the compiled driver's read exactly
from its `%.17g`): `from_rows` is the one adapter, and no row goes through text on the
way.
"""
from __future__ import annotations

from dataclasses import dataclass
from html import escape

import numpy as np

from lagcli.interface import TIME, Column, Layout

HTML_ROWS = 5     # rows shown at each end by _repr_html_


@dataclass(frozen=True, eq=False)
class Trajectory:
    layout: Layout
    data: np.ndarray                   # (rows, len(layout.columns)), float
    notes: tuple[str, ...] = ()        # what was solved for in the initial state
    failure: str | None = None         # "at t = ...: reason" when the integration stopped early
    energy_is_jacobi: bool = False     # the energy column is conserved (plots show its drift)
    events: tuple = ()                 # lagcli.run.records.EventRecord per event, in time order
    end_note: str | None = None        # why a run with events ended before t_end (accumulation, ...)
    angles: frozenset = frozenset()    # the coordinates that are angles (the plot's angle panel)

    @property
    def columns(self) -> tuple[str, ...]:
        """The column names, in CSV order: `traj[name]` for each."""
        return self.layout.header

    @property
    def names(self) -> tuple[str, ...]:
        return self.columns

    @property
    def column_info(self) -> tuple[Column, ...]:
        """Each column's name and kind (`lagcli.interface.Column`), in CSV order."""
        return self.layout.columns

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no column {name!r}; columns are: {', '.join(self.columns)}") from None

    def __len__(self) -> int:
        return len(self.data)

    @property
    def shape(self) -> tuple[int, int]:
        return self.data.shape

    @property
    def t(self) -> np.ndarray:
        return self["t"]

    @property
    def states(self) -> np.ndarray:
        """(rows, nstate): y = [q..., q'...] at each output time."""
        return self._kinds("coordinate", "velocity")

    def of_kind(self, kind: str) -> dict[str, np.ndarray]:
        """{name: column} of every column of `kind` (lagcli.interface.COLUMN_KINDS)."""
        return {c.name: self.data[:, i] for i, c in enumerate(self.column_info) if c.kind == kind}

    def _kinds(self, *kinds: str) -> np.ndarray:
        return self.data[:, [i for i, c in enumerate(self.column_info) if c.kind in kinds]]

    def to_csv(self) -> str:
        """The CSV of `lagcli simulate` (header, then `%.17g` values)."""
        lines = [",".join(self.columns)]
        lines += [",".join(format(float(v), ".17g") for v in row) for row in self.data]
        return "".join(line + "\n" for line in lines)

    def to_pandas(self):
        """A pandas DataFrame indexed by t, one column per other CSV column (needs pandas)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Trajectory.to_pandas needs pandas: pip install pandas") from None
        index = pd.Index(self.t, name=TIME)
        return pd.DataFrame(self.data[:, 1:], index=index, columns=list(self.columns[1:]))

    def plot(self, path: str | None = None, columns=None, phase=()):
        """The figure of `lagcli simulate --plot` (`--columns`, `--phase`; needs matplotlib),
        written to `path` when given, as the PNG, SVG or PDF its extension names."""
        from lagcli.run.rows import Trajectory as Rows
        from lagcli.viz import plot

        rows = Rows(self.columns, data=self.data)
        conserved = any(c.kind == "jacobi" for c in self.column_info) and self.energy_is_jacobi
        options = plot.PlotOptions(None if columns is None else tuple(columns), tuple(phase), self.angles,
                                   self.layout.units, self.layout.kinds)
        if path is not None:
            plot.figure_format(path, "plot(path=)")                  # before drawing
            plot.plot_file(rows, self.layout.coordinates, conserved, path, self.layout.name, options)
        return plot.build_figure(rows, self.layout.coordinates, conserved, self.layout.name, options)

    def __repr__(self) -> str:
        rows, cols = self.shape
        unit = self.layout.column(TIME).unit           # when the spec gives units
        span = (f", t = {self.t[0]:g}\N{HORIZONTAL ELLIPSIS}{self.t[-1]:g}" + (f" {unit}" if unit else "")
                if rows else "")
        failed = f"; failed {self.failure}" if self.failure else ""
        return f"Trajectory of {self.layout.name}: {rows} rows \N{MULTIPLICATION SIGN} {cols} columns{span}{failed}"

    def _repr_html_(self) -> str:
        """The first and last rows (an ellipsis row between them) and the shape."""
        head = "".join(f"<th>{escape(name)}</th>" for name in self.columns)
        rows = [self._html_row(r) for r in (self.data if len(self) <= 2 * HTML_ROWS else self.data[:HTML_ROWS])]
        if len(self) > 2 * HTML_ROWS:
            rows.append("<tr>" + "<td>&#8230;</td>" * len(self.columns) + "</tr>")
            rows += [self._html_row(r) for r in self.data[-HTML_ROWS:]]
        caption = escape(repr(self))
        return f"<table><caption>{caption}</caption><tr>{head}</tr>{''.join(rows)}</table>"

    @staticmethod
    def _html_row(row) -> str:
        return "<tr>" + "".join(f"<td>{v:.6g}</td>" for v in row) + "</tr>"


def from_rows(layout: Layout, rows, notes=(), energy_is_jacobi: bool = False, angles=frozenset()) -> Trajectory:
    """The adapter from a run's in-memory rows (`lagcli.run.rows.Trajectory`: floats
    under a header that must be the layout's)."""
    if tuple(rows.header) != layout.header:
        raise ValueError(f"backend header {rows.header} is not the layout's {layout.header}")
    data = rows.data if rows.rows else np.empty((0, len(layout.columns)))
    return Trajectory(layout, data, tuple(notes), rows.failure, energy_is_jacobi, tuple(rows.events),
                      rows.end_note, frozenset(angles))
