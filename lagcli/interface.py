"""The run interface of a system (`Layout`): what everything after the System reads, written once.

A `Layout` says, in spec order, what a run of a system is made of:

    states        q..., then q'... (`<q>_dot`), each with its unit    y = [q, q']
    parameters    name, default, unit                                p
    inputs        name, default, latex, description (spec `inputs:`)  u
    multipliers   lambda_<j> (1-based) or lambda_<name>, one per constraint row
    columns       the CSV columns, each with its kind and unit:
                    t                        time             s
                    <q>                      coordinate       the spec's unit of q (none: dimensionless)
                    <q>_dot                  velocity         unit of q per s
                    lambda_<k>               multiplier       (constrained)
                    energy                   energy           J  (T + V)
                    jacobi                   jacobi           J  (when the integral exists)
                    p_<q>                    momentum         J*s/(unit of q) (each ignorable q)
                    constraint_residual      residual         (constrained)
                    force_<event>            contact          the normal force of an impact event
                                                              with `rest: true` (0 while free):
                                                              J per unit of its gap g (N for a length)
    settings      t_end, dt, method, rtol, atol with their defaults (`Settings`); a run's
                  own settings add the stabilisation gains (`RunSettings`, `DEFAULT_BAUMGARTE`)
    initial       the spec's `initial:`; start: the consistent default state and its notes
    integrals     energy_conserved (the energy column is the Jacobi integral); the jacobi and
                  momentum columns say which other integrals exist
    source        the spec's file name and description, lagcli's version

Units are filled only when the spec gives some (docs/spec.md, "Units"); `units_of`.

The naming rules of generated names (`_dot`, `_ddot`, `lambda_`, `p_`, the fixed
column names) live here and nowhere else: the spec checker asks `reserved_reason`
and `column_clash` which declared names would collide with them, and consumers
read a column's kind instead of guessing it from its name.

The System builds its layout once (`lagcli.system.System.layout`); the run layer, the
code targets, sweeps and pictures read it. No sympy and no numpy here: the warm C path
reads the layout back from the cache (`Layout.to_json` is the cache entry's metadata,
`Layout.from_json`) without importing either.
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, fields
from pathlib import PurePath

from lagcli.runtime.run_limits import (ACCUMULATION_GAP, EVENT_BUDGET, FIRST_STEP_SAMPLES,  # noqa: F401
                                       RESTING_SPEED, STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT, STEP_BUDGET_TEXT,
                                       default_max_steps)
from lagcli.runtime.run_rules import EXPLICIT_METHODS

# --- the numbers every stage shares ---------------------------------------------------
# (the spec schema, the command line, the run layer and the code targets; the rules the
# generated code carries too -- EXPLICIT_METHODS, output_times, max_step -- are code:
# lagcli/runtime/run_rules.py)

VARIATIONAL = "variational"       # lagcli's own fixed-step integrator (lagcli/derive/discrete.py)
METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA", VARIATIONAL)   # scipy's integrators, and lagcli's
C_METHODS = (*EXPLICIT_METHODS, VARIATIONAL)                         # the ones the compiled driver implements
DEFAULT_BAUMGARTE = (10.0, 10.0)                         # (alpha, beta) of the constraint stabilisation
CONSTRAINT_TOLERANCE = 1e-8                              # largest |constraint| of a consistent initial state
# The step budget of a run and the rules that end a run with accumulating events
# (docs/simulate.md, "Events and input laws") are code the generated Python module carries
# too: lagcli/runtime/run_limits.py (STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT,
# STEP_BUDGET_TEXT, default_max_steps, ACCUMULATION_GAP, RESTING_SPEED, EVENT_BUDGET,
# FIRST_STEP_SAMPLES), imported here for every stage.

# --- naming rules ---------------------------------------------------------------------

TIME = "t"
ENERGY = "energy"
JACOBI = "jacobi"
RESIDUAL = "constraint_residual"
VELOCITY_SUFFIX = "_dot"
ACCELERATION_SUFFIX = "_ddot"
MULTIPLIER_PREFIX = "lambda_"
MOMENTUM_PREFIX = "p_"
CONTACT_PREFIX = "force_"

COLUMN_KINDS = ("time", "coordinate", "velocity", "multiplier", "energy", "jacobi",
                "momentum", "residual", "contact")
INVARIANT_KINDS = ("energy", "jacobi", "momentum", "residual")


def velocity_name(coordinate: str) -> str:
    return coordinate + VELOCITY_SUFFIX


def acceleration_name(coordinate: str) -> str:
    return coordinate + ACCELERATION_SUFFIX


def multiplier_name(row: int, label: str | None = None) -> str:
    """lambda_<label> for a named constraint, else lambda_<row> (row is 1-based)."""
    return MULTIPLIER_PREFIX + (label or str(row))


def momentum_name(coordinate: str) -> str:
    return MOMENTUM_PREFIX + coordinate


def contact_force_name(event: str) -> str:
    """The column of the normal force of a held contact (an impact event with `rest: true`)."""
    return CONTACT_PREFIX + event


def reserved_reason(name: str, coordinates: set[str] | frozenset[str]) -> str:
    """Why `name` cannot be declared anywhere in a spec because lagcli generates it
    (a velocity, an acceleration, a multiplier), or ''."""
    if name.startswith(MULTIPLIER_PREFIX):
        return "'lambda_...' names are the constraint multipliers"
    for suffix, what in ((ACCELERATION_SUFFIX, "acceleration"), (VELOCITY_SUFFIX, "velocity")):
        if name.endswith(suffix) and name[: -len(suffix)] in coordinates:
            return f"it is the {what} of coordinate '{name[: -len(suffix)]}'"
    return ""


def column_clash(name: str, coordinates: set[str] | frozenset[str]) -> str:
    """Why a coordinate called `name` would give two CSV columns (or two generated
    identifiers) the same name, or ''. Coordinates are the spec names that become
    columns; `t` and multipliers are refused for every name by `reserved_reason`."""
    fixed = {ENERGY: "the energy column", JACOBI: "the Jacobi integral column",
             RESIDUAL: "the constraint residual column", TIME: "the time column"}
    if name in fixed:
        return f"it is {fixed[name]} of the simulate output"
    base = name[len(MOMENTUM_PREFIX):]
    if name.startswith(MOMENTUM_PREFIX) and base in coordinates:
        return f"it is the momentum column of coordinate '{base}' (when '{base}' is ignorable)"
    return ""


# --- the layout -----------------------------------------------------------------------


@dataclass(frozen=True)
class State:
    """A state of y = [q, q'], in spec order."""

    name: str
    kind: str                    # "coordinate" | "velocity"
    coordinate: str              # the coordinate it belongs to (itself for a coordinate)
    unit: str | None = None      # from the spec's units (velocity: the coordinate's per second)
    angle: bool = False          # the coordinate is an angle (a rotation, or inside sin/cos/tan)


@dataclass(frozen=True)
class Parameter:
    """A parameter of p, with its default value."""

    name: str
    default: float
    unit: str | None = None      # the spec's `unit:` (None: none given)


@dataclass(frozen=True)
class Input:
    """An input signal u_k (spec `inputs:`), in spec order; `default` is the value
    generated code and simulate use when a run does not set it."""

    name: str
    default: float = 0.0
    latex: str | None = None
    description: str | None = None
    unit: str | None = None


@dataclass(frozen=True)
class Multiplier:
    """A constraint multiplier, one per constraint row."""

    name: str
    constraint: str | None       # the constraint's `name:`, if any
    kind: str                    # "holonomic" | "nonholonomic"


@dataclass(frozen=True)
class Column:
    """A column of the CSV output, with its kind (`COLUMN_KINDS`)."""

    name: str
    kind: str                    # one of COLUMN_KINDS
    of: str | None = None        # momentum: its coordinate
    unit: str | None = None      # when the spec gives units (see `units_of`)


@dataclass(frozen=True)
class Settings:
    """A run's settings; these defaults apply when the spec's `simulate:` omits a key."""

    t_end: float = 10.0
    dt: float = 0.01
    method: str = "DOP853"
    rtol: float = 1e-9
    atol: float = 1e-12

    def as_dict(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(Settings)}


SETTING_NAMES = tuple(f.name for f in fields(Settings))


@dataclass(frozen=True)
class RunSettings(Settings):
    """The settings of one run: the spec's (or the defaults) under what the caller gave,
    and the constraint stabilisation gains (docs/design.md, "Equations")."""

    alpha: float = DEFAULT_BAUMGARTE[0]
    beta: float = DEFAULT_BAUMGARTE[1]
    max_steps: int = 0                   # integrator steps allowed (0: `default_max_steps(t_end, dt)`)
    steps_per_row: int = 1               # --method variational: the step is dt / steps_per_row

    @property
    def step_budget(self) -> int:
        return self.max_steps or default_max_steps(self.t_end, self.dt)


@dataclass(frozen=True)
class Start:
    """The spec's own initial state made consistent with the constraints (what generated
    code embeds and a run without --set/--init starts from), and what was solved for."""

    values: tuple[float, ...]            # [q..., q'...]
    notes: tuple[str, ...] = ()
    consistent: bool = True              # False: it could not be made consistent (used as given)


@dataclass(frozen=True)
class Source:
    """Where the system comes from, as generated files and caches say it."""

    file: str = ""                       # the spec's file name (no directory)
    description: str = ""
    version: str = ""                    # lagcli's


@dataclass(frozen=True)
class Layout:
    """The run interface of one system: see the module docstring."""

    name: str
    states: tuple[State, ...]
    parameters: tuple[Parameter, ...]
    multipliers: tuple[Multiplier, ...]
    columns: tuple[Column, ...]
    settings: Settings = field(default_factory=Settings)
    inputs: tuple[Input, ...] = ()
    initial: dict = field(default_factory=dict)      # the spec's `initial:` as given
    start: Start | None = None                       # the consistent default state (the System's)
    energy_conserved: bool = False                   # the energy column equals the Jacobi integral
    source: Source = field(default_factory=Source)
    events: tuple[str, ...] = ()                     # the names of the spec's events, in order

    @property
    def coordinates(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states if s.kind == "coordinate")

    @property
    def angles(self) -> frozenset:
        """The coordinates that are angles."""
        return frozenset(s.name for s in self.states if s.kind == "coordinate" and s.angle)

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def parameter_defaults(self) -> dict[str, float]:
        return {p.name: p.default for p in self.parameters}

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(u.name for u in self.inputs)

    @property
    def input_defaults(self) -> dict[str, float]:
        return {u.name: u.default for u in self.inputs}

    @property
    def multiplier_names(self) -> tuple[str, ...]:
        return tuple(m.name for m in self.multipliers)

    @property
    def header(self) -> tuple[str, ...]:
        """The CSV header: the one column order of every run and every target."""
        return tuple(c.name for c in self.columns)

    @property
    def kinds(self) -> dict[str, str]:
        """Each CSV column's kind, in CSV order: what pictures group columns by (never
        a guess from the name)."""
        return {c.name: c.kind for c in self.columns}

    @property
    def invariants(self) -> tuple[Column, ...]:
        """The invariant columns (energy, jacobi, momenta, residual), in CSV order."""
        return tuple(c for c in self.columns if c.kind in INVARIANT_KINDS)

    @property
    def invariant_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.invariants)

    @property
    def contacts(self) -> tuple[Column, ...]:
        """The contact force columns (impact events with `rest: true`), last in CSV order."""
        return tuple(c for c in self.columns if c.kind == "contact")

    @property
    def residual_index(self) -> int | None:
        """The place of `constraint_residual` among the invariant columns (None: unconstrained)."""
        kinds = [c.kind for c in self.invariants]
        return kinds.index("residual") if "residual" in kinds else None

    @property
    def fields(self) -> tuple[str, ...]:
        """The names a code target makes identifiers of, in one namespace (a struct's
        fields, index constants): the states, parameters, multipliers and invariant columns."""
        return self.state_names + self.parameter_names + self.multiplier_names + self.invariant_names

    @property
    def constrained(self) -> bool:
        return bool(self.multipliers)

    @property
    def units(self) -> dict[str, str]:
        """{name: unit} of every state, column, parameter and input that has one."""
        items = (*self.states, *self.columns, *self.parameters, *self.inputs)
        return {item.name: item.unit for item in items if item.unit}

    def column(self, name: str) -> Column:
        for c in self.columns:
            if c.name == name:
                return c
        raise KeyError(name)

    def to_json(self) -> str:
        return json.dumps(asdict(self), sort_keys=True)

    @classmethod
    def from_json(cls, text: str) -> "Layout":
        data = json.loads(text)
        start = data.get("start")
        return cls(name=data["name"],
                   states=tuple(State(**s) for s in data["states"]),
                   parameters=tuple(Parameter(**p) for p in data["parameters"]),
                   multipliers=tuple(Multiplier(**m) for m in data["multipliers"]),
                   columns=tuple(Column(**c) for c in data["columns"]),
                   settings=Settings(**data["settings"]),
                   inputs=tuple(Input(**i) for i in data["inputs"]),
                   initial=dict(data["initial"]),
                   start=None if start is None else Start(tuple(start["values"]), tuple(start["notes"]),
                                                          start["consistent"]),
                   energy_conserved=data["energy_conserved"],
                   source=Source(**data["source"]), events=tuple(data.get("events", ())))


