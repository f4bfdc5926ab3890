"""`simulate`: a Request in, its rows out into a sink, through the C or the Python backend.

    warm C path   spec bytes -> cache key -> meta.json (the Layout) -> driver   (no sympy, no numpy)
    cold path     lagcli.load(spec) -> System -> System.start (consistent initial state)
                  -> System.run: C: generate, compile, cache, run the driver
                                 Python: the generated module (cached source) + scipy

The cold path is the Python API's own (`lagcli.system.System`): the command line has
no second way to run a simulation.

The warm path runs only when the cache holds a driver for this very spec and the
state is known to be consistent: the spec's own initial state was made consistent
when the driver was built (meta.json), and for `--set`/`--init` overrides of a
constrained system the driver's first row (its constraint_residual at t = 0) is
checked; if it exceeds 1e-8 the driver is stopped (before any row reaches the sink)
and the cold path solves for the dependent coordinates/velocities, then reruns the
cached driver.

The rows go to a `RowSink` (lagcli.run.rows) as they are computed: the
CLI's writes the CSV file as the run goes on, the default keeps them in memory.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass
from pathlib import Path

from lagcli.errors import SimulationError
from lagcli.run import c_backend
from lagcli.interface import C_METHODS, CONSTRAINT_TOLERANCE, VARIATIONAL
from lagcli.runtime.run_rules import EXPLICIT_METHODS
from lagcli.run.options import Request, parse_assignments, resolve_settings
from lagcli.run.rows import RowSink, Tee, Trajectory
from lagcli.spec.files import read_spec_bytes


class Interrupted(SimulationError):
    """Ctrl-C: during the integration (the rows so far are written) or before it, while
    deriving, generating or compiling (nothing is written). Exit status 1, like every
    run-time failure (README, "Exit status": only 0, 1 and 2)."""


@dataclass(frozen=True)
class Outcome:
    trajectory: RowSink           # the sink given to `simulate`, holding the run's end state
    backend: str                  # "c" | "python"
    coordinates: tuple[str, ...]
    energy_conserved: bool        # the energy column is conserved (it equals the Jacobi integral)
    states: tuple[str, ...] = ()  # the state names (the columns of --events)
    watched_events: bool = False  # the spec has events (the run says how many happened)


def simulate(request: Request, note=lambda text: None, progress=None, sink: RowSink | None = None
             ) -> Outcome:
    """Run `request`, giving the rows to `sink` (a new in-memory `Trajectory` when None).
    `note(text)` receives remarks for stderr; `progress(t_end)` is a context manager
    yielding `update(t)` (or None for no progress report)."""
    try:
        return _simulate(request, note, progress or _no_progress, Trajectory() if sink is None else sink)
    except KeyboardInterrupt:
        raise Interrupted(f"{request.spec}: interrupted before the integration started "
                          "(while deriving, generating or compiling); nothing was written") from None


def _simulate(request: Request, note, progress, sink: RowSink) -> Outcome:
    compiler = c_backend.find_compiler()
    if request.backend == "c":
        c_backend.require_compiler(request.method or EXPLICIT_METHODS[0])   # before any work
    if compiler and request.backend in (None, "c") and request.method in (None, *C_METHODS) \
            and not request.inputs:
        outcome = _warm(request, compiler, note, progress, sink)
        if outcome is not None:
            return outcome
    return _cold(request, compiler, note, progress, sink)


@contextlib.contextmanager
def _no_progress(total):
    yield None


def _warm(request: Request, compiler: str, note, progress, sink: RowSink) -> Outcome | None:
    spec_bytes = read_spec_bytes(request.spec)  # size-limited; refuses a FIFO or a device
    cached = c_backend.lookup(c_backend.cache_key(request.spec, spec_bytes, compiler))
    if cached is None:
        return None
    meta, layout = cached.meta, cached.layout
    settings = resolve_settings(request, layout.settings.as_dict())
    if settings.method not in C_METHODS or (settings.method == VARIATIONAL and any(
            m.kind != "holonomic" for m in layout.multipliers)):
        return None                           # the cold path refuses it, naming the constraint
    sets, inits = _overrides(request, layout)
    if sets or inits:
        given = {**meta["initial"], **inits}
        state, notes = [given.get(name, 0.0) for name in layout.state_names], []
    elif meta["default_state"] is not None:
        state, notes = meta["default_state"], meta["default_notes"]
    else:
        return None                           # the spec's own state is inconsistent: cold path says so
    limit = CONSTRAINT_TOLERANCE if layout.constrained and (sets or inits) else None
    args = c_backend.driver_arguments(settings, sets, dict(zip(layout.state_names, state)))
    watched, drift = _watched(settings, layout, sink)
    with progress(settings.t_end) as update:
        traj = c_backend.run(cached, args, update, max_first_residual=limit, sink=watched)
    if traj is None:
        return None
    if sets and traj.failure and traj.rows <= 1:
        _explain_failed_start(request, sets)        # --set m=0: physical validation, not "singular"
    for text in _at_rest(meta["initial"], inits) + list(notes):
        note(text)
    _drift_note(drift, settings, note)
    return Outcome(traj, "c", layout.coordinates, meta["energy_conserved"], layout.state_names)


def _explain_failed_start(request: Request, sets: dict) -> None:
    """A warm run with --set that failed at its start: raise what physical validation says
    of those values, if anything (the cold path says it before running; the warm path
    does not import sympy unless a run fails this way)."""
    from lagcli.system import load

    load(Path(request.spec)).start(sets, {})


def _cold(request: Request, compiler: str | None, note, progress, sink: RowSink) -> Outcome:
    """Through the Python API: load the System, make the initial state consistent, run."""
    from lagcli.system import load

    system = load(Path(request.spec))
    layout = system.layout
    settings = resolve_settings(request, layout.settings.as_dict())
    sets, inits = _overrides(request, layout)
    laws = _laws(request, system)
    backend = request.backend or ("c" if compiler and settings.method in C_METHODS else "python")
    python_only = system.hybrid(sets, laws) is not None and system.compiled_laws(sets, laws) is None
    if python_only and request.backend is None:
        backend = "python"
        if compiler:
            note("lagcli: events run on the Python backend (the C driver does not run them yet)")
    start = system.start(sets, inits)
    for text in _at_rest(system.model.initial, inits) + list(start.notes):
        note(text)
    watched, drift = _watched(settings, layout, sink)
    traj = system.run(settings, sets, start, backend, watched, progress, laws=laws)
    _drift_note(drift, settings, note)
    return Outcome(traj, backend, layout.coordinates, system.energy_conserved, layout.state_names,
                   bool(system.model.events))


AT_REST = ("initial state: the spec has no initial: values and no --init was given, so the run starts "
           "at rest with every coordinate 0 (give initial: in the spec, or --init NAME=VALUE)")


def _at_rest(initial: dict, inits: dict) -> list[str]:
    """The note that a run starts from the all-zero state only because nothing was given."""
    return [] if initial or inits else [AT_REST]


def _laws(request: Request, system) -> dict:
    """--input NAME=EXPR as {name: sympy law}, parsed with the safe parser."""
    from lagcli.hybrid.hybrid_model import parse_law

    def parse(text, where):
        return text

    given = parse_assignments(request.inputs, "--input", list(system.layout.input_names), "input", "inputs",
                              parse)
    return {name: parse_law(system.model, name, text.strip(), f"--input {name}").expr
            for name, text in given.items()}


def _watched(settings, layout, sink: RowSink):
    """`sink`, and for --method variational also the drift of the integrals
    (`lagcli.run.variational_run.IntegralDrift`, the end-of-run line)."""
    if settings.method != VARIATIONAL:
        return sink, None
    from lagcli.run.variational_run import IntegralDrift

    drift = IntegralDrift(layout)
    return Tee(sink, drift), drift


def _drift_note(drift, settings, note) -> None:
    if drift is not None and drift.rows:
        note(drift.summary(settings.dt, settings.steps_per_row))


def _overrides(request: Request, layout) -> tuple[dict, dict]:
    """--set and --init as {name: value}, names checked against the layout."""
    sets = parse_assignments(request.sets, "--set", list(layout.parameter_names) + list(layout.input_names),
                             "parameter or input", "parameters and inputs")
    inits = parse_assignments(request.inits, "--init", list(layout.state_names),
                              "coordinate or velocity", "coordinates and velocities")
    return sets, inits
