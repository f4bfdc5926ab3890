"""`simulate --method variational` on lagcli's side: the Python backend's run loop, and
the end-of-run line on the drift of the integrals (both backends).

The integrator itself is lagcli/runtime/variational.py (carried by the generated Python
module, which this runs) and lagcli/runtime/c/lagcli_variational.c; the scheme is
lagcli/derive/discrete.py, its documentation docs/simulate.md ("The variational integrator").
"""
from __future__ import annotations

import math

import numpy as np

from lagcli.interface import STEP_BUDGET_TEXT
from lagcli.run.rows import RowSink, Trajectory
from lagcli.runtime.run_rules import END_TOLERANCE, output_time_windows

DRIFT_ABSOLUTE = 1e-12      # |x(0)| below this: absolute drift (as the plot and the sweep summary)
INTEGRAL_KINDS = ("jacobi", "momentum")


def integrate_variational(module, p: list[float], y0: list[float], s, progress=None,
                          sink: RowSink | None = None, u: list[float] | None = None) -> RowSink:
    """Rows of the generated `module`'s variational integrator, given to `sink` as they come
    (as `lagcli.run.python_backend.integrate_module`); the multipliers of each row are
    those of the exact equations (alpha = beta = 0) at its state. The steps count against
    the step budget (`s.step_budget`), as in the C driver."""
    inputs = (u,) if u is not None else ()
    sink = Trajectory() if sink is None else sink
    sink.begin(module.HEADER)
    model = module.variational_model(p, *inputs)
    rows = module.variational_rows(model, y0, output_time_windows(s.t_end, s.dt), s.steps_per_row)
    t, done, last = 0.0, 0, s.t_end - END_TOLERANCE * max(1.0, s.t_end)
    try:
        with np.errstate(all="ignore"):
            for t, y in rows:
                sink.add_row(module.output_row(t, y, module.accelerations(t, y, p, 0.0, 0.0, *inputs)[1], p))
                if progress is not None:
                    progress(t)
                done += 1
                if t < last and done * s.steps_per_row > s.step_budget:
                    sink.failure = f"at t = {t:.10g}: " + STEP_BUDGET_TEXT.format(steps=s.step_budget)
                    break
    except module.VariationalFailure as exc:
        sink.failure = str(exc)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
        sink.failure = f"at t = {t:.10g}: {type(exc).__name__}: {exc}"
    except KeyboardInterrupt:
        sink.interrupted = True
    return sink


class IntegralDrift(RowSink):
    """Watches the rows of a run for the drift of the integrals the system has (the Jacobi
    integral, each conserved momentum p_s: max |x - x(0)| / |x(0)|, absolute when |x(0)| <
    DRIFT_ABSOLUTE) and the largest constraint residual."""

    def __init__(self, layout):
        super().__init__()
        self.layout = layout
        self.watched = [(i, c) for i, c in enumerate(layout.columns) if c.kind in INTEGRAL_KINDS]
        self.residual = next((i for i, c in enumerate(layout.columns) if c.kind == "residual"), None)
        self.first: list[float] | None = None
        self.drift = [0.0] * len(self.watched)
        self.largest_residual = 0.0

    def _row(self, values) -> None:
        self._observe(values)

    def _write(self, block: str) -> None:
        for line in block[:-1].split("\n"):
            self._observe(line.split(","))

    def _observe(self, values) -> None:
        """One row: floats, or the strings of a CSV line."""
        x = [float(values[i]) for i, _ in self.watched]
        if self.first is None:
            self.first = x
        for k, (value, start) in enumerate(zip(x, self.first)):
            change = abs(value - start) / (abs(start) if abs(start) >= DRIFT_ABSOLUTE else 1.0)
            if not change <= self.drift[k]:
                self.drift[k] = change
        if self.residual is not None:
            self.largest_residual = max(self.largest_residual, float(values[self.residual]))

    def summary(self, dt: float, steps_per_row: int) -> str:
        """The end-of-run line (stderr)."""
        step = f"{steps_per_row} steps of {dt / steps_per_row:.6g} per row" if steps_per_row > 1 \
            else f"step {dt:.6g}"
        parts = [f"{c.name} {_drift(d, s)}" for (_, c), d, s in zip(self.watched, self.drift, self.first or [])]
        text = f"variational: {self.rows} rows, {step}; drift of the integrals (max |x - x(0)|/|x(0)|): "
        text += ", ".join(parts) if parts else "none (this system has no Jacobi integral and no ignorable coordinate)"
        if not any(c.kind == "jacobi" for _, c in self.watched):
            text += "; energy is not an invariant (no Jacobi integral: see `lagcli derive`)"
        if self.residual is not None:
            text += f"; largest constraint_residual {self.largest_residual:.3g}"
        return text


def _drift(value: float, start: float) -> str:
    absolute = "" if abs(start) >= DRIFT_ABSOLUTE else " (absolute)"
    return f"{value:.3g}{absolute}" if math.isfinite(value) else "nan"
