"""A sweep from start to end: plan -> consistent initial states -> chunks -> summary.

1. The compiled driver is built once (the C backend's cache, as `lagcli simulate`).
2. Each run's values are split by the layout into parameters, initial values and
   inputs; its initial state is made consistent here, in Python, as `simulate` does
   (`lagcli.analysis.initial_state`: dependent coordinates and velocities solved for) — a
   run whose state cannot be made consistent is recorded as failed with the reason.
   The driver then gets the whole state and every changed parameter of every run.
3. The runs not yet in the journal go in chunks to local driver processes or to a
   Dask cluster (`lagcli.sweep.executors`); finished chunks go to the journal (and
   their trajectories to `--trajectories DIR`) as they come.
4. The summary is written sorted by run id (`lagcli.sweep.summary`).
"""
from __future__ import annotations

import contextlib
import hashlib
import math
import os
from dataclasses import dataclass, field

from lagcli.version import __version__
from lagcli.errors import LagcliError, SimulationError, UsageError
from lagcli.runtime.run_rules import EXPLICIT_METHODS
from lagcli.render.output import check_directory_output, resolve_target, write_output
from lagcli.run.options import Request, RunSettings, resolve_settings
from lagcli.sweep import driver, executors, summary
from lagcli.sweep.plan import Plan

CHUNKS_PER_WORKER = 4            # enough chunks to balance the workers' load
MAX_CHUNK = 256                  # runs per chunk: what a lost chunk costs again


@dataclass(frozen=True)
class SweepOptions:
    """What a sweep is asked for besides its plan (None: the spec's value, else the default)."""

    t_end: float | None = None
    dt: float | None = None
    method: str | None = None
    rtol: float | None = None
    atol: float | None = None
    baumgarte: tuple[float, float] | None = None
    parameters: dict = field(default_factory=dict)    # fixed overrides for every run (--set)
    initial: dict = field(default_factory=dict)       # fixed initial values (--init)
    exceed: dict = field(default_factory=dict)        # NAME -> VALUE: exceed_<NAME> metrics
    inputs: dict = field(default_factory=dict)        # input laws for every run (--input): NAME -> text or sympy
    output: str | None = None                         # the summary file (None: in memory only)
    trajectories: str | None = None                   # DIR for run_<id>.csv
    workers: int | None = None                        # local driver processes (None: every core)
    scheduler: str | None = None                      # a Dask scheduler's address


@dataclass(frozen=True)
class SweepResult:
    """The summary: `csv` (its text, sorted by run id) and where it was written."""

    header: tuple[str, ...]
    csv: str
    path: str | None = None

    def column(self, name: str):
        """A column as a numpy array (float; `status` and `failure` as str)."""
        import numpy as np

        k = self.header.index(name)
        cells = [_cells(line)[k] for line in self.csv.splitlines()[1:]]
        return np.array(cells, dtype=str if name in ("status", "failure") else float)

    def to_pandas(self):
        import io

        import pandas as pd

        return pd.read_csv(io.StringIO(self.csv), keep_default_na=False,
                           na_values={n: ["nan"] for n in self.header if n not in ("status", "failure")})


def _cells(line: str) -> list[str]:
    import csv

    return next(csv.reader([line]))


def sweep(system, plan: Plan, options: SweepOptions, note=lambda text: None, progress=None) -> SweepResult:
    """Run every run of `plan` on `system` (a lagcli.System); see the module docstring."""
    layout = system.layout
    settings = _settings(system, options)
    kinds = _kinds(layout, plan, options)
    if options.output is not None:
        resolve_target(options.output)                       # a bad -o fails before any work
    if options.trajectories is not None:
        check_directory_output(options.trajectories)
    laws = _laws(system, options.inputs)
    held = {name: 0.0 for name in (*plan.names, *options.parameters) if kinds[name] == "input"}
    program, binary = _driver(system, held, laws)
    exceed = _exceed(layout, options.exceed)
    arguments = _arguments(settings, exceed, options.trajectories is not None)
    lines, failed = _run_lines(system, plan, options, kinds)
    metrics = _metric_names(layout, exceed)
    names, _ = driver.run_batch(program, arguments, [])      # the driver's own #summary line
    if names != metrics:
        raise SimulationError(f"lagcli bug: the driver's summary columns {names} are not the layout's {metrics}")
    header = summary.summary_header(plan.names, metrics)
    journal = _journal(system, options, arguments + [f"--input {k}={v}" for k, v in sorted(laws.items())],
                       lines, failed, header)
    done = dict(journal.done) if journal else {}
    for run_id, reason in failed.items():
        done.setdefault(run_id, summary.summary_line(_failed(run_id, reason, metrics), plan.values[run_id]))
    pending = [lines[k] for k in sorted(lines) if k not in done]
    if journal and journal.done:
        note(f"resuming: {len(journal.done)} of {len(plan)} runs were done already ({journal.path})")
    try:
        with (progress or _no_progress)(len(plan)) as update:
            _execute(system, plan, options, arguments, binary, program, pending, done, journal, update,
                     len(plan) - len(pending))
    except KeyboardInterrupt:
        kept = f"; they are kept in {journal.path}: run the same command again to resume" if journal else ""
        raise SimulationError(f"sweep interrupted after {len(done)} of {len(plan)} runs{kept}") from None
    finally:
        if journal:
            journal.close()
    if options.output is not None:
        summary.write_summary(options.output, header, done)
        if journal:
            journal.remove()
    return SweepResult(tuple(header), summary.summary_csv(header, done), options.output)


