"""The run layer's entry: a run interface and a program in, the rows out into a sink.

    program     lagcli.run.c_backend.CDriver (a compiled driver in the cache) or
                lagcli.run.python_backend.PythonModule (the generated module + scipy); each has
                run(settings, values, state, sink, progress, max_first_residual) -> sink | None
    interface   lagcli.interface.Layout: names, defaults, units, the consistent default state

Both come from the System (`lagcli.system.System.layout`, `.program`) or, on the warm
path, from the cache alone (`cached_driver`: spec bytes -> key -> the driver and its
meta.json, the layout; no sympy, no numpy). This layer never imports the System, the
commands or the code targets: it compiles nothing it did not receive as sources, and
solves no initial state (the System does).

The warm path runs only when the state is known to be consistent: the spec's own initial
state was made consistent when the driver was built (the layout's `start`), and for
`--set`/`--init` overrides of a constrained system the driver's first row (its
constraint_residual at t = 0) is checked (`warm_start`: a limit of 1e-8); a run stopped
there returns None before any row reaches the sink, and the caller goes through the
System, which solves for the dependent coordinates and velocities.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass

from lagcli.errors import SimulationError
from lagcli.interface import CONSTRAINT_TOLERANCE, VARIATIONAL, Layout, RunSettings
from lagcli.run import c_backend
from lagcli.run.options import Overrides
from lagcli.run.rows import RowSink, Tee, Trajectory


class Interrupted(SimulationError):
    """Ctrl-C: during the integration (the rows so far are written) or before it, while
    deriving, generating or compiling (nothing is written). Exit status 1, like every
    run-time failure (README, "Exit status": only 0, 1 and 2)."""


@dataclass(frozen=True)
class Outcome:
    trajectory: RowSink           # the sink given to the run, holding the run's end state
    backend: str                  # "c" | "python"
    layout: Layout                # the run interface the rows follow
    watched_events: bool = False  # the spec has events (the run says how many happened)

    @property
    def coordinates(self) -> tuple[str, ...]:
        return self.layout.coordinates

    @property
    def energy_conserved(self) -> bool:
        return self.layout.energy_conserved

    @property
    def states(self) -> tuple[str, ...]:
        """The state names (the columns of --events)."""
        return self.layout.state_names


def cached_driver(spec: str, spec_bytes: bytes, compiler) -> c_backend.CDriver | None:
    """The compiled driver of this very spec in the cache (with its layout), or None."""
    return c_backend.lookup(c_backend.cache_key(spec, spec_bytes, compiler))


def warm_start(layout: Layout, overrides: Overrides) -> tuple[list[float], tuple[str, ...], float | None] | None:
    """(state, notes, first-row residual limit) of a run that needs no solving, or None
    when only the System can give a consistent state."""
    if overrides.values or overrides.initial:
        given = {**layout.initial, **overrides.initial}
        limit = CONSTRAINT_TOLERANCE if layout.constrained else None
        return [given.get(name, 0.0) for name in layout.state_names], (), limit
    if layout.start is not None and layout.start.consistent:
        return list(layout.start.values), layout.start.notes, None
    return None                               # the spec's own state is inconsistent: the System says so


def run(program, settings: RunSettings, overrides: Overrides, state, sink: RowSink | None = None,
        progress=None, max_first_residual: float | None = None) -> RowSink | None:
    """One run of `program` from `state`, its rows given to `sink` (in memory when None) as
    they are computed; `progress(t_end)`: a context manager yielding `update(t)` (or None).
    None when `max_first_residual` is given and the first row exceeds it."""
    sink = Trajectory() if sink is None else sink
    with (progress or _no_progress)(settings.t_end) as update:
        return program.run(settings, overrides.values, state, sink, update, max_first_residual)


@contextlib.contextmanager
def _no_progress(total):
    yield None


AT_REST = ("initial state: the spec has no initial: values and no --init was given, so the run starts "
           "at rest with every coordinate 0 (give initial: in the spec, or --init NAME=VALUE)")


def at_rest(initial: dict, inits: dict) -> list[str]:
    """The note that a run starts from the all-zero state only because nothing was given."""
    return [] if initial or inits else [AT_REST]


def watched(settings, layout, sink: RowSink):
    """`sink`, and for --method variational also the drift of the integrals
    (`lagcli.run.variational_run.IntegralDrift`, the end-of-run line)."""
    if settings.method != VARIATIONAL:
        return sink, None
    from lagcli.run.variational_run import IntegralDrift

    drift = IntegralDrift(layout)
    return Tee(sink, drift), drift


def drift_note(drift, settings, note) -> None:
    if drift is not None and drift.rows:
        note(drift.summary(settings.dt, settings.steps_per_row))
