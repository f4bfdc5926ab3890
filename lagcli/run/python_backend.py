"""The Python backend: scipy's integrators on the generated Python module.

The module is the one `lagcli generate --lang python` writes (lagcli.targets.python),
generated from sympy objects (never from spec text) and loaded from its source
text. `cached_module` keeps that source in the cache of `lagcli.run.cache`
(`<key>/module.py`, variant `python-module`): a second run of the same spec skips
the code generation (tidying and CSE, ~2 s for rolling_disc), not the derivation
(the initial state is solved from it). A cached module is executed from the bytes
whose SHA-256 the cache has just checked, never imported by its path.

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

import numpy as np
from scipy import integrate

from lagcli.interface import STEP_BUDGET_TEXT, VARIATIONAL
from lagcli.runtime.run_rules import max_step, output_time_windows
from lagcli.run import cache
from lagcli.run.options import RunSettings
from lagcli.run.rows import RowSink, Trajectory

MODULE, MODULE_VARIANT = "module.py", "python-module"
SOLVERS = {"RK45": integrate.RK45, "DOP853": integrate.DOP853, "Radau": integrate.Radau,
           "BDF": integrate.BDF, "LSODA": integrate.LSODA}


class _RhsFailure(Exception):
    def __init__(self, t: float, reason: str):
        super().__init__(reason)
        self.t, self.reason = t, reason


def load_module(derivation, spec_start=None) -> types.ModuleType:
    """The generated Python module of `derivation`, executed into a fresh module object.
    `spec_start`: `initial.spec_initial_state(derivation)` when the caller has it."""
    return _execute(derivation.model.name, module_source(derivation, spec_start))


def cached_module(system) -> types.ModuleType:
    """`load_module` of a `lagcli.system.System`, with the source taken from the cache
    when this spec's module is there (and intact), and stored there when it is not."""
    name = system.name
    key = cache.cache_key(system.model.source, system.spec_bytes, MODULE_VARIANT)
    entry = cache.load(key)
    if entry is not None and MODULE in entry.contents:
        return _execute(name, entry.contents[MODULE].decode())
    source = module_source(system.derivation, system.spec_start())
    _store(key, name, source)
    return _execute(name, source)


def module_source(derivation, spec_start=None) -> str:
    """The text `lagcli generate --lang python` writes for `derivation`."""
    from lagcli.targets.python import python_module
    from lagcli.analysis.initial_state import spec_initial_state

    start, _ = spec_start or spec_initial_state(derivation)
    return python_module(derivation, start.values, start.notes)


def _execute(model_name: str, source: str) -> types.ModuleType:
    name = f"lagcli_generated_{model_name}"
    module = types.ModuleType(name)
    module.__file__ = f"<{name}>"
    exec(compile(source, module.__file__, "exec"), module.__dict__)
    return module


def _store(key: str, model_name: str, source: str) -> None:
    """Cache `source` as the entry `key`; a cache that cannot be written is skipped."""
    try:
        with cache.new_entry(key) as work:
            (work / MODULE).write_text(source)
            cache.publish(work, key, f"{model_name}: Python module")
    except OSError:
        pass


def header(module) -> list[str]:
    return ["t", *module.STATE, *module.MULTIPLIERS, *module.INVARIANTS]


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
        lam = accelerations(t, y)[1]
        inv = module.invariants(t, y, p)
        return [t, *y, *lam, *(inv[name] for name in module.INVARIANTS)]

    sink = Trajectory() if sink is None else sink
    sink.begin(header(module))
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