def layout_of(d, start: Start | None = None, angles=frozenset()) -> Layout:
    """The layout of a `lagcli.derive.result.Derivation` (plain attribute reads: no sympy
    work here). `start` (the consistent initial state) and `angles` (the coordinates that
    are angles) are the System's, computed once (lagcli.system)."""
    from lagcli.version import __version__

    model = d.model
    unit = units_of(model)
    coordinates = [q.name for q in model.q]
    states = ([State(q, "coordinate", q, unit.get(q), q in angles) for q in coordinates]
              + [State(velocity_name(q), "velocity", q, unit.get(velocity_name(q)), q in angles)
                 for q in coordinates])
    multipliers = tuple(Multiplier(row.multiplier.name, row.label, row.kind) for row in d.constraints)
    columns = ([Column(TIME, "time", unit=unit.get(TIME))] + [Column(s.name, s.kind, unit=s.unit) for s in states]
               + [Column(m.name, "multiplier") for m in multipliers] + [Column(ENERGY, "energy", unit=unit.get(ENERGY))])
    if d.jacobi_integral is not None:
        columns.append(Column(JACOBI, "jacobi", unit=unit.get(ENERGY)))
    columns += [Column(momentum_name(q.name), "momentum", q.name, unit.get(momentum_name(q.name)))
                for q in d.ignorable]
    if multipliers:
        columns.append(Column(RESIDUAL, "residual"))
    columns += [Column(contact_force_name(e.name), "contact", unit=e.force_unit)
                for e in d.events if e.hold_bias is not None]
    layout = Layout(model.name, tuple(states),
                    tuple(Parameter(p.symbol.name, float(p.value), unit.get(p.symbol.name))
                          for p in model.parameters),
                    multipliers, tuple(columns), model.settings,
                    tuple(Input(u.symbol.name, float(u.value), u.latex, u.description) for u in model.inputs),
                    initial={k: float(v) for k, v in model.initial.items()}, start=start,
                    energy_conserved=d.jacobi_integral is not None and bool(d.energy_is_jacobi),
                    source=Source(PurePath(model.source).name, model.description or "", __version__),
                    events=tuple(e.name for e in model.events))
    require_unique(layout)
    return layout