@contextlib.contextmanager
def _no_progress(total):
    yield None


def _settings(system, options: SweepOptions) -> RunSettings:
    request = Request(system.model.source, options.t_end, options.dt, options.method, options.rtol,
                      options.atol, baumgarte=options.baumgarte)
    settings = resolve_settings(request, system.layout.settings.as_dict())
    if settings.method not in EXPLICIT_METHODS:
        raise UsageError(f"--method {settings.method}: sweeps run the compiled driver, which implements "
                         f"{' and '.join(EXPLICIT_METHODS)}")
    return settings


def _kinds(layout, plan: Plan, options: SweepOptions) -> dict[str, str]:
    """'parameter', 'state' or 'input' for every varied or fixed name (else a UsageError)."""
    from lagcli.run.options import _hint

    kinds = {**{p: "parameter" for p in layout.parameter_names}, **{s: "state" for s in layout.state_names},
             **{i.name: "input" for i in getattr(layout, "inputs", ())}}
    for where, names in (("sweep", plan.names), ("--set", options.parameters), ("--init", options.initial)):
        for name in names:
            if name not in kinds:
                raise UsageError(f"{where}: unknown name {name!r}: a sweep varies parameters, inputs "
                                 "and initial values" + _hint(name, list(kinds), "names"))
    return kinds


def _laws(system, given: dict) -> dict:
    """The sweep's input laws {name: sympy law}: text parsed with the safe parser; a
    Python callable is refused (the compiled driver runs the law as C code)."""
    from lagcli.model.hybrid_model import parse_law

    from lagcli.run.options import _hint

    laws = {}
    for name, law in given.items():
        if name not in system.layout.input_names:
            raise UsageError(f"--input {name}: unknown input {name!r}"
                             + _hint(name, list(system.layout.input_names), "inputs"))
        if isinstance(law, str):
            law = parse_law(system.model, name, law, f"--input {name}").expr
        elif not hasattr(law, "free_symbols"):
            raise UsageError(f"inputs={{{name!r}: ...}}: a sweep runs the compiled driver, which takes a law "
                             "as an expression (text such as '-k*x'), not a Python callable")
        laws[name] = law
    return laws


def _driver(system, held: dict, laws: dict) -> tuple[str, bytes]:
    """The compiled driver (built into the cache if needed): (path to run, its bytes).
    `held`: the inputs the sweep gives values (no law for them); `laws`: --input's, over
    the spec's (they are C code of the driver: lagcli.system.System.program)."""
    from lagcli.run import c_backend

    if c_backend.find_compiler() is None:
        raise SimulationError("lagcli sweep runs the compiled driver, but 'cc' was not found on PATH "
                              "(install gcc or clang)")
    try:
        cached = system.program("c", values=held, laws=laws)
    except UsageError as exc:
        raise UsageError(f"{system.model.source}: lagcli sweep runs the compiled C driver, which cannot run this "
                         f"spec: {str(exc).splitlines()[0].split(': ', 1)[-1]}\n"
                         "  hint: loop over `lagcli simulate` (its Python backend runs it)") from None
    return cached.binary, cached.entry.contents[c_backend.BINARY]


def _exceed(layout, exceed: dict) -> dict[str, float]:
    for name in exceed:
        if name not in layout.state_names:
            raise UsageError(f"--exceed {name}: not a coordinate or velocity; state names are: "
                             f"{', '.join(layout.state_names)}")
    return {name: float(value) for name, value in exceed.items()}


