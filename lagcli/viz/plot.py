"""`--plot FILE.png` (or .svg, .pdf): the coordinates and the drift of what should stay constant.

Top panel: every coordinate against t.  Bottom panel (log scale), only the
columns that are *conserved* by the equations, so that any visible growth is
integration error:

- `jacobi` when the Jacobi integral exists (labelled `jacobi = energy` when it
  equals T + V); otherwise `energy` is never drawn, since it is not conserved
  (driven, rheonomic or damped systems), and showing it would look like error;
- each ignorable momentum `p_<q>`;
- these as the relative drift |x(t) - x(0)| / |x(0)|, or the absolute drift
  |x(t) - x(0)| when |x(0)| < 1e-12 (a zero momentum), said in the legend;
- `constraint_residual` as it is (already an absolute error).

Drifts are drawn from the second row on (they are 0 at t = 0 by definition);
values below 1e-17 are drawn at 1e-17 so that exact zeros stay on the log axis.
When nothing is conserved the figure has the top panel only.

The data: `lagcli simulate --plot` streams the CSV to its output and keeps a
bounded copy for the figure (`trajectory.Decimated`: every k-th row and the last,
at most 40 000 rows, k doubling as the run grows), rather than reading the CSV
back, which a FIFO or stdout could not give.  Runs of up to 20 000 rows are drawn
whole; longer ones evenly thinned, so a spike narrower than k rows may not show.

Choosing what is drawn (`PlotOptions`, `lagcli simulate --columns/--phase`):

- the coordinates are split into an "angle (rad)" and a "coordinates" (lengths) panel
  when the caller knows which coordinates are angles (the layout's `angles`, from `lagcli.model.angles`: a
  body's rotation angle, or the argument of a sin/cos/tan in a position or energy);
- `--columns a,b,...` draws exactly those columns, one panel per kind, in the order
  angles, lengths, velocities, multipliers, contact forces, invariants (their values; the
  drift panel below stays); a held contact's force (`rest: true`) is drawn by default too;
- `--phase q` adds a phase portrait, q_dot against q;
- `units` (column -> unit: the run interface's `Layout.units`, from the spec's `unit:`s) labels
  the legend and the axes: "x [m]", "t [s]" (`axis_label`).

matplotlib is optional (the `plot` extra); `build_figure` makes a pyplot-free
`Figure` (drawn by the Agg renderer), `plot_file` writes it as the PNG, SVG or PDF its file name's extension names
(like `-o`).
"""
from __future__ import annotations

import io
import os
from dataclasses import dataclass, field

from lagcli.render.escape import plot_text
from lagcli.errors import SimulationError, UsageError
from lagcli.interface import INVARIANT_KINDS, TIME, velocity_name
from lagcli.render.output import write_output
from lagcli.run.rows import Trajectory

FLOOR = 1e-17
ABSOLUTE_BELOW = 1e-12
FIGURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
_NO_DATE = {"svg": {"metadata": {"Date": None}}, "pdf": {"metadata": {"CreationDate": None}}}
PANELS = (("angle", "angle (rad)"), ("length", "coordinates"), ("velocity", "velocities"),
          ("multiplier", "multipliers"), ("contact", "contact forces"), ("invariant", "invariants"))


@dataclass(frozen=True)
class PlotOptions:
    columns: tuple[str, ...] | None = None    # None: the coordinates
    phase: tuple[str, ...] = ()               # coordinates to draw q_dot against q for
    angles: frozenset = frozenset()           # coordinates that are angles (radians)
    units: dict = field(default_factory=dict) # column -> unit, where known
    kinds: dict = field(default_factory=dict) # column -> its kind (`Layout.kinds`), in CSV order


def column_kind(name: str, kinds: dict, angles) -> str | None:
    """The panel of a CSV column, from its kind in the run interface (None for t)."""
    kind = kinds.get(name)
    if kind == "coordinate":
        return "angle" if name in angles else "length"
    if kind in ("velocity", "multiplier", "contact"):
        return kind
    return "invariant" if kind in INVARIANT_KINDS else None


