"""`--plot FILE.png`: the coordinates and the drift of what should stay constant.

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

matplotlib is optional (the `plot` extra); `build_figure` makes a pyplot-free
`Figure` (drawn by the Agg renderer), `plot_png` writes it as a PNG (like `-o`).
"""
from __future__ import annotations

import io

from lagcli.emit.escape import plot_text
from lagcli.errors import SimulationError
from lagcli.output import write_output
from lagcli.simulate.trajectory import Trajectory, parse_csv

FLOOR = 1e-17
ABSOLUTE_BELOW = 1e-12


def drift_series(header: list[str], energy_conserved: bool) -> list[tuple[str, str]]:
    """(column, label) of the bottom panel, in CSV order."""
    chosen = []
    for name in header:
        if name == "jacobi":
            chosen.append((name, "jacobi = energy" if energy_conserved else "jacobi"))
        elif name == "energy" and energy_conserved and "jacobi" not in header:
            chosen.append((name, "energy"))
        elif name.startswith("p_") or name == "constraint_residual":
            chosen.append((name, name))
    return chosen


def plot_png(traj: Trajectory, coordinates, energy_conserved: bool, path: str, title: str) -> None:
    """Write the figure of `build_figure` to `path` as a PNG (lagcli.output.write_output)."""
    figure = build_figure(traj, coordinates, energy_conserved, title)
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=110)
    write_output(path, buffer.getvalue())


def build_figure(traj: Trajectory, coordinates, energy_conserved: bool, title: str):
    """The matplotlib Figure (not registered with pyplot, so nothing global to close):
    the coordinates on top, the drift panel (`drift_series`) below when there is one."""
    try:
        import numpy as np
        from matplotlib.figure import Figure
    except ImportError:
        raise SimulationError("--plot needs matplotlib, which is not installed; install it with "
                              "pip install 'lagcli[plot]' (the CSV was written)") from None
    header, rows = parse_csv(traj.csv_text())
    data = np.array(rows, dtype=float).reshape(len(rows), len(header))
    column = {name: data[:, i] for i, name in enumerate(header)}
    series = drift_series(header, energy_conserved)
    fig = Figure(figsize=(8, 6.5 if series else 4), constrained_layout=True)
    axes = fig.subplots(2 if series else 1, 1, sharex=True, squeeze=False)
    top = axes[0, 0]
    for name in coordinates:
        top.plot(column["t"], column[name], label=name)
    top.set_ylabel("coordinates")
    top.legend(loc="best", fontsize="small")
    top.grid(True, alpha=0.3)
    top.set_title(plot_text(title), usetex=False)   # the spec's file name: never TeX
    if series:
        _drift_panel(axes[1, 0], column, series, np)
    axes[-1, 0].set_xlabel("t")
    return fig


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
