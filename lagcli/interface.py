"""The typed interface of a system (`Layout`): what every consumer reads, written once.

A `Layout` says, in spec order, what a run of a system is made of:

    states        q..., then q'... (`<q>_dot`)                       y = [q, q']
    parameters    name, default (and room for a unit)                p
    inputs        name, default, latex, description (spec `inputs:`)  u
    multipliers   lambda_<j> (1-based) or lambda_<name>, one per constraint row
    columns       the CSV columns, each with its kind:
                    t                        time
                    <q>                      coordinate
                    <q>_dot                  velocity
                    lambda_<k>               multiplier       (constrained)
                    energy                   energy           (T + V)
                    jacobi                   jacobi           (when the integral exists)
                    p_<q>                    momentum         (each ignorable coordinate)
                    constraint_residual      residual         (constrained)
    settings      t_end, dt, method, rtol, atol with their defaults

The naming rules of generated names (`_dot`, `_ddot`, `lambda_`, `p_`, the fixed
column names) live here and nowhere else: the spec checker asks `reserved_reason`
and `column_clash` which declared names would collide with them, and consumers
read a column's kind instead of guessing it from its name.

No sympy and no numpy here: the warm C path reads a layout back from cache
metadata (`Layout.to_json` / `Layout.from_json`) without importing either.
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, fields

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
STEP_BUDGET_BASE = 20_000         # a run takes at most this many integrator steps, plus
STEP_BUDGET_PER_OUTPUT = 1_000    # this many per output interval, unless --max-steps says otherwise
STEP_BUDGET_TEXT = ("the integration reached its bound of {steps} steps before t_end (a stiff or "
                    "blowing-up solution?); raise the bound with --max-steps N")


def default_max_steps(t_end: float, dt: float) -> int:
    """The step budget of a run (`--max-steps` default): deterministic, from the output grid
    (the C driver's `step_budget` is the same rule)."""
    return STEP_BUDGET_BASE + STEP_BUDGET_PER_OUTPUT * math.ceil(t_end / dt - 1e-9)

# --- naming rules ---------------------------------------------------------------------

TIME = "t"
ENERGY = "energy"
JACOBI = "jacobi"
RESIDUAL = "constraint_residual"
VELOCITY_SUFFIX = "_dot"
ACCELERATION_SUFFIX = "_ddot"
MULTIPLIER_PREFIX = "lambda_"
MOMENTUM_PREFIX = "p_"

COLUMN_KINDS = ("time", "coordinate", "velocity", "multiplier", "energy", "jacobi",
                "momentum", "residual")
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
    name: str
    kind: str                    # "coordinate" | "velocity"
    coordinate: str              # the coordinate it belongs to (itself for a coordinate)


@dataclass(frozen=True)
class Parameter:
    name: str
    default: float
    unit: str | None = None      # room: specs do not give units yet


@dataclass(frozen=True)
class Input:
    """An input signal u_k (spec `inputs:`), in spec order; `default` is the value
    generated code and simulate use when a run does not set it."""

    name: str
    default: float = 0.0
    latex: str | None = None
    description: str | None = None


@dataclass(frozen=True)
class Multiplier:
    name: str
    constraint: str | None       # the constraint's `name:`, if any
    kind: str                    # "holonomic" | "nonholonomic"


@dataclass(frozen=True)
class Column:
    name: str
    kind: str                    # one of COLUMN_KINDS
    of: str | None = None        # momentum: its coordinate


@dataclass(frozen=True)
class Settings:
    """A run's settings; these defaults apply when the spec's `simulate:` omits a key."""

    t_end: float = 10.0
    dt: float = 0.01
    method: str = "DOP853"
    rtol: float = 1e-9
    atol: float = 1e-12

    def as_dict(self) -> dict:
        return asdict(self)


SETTING_NAMES = tuple(f.name for f in fields(Settings))


@dataclass(frozen=True)
class Layout:
    name: str
    states: tuple[State, ...]
    parameters: tuple[Parameter, ...]
    multipliers: tuple[Multiplier, ...]
    columns: tuple[Column, ...]
    settings: Settings = field(default_factory=Settings)
    inputs: tuple[Input, ...] = ()

    @property
    def coordinates(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states if s.kind == "coordinate")

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
        """The CSV header."""
        return tuple(c.name for c in self.columns)

    @property
    def invariants(self) -> tuple[Column, ...]:
        """The invariant columns (energy, jacobi, momenta, residual), in CSV order."""
        return tuple(c for c in self.columns if c.kind in INVARIANT_KINDS)

    @property
    def constrained(self) -> bool:
        return bool(self.multipliers)

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
        return cls(name=data["name"],
                   states=tuple(State(**s) for s in data["states"]),
                   parameters=tuple(Parameter(**p) for p in data["parameters"]),
                   multipliers=tuple(Multiplier(**m) for m in data["multipliers"]),
                   columns=tuple(Column(**c) for c in data["columns"]),
                   settings=Settings(**data["settings"]),
                   inputs=tuple(Input(**i) for i in data["inputs"]))


def layout_of(d) -> Layout:
    """The layout of a `lagcli.derive.result.Derivation`."""
    model = d.model
    coordinates = [q.name for q in model.q]
    states = ([State(q, "coordinate", q) for q in coordinates]
              + [State(velocity_name(q), "velocity", q) for q in coordinates])
    multipliers = tuple(Multiplier(row.multiplier.name, row.label, row.kind) for row in d.constraints)
    columns = ([Column(TIME, "time")] + [Column(s.name, s.kind) for s in states]
               + [Column(m.name, "multiplier") for m in multipliers] + [Column(ENERGY, "energy")])
    if d.jacobi_integral is not None:
        columns.append(Column(JACOBI, "jacobi"))
    columns += [Column(momentum_name(q.name), "momentum", q.name) for q in d.ignorable]
    if multipliers:
        columns.append(Column(RESIDUAL, "residual"))
    layout = Layout(model.name, tuple(states),
                    tuple(Parameter(p.symbol.name, float(p.value)) for p in model.parameters),
                    multipliers, tuple(columns), model.settings,
                    tuple(Input(u.symbol.name, float(u.value), u.latex, u.description)
                          for u in model.inputs))
    require_unique(layout)
    return layout


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
