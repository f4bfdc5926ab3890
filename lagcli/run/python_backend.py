"""The Python backend: scipy's integrators on the generated Python module.

The module is the one `lagcli generate --lang python` writes, made by the System (the
Python target; never from spec text) and handed here as source text. Its source is
kept in the cache of `lagcli.run.cache` (`<key>/module.py`, variant `python-module`;
`cached_source`, `store`): a second run of the same spec skips the code generation
(tidying and CSE, ~2 s for rolling_disc), not the derivation. A cached module is
executed from the bytes whose SHA-256 the cache has just checked, never imported by
its path.

Integration is scipy.integrate.solve_ivp with `t_eval`, written out as its own
loop (the same solver classes, steps and dense output, so the same numbers) in
order to hand each row to its sink as soon as it is computed (output times are
made a window at a time: memory does not grow with the number of rows), to keep
the rows computed so far when the solver fails, a state becomes non-finite, the
right-hand side raises (singular mass matrix) or the run is interrupted, and to
report progress.  The right-hand side is the Baumgarte-stabilised
one (docs/design.md); each output row holds t, the state, the multipliers of that
stabilised system and the invariants. On a constrained system RK45 and DOP853 run
with the step cap of `lagcli.interface.max_step` (docs/simulate.md).
"""
from __future__ import annotations

import types
from dataclasses import dataclass

import numpy as np
from scipy import integrate

from lagcli.interface import STEP_BUDGET_TEXT, VARIATIONAL
from lagcli.runtime.run_rules import max_step, output_time_windows
from lagcli.run import cache
from lagcli.interface import Layout, RunSettings
from lagcli.run.rows import RowSink, Trajectory

MODULE, MODULE_VARIANT = "module.py", "python-module"
SOLVERS = {"RK45": integrate.RK45, "DOP853": integrate.DOP853, "Radau": integrate.Radau,
           "BDF": integrate.BDF, "LSODA": integrate.LSODA}


class _RhsFailure(Exception):
    def __init__(self, t: float, reason: str):
        super().__init__(reason)
        self.t, self.reason = t, reason


@dataclass(frozen=True)
class PythonModule:
    """The generated Python module of a system with its interface: a program of the run layer."""

    module: types.ModuleType
    layout: Layout

    def run(self, settings: RunSettings, values: dict[str, float], state, sink=None, progress=None,
            max_first_residual: float | None = None) -> RowSink:
        """One run (the program protocol of lagcli.run.simulate); the state is used as given."""
        p, u = self.vectors(values)
        return integrate_module(self.module, p, list(state), settings, progress, sink, u)

    def vectors(self, values: dict[str, float]) -> tuple[list[float], list[float] | None]:
        """p and u in the layout's order (u None without inputs): `values` over the defaults."""
        layout = self.layout
        params = {**layout.parameter_defaults, **values}
        inputs = {**layout.input_defaults, **values}
        return [params[n] for n in layout.parameter_names], [inputs[n] for n in layout.input_names] or None


def cached_source(key: str) -> str | None:
    """The module source cached under `key` (checked by the cache), or None."""
    entry = cache.load(key)
    return entry.contents[MODULE].decode() if entry is not None and MODULE in entry.contents else None


def module_of(model_name: str, source: str) -> types.ModuleType:
    """The module executed from `source` (the Python target's text) into a fresh module object."""
    name = f"lagcli_generated_{model_name}"
    module = types.ModuleType(name)
    module.__file__ = f"<{name}>"
    exec(compile(source, module.__file__, "exec", dont_inherit=True), module.__dict__)   # not this file's __future__
    return module


def store(key: str, model_name: str, source: str) -> None:
    """Cache `source` as the entry `key`; a cache that cannot be written is skipped."""
    try:
        with cache.new_entry(key) as work:
            (work / MODULE).write_text(source)
            cache.publish(work, key, f"{model_name}: Python module")
    except OSError:
        pass