def drift_series(kinds: dict, energy_conserved: bool) -> list[tuple[str, str]]:
    """(column, label) of the bottom panel, in CSV order (`kinds`: column -> kind)."""
    has_jacobi = "jacobi" in kinds.values()
    chosen = []
    for name, kind in kinds.items():
        if kind == "jacobi":
            chosen.append((name, "jacobi = energy" if energy_conserved else "jacobi"))
        elif kind == "energy" and energy_conserved and not has_jacobi:
            chosen.append((name, "energy"))
        elif kind in ("momentum", "residual"):
            chosen.append((name, name))
    return chosen


def plot_file(traj: Trajectory, coordinates, energy_conserved: bool, path: str, title: str,
              options: PlotOptions = PlotOptions()) -> None:
    """Write the figure of `build_figure` to `path` in the format its extension names
    (`figure_format`), through lagcli.render.output.write_output."""
    figure = build_figure(traj, coordinates, energy_conserved, title, options)
    write_output(path, figure_bytes(figure, figure_format(path), dpi=110))


def figure_format(path, option: str = "--plot") -> str:
    """"png", "svg" or "pdf", as the extension of `path` names it ("-": PNG on stdout);
    any other extension is refused with a hint, before any work is done."""
    if str(path) == "-":
        return "png"
    stem, suffix = os.path.splitext(str(path))
    if suffix.lower() not in FIGURE_FORMATS:
        raise UsageError(f"{option} {path}: the file's extension names the picture's format: "
                         f"{', '.join(FIGURE_FORMATS)}\n  hint: e.g. {option} {stem or 'plot'}.png or "
                         f"{option} {stem or 'plot'}.svg")
    return FIGURE_FORMATS[suffix.lower()]


def figure_bytes(figure, format: str, dpi: float | None = None) -> bytes:
    """The bytes of a matplotlib Figure in `format`, the same for the same figure: no date
    in SVG or PDF, SVG element ids from a fixed salt (not a random one). `dpi`: None for
    matplotlib's default."""
    import matplotlib

    buffer = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "lagcli"}):
        figure.savefig(buffer, format=format, dpi=dpi, **_NO_DATE.get(format, {}))
    return buffer.getvalue()


def build_figure(traj: Trajectory, coordinates, energy_conserved: bool, title: str,
                 options: PlotOptions = PlotOptions()):
    """The matplotlib Figure (not registered with pyplot, so nothing global to close):
    the panels of `options` on top, the drift panel (`drift_series`) below when there
    is one, the phase portraits last."""
    try:
        import numpy as np
        from matplotlib.figure import Figure
    except ImportError:
        raise SimulationError("--plot needs matplotlib, which is not installed; install it with "
                              "pip install 'lagcli[plot]' (the CSV was written)") from None
    header, data = traj.header, traj.data                 # floats: no CSV text on the way
    column = {name: data[:, i] for i, name in enumerate(header)}
    panels = by_scale(_panels(header, coordinates, options), column)
    series = drift_series({n: options.kinds[n] for n in header if n in options.kinds}, energy_conserved)
    phase = _phase_names(options.phase, coordinates)
    count = len(panels) + bool(series)
    fig = Figure(figsize=(8, 1.5 + 2.5 * (count + len(phase))), constrained_layout=True)
    grid = fig.add_gridspec(count + len(phase), 1)
    first = fig.add_subplot(grid[0, 0])
    axes = [first] + [fig.add_subplot(grid[k, 0], sharex=first) for k in range(1, count)]
    for ax, (label, names) in zip(axes, panels):
        for name in names:
            ax.plot(column[TIME], column[name], label=_with_unit(name, options.units))
        ax.set_ylabel(axis_label(label, names, options.units))
        ax.legend(loc="best", fontsize="small")
        ax.grid(True, alpha=0.3)
    first.set_title(plot_text(title), usetex=False)   # the spec's file name: never TeX
    if series:
        _drift_panel(axes[len(panels)], column, series, np)
    axes[-1].set_xlabel(_with_unit(TIME, options.units))
    for k, (q, qd) in enumerate(phase):
        ax = fig.add_subplot(grid[count + k, 0])
        ax.plot(column[q], column[qd], lw=1)
        ax.set_xlabel(_with_unit(q, options.units))
        ax.set_ylabel(_with_unit(qd, options.units))
        ax.set_title(f"phase portrait of {q}", fontsize="small")
        ax.grid(True, alpha=0.3)
    return fig


