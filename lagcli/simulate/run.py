"""`simulate`: a Request in, its rows out into a sink, through the C or the Python backend.

    warm C path   spec bytes -> cache key -> meta.json -> driver          (no sympy, no numpy)
    cold path     spec -> Model -> Derivation -> consistent initial state
                  -> C: generate, compile, cache, run the driver
                  -> Python: the generated module (cached source) + scipy

The warm path runs only when the cache holds a driver for this very spec and the
state is known to be consistent: the spec's own initial state was made consistent
when the driver was built (meta.json), and for `--set`/`--init` overrides of a
constrained system the driver's first row (its constraint_residual at t = 0) is
checked; if it exceeds 1e-8 the driver is stopped (before any row reaches the sink)
and the cold path solves for the dependent coordinates/velocities, then reruns the
cached driver.

The rows go to a `RowSink` (lagcli.simulate.trajectory) as they are computed: the
CLI's writes the CSV file as the run goes on, the default keeps them in memory.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass

from lagcli.errors import SimulationError, UsageError
from lagcli.simulate import c_backend
from lagcli.numerics import CONSTRAINT_TOLERANCE, EXPLICIT_METHODS
from lagcli.simulate.options import Request, RunSettings, parse_assignments, resolve_settings
from lagcli.simulate.trajectory import RowSink, Trajectory
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
    if request.backend == "c" and compiler is None:
        raise SimulationError("--backend c needs a C compiler, but 'cc' was not found on PATH "
                              "(install gcc or clang, or use --backend python)")
    if compiler and request.backend in (None, "c") and request.method in (None, *EXPLICIT_METHODS):
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
    meta = cached.meta
    settings = resolve_settings(request, meta["settings"])
    if settings.method not in EXPLICIT_METHODS:
        return None
    sets = parse_assignments(request.sets, "--set", list(meta["parameters"]) + list(meta.get("inputs", {})),
                             "parameter or input", "parameters and inputs")
    inits = parse_assignments(request.inits, "--init", meta["state"], "coordinate or velocity",
                               "coordinates and velocities")
    if sets or inits:
        given = {**meta["initial"], **inits}
        state, notes = [given.get(name, 0.0) for name in meta["state"]], []
    elif meta["default_state"] is not None:
        state, notes = meta["default_state"], meta["default_notes"]
    else:
        return None                           # the spec's own state is inconsistent: cold path says so
    limit = CONSTRAINT_TOLERANCE if meta["constrained"] and (sets or inits) else None
    args = c_backend.driver_arguments(settings, sets, dict(zip(meta["state"], state)))
    with progress(settings.t_end) as update:
        traj = c_backend.run(cached, args, update, max_first_residual=limit, sink=sink)
    if traj is None:
        return None
    for text in notes:
        note(text)
    return Outcome(traj, "c", tuple(meta["coordinates"]), meta["energy_conserved"])


def _cold(request: Request, compiler: str | None, note, progress, sink: RowSink) -> Outcome:
    from lagcli.api import derive_model, load_model
    from lagcli.simulate.initial import initial_state

    model = load_model(request.spec)
    settings = resolve_settings(request, _spec_settings(model))
    backend = _backend(request, settings, compiler)
    parameter_names = [p.symbol.name for p in model.parameters]
    input_names = [u.symbol.name for u in model.inputs]
    sets = parse_assignments(request.sets, "--set", parameter_names + input_names,
                             "parameter or input", "parameters and inputs")
    state_names = [s.name for s in model.q + model.qd]
    inits = parse_assignments(request.inits, "--init", state_names, "coordinate or velocity",
                               "coordinates and velocities")
    d = derive_model(model)
    params = {**{p.symbol.name: p.value for p in model.parameters},
              **{name: value for name, value in sets.items() if name not in input_names}}
    inputs = {**{u.symbol.name: u.value for u in model.inputs},
              **{name: value for name, value in sets.items() if name in input_names}}
    soft = set(model.initial) - set(inits)        # the spec's values: solved for when nothing else can be
    start = initial_state(d, {**model.initial, **inits}, params, soft=soft)
    for text in start.notes:
        note(text)
    spec_start = None if sets or inits else (start, True)   # the spec's own state: solved once
    coordinates = tuple(s.name for s in model.q)
    energy_conserved = d.jacobi_integral is not None and d.energy_is_jacobi
    if backend == "python":
        traj = _python(d, request.spec, spec_start, params, start.values, settings, progress, sink, inputs)
    else:
        cached = _cached_driver(d, request.spec, compiler, spec_start)
        args = c_backend.driver_arguments(settings, sets, dict(zip(state_names, start.values)))
        with progress(settings.t_end) as update:
            traj = c_backend.run(cached, args, update, sink=sink)
    return Outcome(traj, backend, coordinates, energy_conserved)


def _backend(request: Request, settings: RunSettings, compiler: str | None) -> str:
    if request.backend == "c" and settings.method not in EXPLICIT_METHODS:
        raise UsageError(f"--method {settings.method}: the C backend implements "
                         f"{' and '.join(EXPLICIT_METHODS)} only; use --backend python for {settings.method}")
    if request.backend:
        return request.backend
    return "c" if compiler and settings.method in EXPLICIT_METHODS else "python"


def _spec_settings(model) -> dict:
    s = model.settings
    return {"t_end": s.t_end, "dt": s.dt, "method": s.method, "rtol": s.rtol, "atol": s.atol}


def _python(d, spec: str, spec_start, params: dict, y0, settings: RunSettings, progress,
            sink: RowSink, inputs: dict) -> RowSink:
    from lagcli.simulate.python_backend import cached_module, integrate_module

    module = cached_module(d, spec, spec_start)
    p = [params[p.symbol.name] for p in d.model.parameters]
    u = [inputs[u.symbol.name] for u in d.model.inputs] if d.model.inputs else None
    with progress(settings.t_end) as update:
        return integrate_module(module, p, list(y0), settings, update, sink, u)


def _cached_driver(d, spec: str, compiler: str, spec_start=None) -> c_backend.Cached:
    """The compiled driver of `d` from the cache, building it (and meta.json) if needed.
    `spec_start`: `initial.spec_initial_state(d)` when the caller has it already."""
    key = c_backend.cache_key(spec, read_spec_bytes(spec), compiler)
    cached = c_backend.lookup(key)
    if cached is not None:
        return cached
    from lagcli.emit.c import c_files
    from lagcli.simulate.initial import spec_initial_state

    model = d.model
    defaults = {p.symbol.name: p.value for p in model.parameters}
    start, consistent = spec_start or spec_initial_state(d)
    files = c_files(d, initial=start.values, initial_notes=start.notes)
    if not consistent:
        start = None                          # only runs with a repairing --init can use it
    meta = {
        "name": model.name,
        "coordinates": [s.name for s in model.q],
        "state": [s.name for s in model.q + model.qd],
        "parameters": defaults,
        "inputs": {u.symbol.name: u.value for u in model.inputs},   # the driver's --set takes them too
        "initial": dict(model.initial),
        "settings": _spec_settings(model),
        "constrained": bool(d.constraints),
        "energy_conserved": d.jacobi_integral is not None and d.energy_is_jacobi,
        "default_state": list(start.values) if start else None,
        "default_notes": list(start.notes) if start else [],
    }
    return c_backend.build(files, key, compiler, meta)