def integrate_module(module, p: list[float], y0: list[float], s: RunSettings,
                     progress=None, sink: RowSink | None = None, u: list[float] | None = None) -> RowSink:
    """Integrate from t = 0 to s.t_end, giving each row to `sink` as it is computed (a new
    in-memory `Trajectory` when None) and returning it; never raises for run-time
    failures (see lagcli.run.rows). `u`: the inputs, held constant (a module
    of a spec with `inputs:` only; None: their defaults)."""
    if s.method == VARIATIONAL:
        from lagcli.run.variational_run import integrate_variational

        return integrate_variational(module, p, y0, s, progress, sink, u)
    n = len(module.COORDINATES)
    inputs = (u,) if u is not None else ()

    def accelerations(t, y):
        try:
            qdd, lam = module.accelerations(t, y, p, s.alpha, s.beta, *inputs)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            raise _RhsFailure(t, _reason(exc)) from None
        return np.asarray(qdd, dtype=float), np.asarray(lam, dtype=float)

    def fun(t, y):
        return np.concatenate([y[n:], accelerations(t, y)[0]])

    def row(t, y):
        return module.output_row(t, y, accelerations(t, y)[1], p)

    sink = Trajectory() if sink is None else sink
    sink.begin(module.HEADER)      # the run interface's columns, written into the module
    y = np.array(y0, dtype=float)
    with np.errstate(all="ignore"):   # overflow shows up as a failure, not as warnings
        _run(fun, row, y, s, max_step(s.method, s.alpha, s.beta, bool(module.MULTIPLIERS)),
             sink, progress)
    return sink


def _run(fun, row, y, s, cap, sink: RowSink, progress) -> None:
    try:
        _check_finite(0.0, y)
        sink.add_row(row(0.0, y))
        _steps(SOLVERS[s.method](fun, 0.0, y, s.t_end, rtol=s.rtol, atol=s.atol, max_step=cap),
               output_time_windows(s.t_end, s.dt), sink, row, progress, s.step_budget)
    except _RhsFailure as exc:
        sink.failure = f"at t = {exc.t:.10g}: {exc.reason}"
    except KeyboardInterrupt:
        sink.interrupted = True


def _steps(solver, windows, sink: RowSink, row, progress, budget: int) -> None:
    """solve_ivp's loop for increasing t_eval (the output times after t = 0, a window at
    a time): step, then dense output at the times passed; at most `budget` steps."""
    times, k = np.array(next(windows)), 1             # times[0] = 0: its row is written
    steps = 0
    while True:
        while k == len(times):
            times, k = np.array(next(windows, [])), 0
            if not len(times):
                return
        if steps == budget:
            raise _RhsFailure(solver.t, STEP_BUDGET_TEXT.format(steps=budget))
        steps += 1
        message = solver.step()
        if solver.status == "failed":
            raise _RhsFailure(solver.t, f"the {type(solver).__name__} integrator failed: {message}")
        _check_finite(solver.t, solver.y)
        dense = None
        while k < len(times):
            end = len(times) if solver.status == "finished" else int(np.searchsorted(times, solver.t, "right"))
            if end == k:
                break
            if dense is None:
                dense = solver.dense_output()
            for tk in times[k:end]:
                y = dense(tk)
                _check_finite(tk, y)
                sink.add_row(row(tk, y))
            k = end
            if k == len(times):
                times, k = np.array(next(windows, [])), 0
        if progress is not None:
            progress(solver.t)


def _check_finite(t: float, y) -> None:
    if not np.all(np.isfinite(y)):
        raise _RhsFailure(t, "the state is no longer finite (inf/nan): the solution blows up")


def _reason(exc: Exception) -> str:
    if isinstance(exc, np.linalg.LinAlgError) or "singular" in str(exc).lower():
        return f"singular mass matrix or constraint matrix ({exc})"
    return f"{type(exc).__name__}: {exc}"