def _panels(header, coordinates, options: PlotOptions) -> list[tuple[str, list[str]]]:
    """(y label, column names) per panel: the coordinates by default (one panel unless
    angles are known), else the chosen columns grouped by kind."""
    contacts = [n for n in header if options.kinds.get(n) == "contact"]     # drawn by default too
    chosen = list(coordinates) + contacts if options.columns is None else list(options.columns)
    unknown = [n for n in chosen if n not in header or n == TIME]
    if unknown:
        raise UsageError(f"--columns: no column {unknown[0]!r}; columns are: {', '.join(header[1:])}")
    if options.columns is None and not options.angles and not contacts:
        return [("coordinates", chosen)] if chosen else []
    kinds = {name: column_kind(name, options.kinds, options.angles) for name in chosen}
    return [(label, [n for n in chosen if kinds[n] == kind]) for kind, label in PANELS
            if any(kinds[n] == kind for n in chosen)]


SCALE_SPLIT = 20.0     # columns whose ranges differ by more than this share no panel


def by_scale(panels, column) -> list[tuple[str, list[str]]]:
    """Each panel split by scale: columns sorted by their range (max - min) start a new
    panel (same label) when their range exceeds SCALE_SPLIT times the range of the
    panel's smallest, so that a fast-spinning wheel's angle (hundreds of rad) does not
    flatten the tilt (tenths) to a line. Spec order is kept within a panel."""
    out = []
    for label, names in panels:
        spans = {n: float(column[n].max() - column[n].min()) if len(column[n]) else 0.0 for n in names}
        groups: list[list[str]] = []
        for name in sorted(names, key=lambda n: spans[n]):
            if groups and spans[name] <= SCALE_SPLIT * max(spans[groups[-1][0]], 1e-300):
                groups[-1].append(name)
            else:
                groups.append([name])
        out += [(label, [n for n in names if n in group]) for group in groups]
    return out


def _phase_names(phase, coordinates) -> list[tuple[str, str]]:
    for q in phase:
        if q not in coordinates:
            raise UsageError(f"--phase {q}: not a coordinate; coordinates are: {', '.join(coordinates)}")
    return [(q, velocity_name(q)) for q in phase]


def axis_label(label: str, names, units: dict) -> str:
    """The y label of a panel: its one column with its unit (`x [m]`), else the panel's
    name with the unit its columns share (`coordinates [m]`), else the name alone."""
    if len(names) == 1 and units.get(names[0]):
        return _with_unit(names[0], units)
    shared = {units.get(name) for name in names}
    return f"{label} [{shared.pop()}]" if len(shared) == 1 and None not in shared else label


def _with_unit(name: str, units: dict) -> str:
    return f"{name} [{units[name]}]" if units.get(name) else name


def _drift_panel(ax, column, series, np) -> None:
    t = column["t"]
    for name, label in series:
        values = column[name]
        if name == "constraint_residual":
            shown, text = np.abs(values), f"{label} (absolute)"
        elif abs(values[0]) < ABSOLUTE_BELOW:
            shown, text = np.abs(values - values[0]), f"{label}: |x - x(0)|"
        else:
            shown, text = np.abs(values - values[0]) / abs(values[0]), f"{label}: relative drift"
        skip = 0 if name == "constraint_residual" else 1      # a drift is 0 at t = 0 by definition
        ax.semilogy(t[skip:], np.maximum(shown[skip:], FLOOR), label=text)
    ax.set_ylabel("drift / residual")
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, which="both", alpha=0.3)