def units_of(model) -> dict[str, str]:
    """{name: unit} from the spec's `unit:`s (docs/spec.md, "Units"): parameters and
    coordinates as given, velocities per second, t in s, energies in J, the momentum of
    q in J*s/(unit of q). Empty when the spec gives none; a name without one is
    dimensionless (angles too) and has none."""
    given = {name: text for name, (text, _) in model.units.items() if text}
    if not given:
        return {}
    units = {TIME: "s", ENERGY: "J", **given}
    for q in model.q:
        u = given.get(q.name)
        if u:
            units[velocity_name(q.name)] = _per(u, "s")
        units[momentum_name(q.name)] = _per("J*s", u) if u else "J*s"
    return units


def _per(unit: str, by: str) -> str:
    """unit / by, in the spec's unit language."""
    wrap = (lambda u: u) if all(c.isalnum() or c == "_" for c in by) else (lambda u: f"({u})")
    return f"{unit}/{wrap(by)}"


def require_unique(layout: Layout) -> None:
    """Every output name is unique within its namespace: the CSV header, the state and
    parameter names. The spec checker refuses names that would collide
    (`reserved_reason`, `column_clash`), so a clash here is a lagcli bug."""
    from lagcli.errors import EmitError

    for what, names in (("CSV column", layout.header),
                        ("parameter or input", layout.parameter_names + layout.input_names)):
        seen = set()
        for name in names:
            if name in seen:
                raise EmitError(f"{layout.name}: two {what}s are called {name!r}")
            seen.add(name)