def _arguments(settings: RunSettings, exceed: dict, rows: bool) -> list[str]:
    from lagcli.run.c_backend import driver_arguments

    return driver_arguments(settings, {}, {}) + driver.batch_options(rows, exceed)


def _metric_names(layout, exceed: dict) -> list[str]:
    """The driver's #summary names (lagcli_driver.c, batch mode), made from the layout."""
    states, invariants = layout.state_names, layout.invariant_names
    return (["t_last", *driver.COUNTS]
            + [f"final_{name}" for name in layout.header[1:]]           # every column but t
            + [f"min_{s}" for s in states] + [f"max_{s}" for s in states]
            + [f"drift_{name}" for name in invariants] + [f"exceed_{name}" for name in exceed])


def _run_lines(system, plan: Plan, options: SweepOptions, kinds) -> tuple[dict[int, str], dict[int, str]]:
    """{run id: the driver's input line} and {run id: why its initial state failed}."""
    from lagcli.analysis.initial_state import Sources, initial_state

    model, layout = system.model, system.layout
    defaults = layout.parameter_defaults
    sources = Sources("the sweep's values", "initial:", "the sweep's values")
    lines, failed = {}, {}
    for run_id in range(len(plan)):
        values = {**options.parameters, **options.initial, **plan.run(run_id)}
        params = {**defaults, **{k: v for k, v in values.items() if kinds[k] == "parameter"}}
        given = {k: v for k, v in values.items() if kinds[k] == "state"}
        inputs = {k: v for k, v in values.items() if kinds[k] == "input"}
        state = {**model.initial, **given}
        if layout.constrained:
            try:
                start = initial_state(system.derivation, state, params, soft=set(model.initial) - set(given),
                                      sources=sources)
            except LagcliError as exc:
                failed[run_id] = "initial state: " + " ".join(str(exc).split())
                continue
            state = dict(zip(layout.state_names, start.values))
        changed = {k: v for k, v in params.items() if v != defaults[k]}
        full = {name: state.get(name, 0.0) for name in layout.state_names}
        lines[run_id] = driver.run_line(run_id, {**changed, **full, **inputs})
    return lines, failed


def _failed(run_id: int, reason: str, metrics) -> driver.RunResult:
    values = tuple("0" if name in driver.COUNTS else "nan" for name in metrics)
    return driver.RunResult(run_id, reason, values)


def _journal(system, options: SweepOptions, arguments, lines, failed, header) -> summary.Journal | None:
    if options.output is None:
        return None
    digest = hashlib.sha256(system.spec_bytes)      # as read: a file, standard input or text
    for part in (__version__, *arguments, str(bool(options.trajectories)), *header,
                 *lines.values(), *(f"{k}:{v}" for k, v in sorted(failed.items()))):
        digest.update(part.encode() + b"\0")
    return summary.Journal(options.output, digest.hexdigest(), header)


def _execute(system, plan, options, arguments, binary, program, pending, done, journal, update, finished):
    if not pending:
        return
    workers = options.workers or executors.default_workers()
    size = max(1, min(MAX_CHUNK, math.ceil(len(pending) / (CHUNKS_PER_WORKER * workers))))
    chunks = [pending[k:k + size] for k in range(0, len(pending), size)]
    if options.scheduler:
        results = executors.dask_chunks(options.scheduler, binary, arguments, chunks)
    else:
        results = executors.local_chunks(program, arguments, chunks, workers)
    try:
        for _, chunk in results:
            _record(system, plan, options, chunk, done, journal)
            finished += len(chunk)
            if update is not None:
                update(finished)
    except driver.DriverDied as exc:
        raise SimulationError(str(exc)) from None
    finally:
        results.close()


def _record(system, plan, options, chunk, done, journal) -> None:
    if options.trajectories:
        _write_trajectories(system.layout, options.trajectories, chunk, len(plan))
    lines = [summary.summary_line(result, plan.values[result.run]) for result in chunk]
    if journal:
        journal.add(lines)
    for result, line in zip(chunk, lines):
        done[result.run] = line


def trajectory_path(directory: str, run_id: int, total: int) -> str:
    return os.path.join(directory, f"run_{run_id:0{len(str(max(total - 1, 0)))}d}.csv")


def _write_trajectories(layout, directory: str, chunk, total: int) -> None:
    os.makedirs(directory, exist_ok=True)
    head = ",".join(layout.header) + "\n"
    for result in chunk:
        write_output(trajectory_path(directory, result.run, total),
                     head + "".join(row + "\n" for row in result.rows))
