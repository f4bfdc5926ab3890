"""The model: the spec turned into sympy objects (built by `lagcli.model.build.build_model`).

Symbols are real `sympy.Symbol`s: coordinate `theta`, its velocity
`theta_dot` and acceleration `theta_ddot` (`lagcli.model.symbols.Velocity`/`Acceleration`,
shown as θ̇, θ̈ by sympy's latex and pretty printers); time `t`. Known functions and
definitions are already substituted into every expression, so a model
expression depends only on t, q, q', parameters (and q'' where `diff` of a
velocity was asked for).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from lagcli.errors import Loc
from lagcli.interface import Settings  # noqa: F401 - the run settings and their defaults live in the layout


@dataclass(frozen=True)
class ParameterInfo:
    """A parameter's symbol, its value and how reports name it."""

    symbol: sp.Symbol
    value: float
    latex: str | None
    description: str | None


@dataclass(frozen=True)
class InputInfo:
    """An input signal u_k (spec `inputs:`): appears only in applied forces, torques
    and generalized forces; `value` is its default (held constant by simulate)."""

    symbol: sp.Symbol
    value: float
    latex: str | None
    description: str | None


@dataclass(frozen=True)
class PointMass:
    """A particle: its mass at an inertial position."""

    name: str
    mass: sp.Expr
    position: sp.ImmutableMatrix      # 3 x 1 (z = 0 for planar specs)
    loc: Loc | None = None


@dataclass(frozen=True)
class RigidBody:
    """A rigid body: mass, inertia and position of its centre of mass, orientation."""

    name: str
    mass: sp.Expr
    inertia: sp.ImmutableMatrix       # 3 x 3 about the CM, body axes (planar: diag(0, 0, Izz))
    position: sp.ImmutableMatrix      # 3 x 1
    rotations: tuple[tuple[str, sp.Expr], ...]  # successive body-fixed (axis, angle); planar: (("z", angle),)
    loc: Loc | None = None

    @property
    def rotation(self) -> sp.ImmutableMatrix:
        """Body -> inertial rotation matrix R = R_1(a_1) R_2(a_2) ..."""
        matrix = sp.eye(3)
        for axis, angle in self.rotations:
            matrix = matrix * elementary_rotation(axis, angle)
        return sp.ImmutableMatrix(matrix)


def elementary_rotation(axis: str, angle: sp.Expr) -> sp.Matrix:
    """Active rotation by `angle` about the x, y or z axis."""
    c, s = sp.cos(angle), sp.sin(angle)
    if axis == "x":
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return sp.Matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


@dataclass(frozen=True)
class AppliedForce:
    """A force acting at `point` and/or a torque acting on `body`."""

    point: sp.ImmutableMatrix | None  # 3 x 1 inertial position where the force acts
    force: sp.ImmutableMatrix | None  # 3 x 1, inertial components
    body: str | None                  # body the torque acts on
    torque: sp.ImmutableMatrix | None # 3 x 1, inertial components (planar: (0, 0, tau))
    loc: Loc | None = None


@dataclass(frozen=True)
class LinearSpring:
    """A linear spring between two points."""

    end_a: sp.ImmutableMatrix         # 3 x 1 positions of the two ends
    end_b: sp.ImmutableMatrix
    stiffness: sp.Expr
    rest_length: sp.Expr
    loc: Loc | None = None


@dataclass(frozen=True)
class LinearDamper:
    """A linear dashpot between two points."""

    end_a: sp.ImmutableMatrix         # 3 x 1 positions of the two ends
    end_b: sp.ImmutableMatrix
    damping: sp.Expr                  # c: force = c x (rate of change of the length)
    loc: Loc | None = None


@dataclass(frozen=True)
class RollingContact:
    """What pictures need of a `rolling:` element: the body, the wheel's radius and axis
    (None for a `contact:` offset) and the plane n . X = height it rolls on (n a unit vector)."""

    body: str
    radius: sp.Expr | None
    axis: str | None
    normal: sp.ImmutableMatrix
    height: sp.Expr


@dataclass(frozen=True)
class ConstraintSpec:
    """A constraint `expr` = 0 (holonomic; nonholonomic when linear in the velocities)."""

    label: str | None
    expr: sp.Expr
    loc: Loc | None = None


@dataclass(frozen=True)
class InputLaw:
    """`simulate: inputs:`: the input `symbol` follows `expr` (t, q, q', parameters)."""

    symbol: sp.Symbol
    expr: sp.Expr
    loc: Loc | None = None


@dataclass(frozen=True)
class EventSpec:
    """An item of `events:`: `action` where g = `when` crosses zero in `direction`."""

    name: str
    when: sp.Expr                      # g(t, q, q'); an impact's: g(t, q)
    direction: str                     # "falling" | "rising" | "either"
    action: str                        # "impact" | "reset" | "stop"
    restitution: sp.Expr | None        # impact: parameters only
    reset: tuple[tuple[str, sp.Expr], ...] = ()   # state name -> new value (of the state before)
    loc: Loc | None = None
    rest: bool = False                 # impact: hold the contact g = 0 after an accumulation


@dataclass(frozen=True)
class Model:
    """The whole model: symbols, bodies, forces and energies of one spec (module docstring)."""

    name: str
    description: str
    source: str                       # spec file path as given
    dimension: int
    t: sp.Symbol
    q: tuple[sp.Symbol, ...]
    qd: tuple[sp.Symbol, ...]
    qdd: tuple[sp.Symbol, ...]
    coordinate_latex: dict            # q symbol -> LaTeX (user's or a default)
    parameters: tuple[ParameterInfo, ...]
    known: tuple[tuple[str, sp.Expr], ...]        # name -> expression of t (already substituted)
    definitions: tuple[tuple[str, sp.Expr], ...]  # name -> expression (already substituted)
    particles: tuple[PointMass, ...]
    bodies: tuple[RigidBody, ...]
    gravity: sp.ImmutableMatrix | None
    forces: tuple[AppliedForce, ...]
    springs: tuple[LinearSpring, ...]
    potential: sp.Expr
    kinetic: sp.Expr
    generalized_forces: tuple[sp.Expr, ...]      # Q'_j given directly, one per coordinate (0 if absent)
    constraints: tuple[ConstraintSpec, ...]
    initial: dict = field(default_factory=dict)  # name ("theta", "theta_dot") -> float
    settings: Settings = field(default_factory=Settings)
    dampers: tuple[LinearDamper, ...] = ()
    dissipation: sp.Expr = sp.S.Zero             # Rayleigh R(q, q', t) as written (dampers not included)
    units: dict = field(default_factory=dict)    # name -> (unit text, Loc) of parameters, inputs and coordinates
    locs: dict = field(default_factory=dict)     # key path ("coordinates[1]", "potential") -> Loc, for messages

    def loc(self, path: str) -> Loc:
        """Where the spec item at key `path` was written (its path alone when unknown)."""
        return self.locs.get(path) or Loc(self.source, path=path)
    inputs: tuple[InputInfo, ...] = ()
    laws: tuple[InputLaw, ...] = ()              # spec `simulate: inputs:`
    events: tuple[EventSpec, ...] = ()           # spec `events:`
    rolling: tuple[RollingContact, ...] = ()     # the `rolling:` elements, for pictures

    def symbol(self, name: str) -> sp.Symbol:
        """The symbol called `name`: t, a coordinate, velocity, acceleration or parameter."""
        for s in (self.t, *self.q, *self.qd, *self.qdd, *self.parameter_symbols, *self.input_symbols):
            if s.name == name:
                return s
        raise KeyError(name)

    @property
    def mass_points(self) -> list[tuple[sp.Expr, sp.ImmutableMatrix]]:
        """(mass, position) of every particle and every body's centre of mass."""
        return [(p.mass, p.position) for p in self.particles] + [(b.mass, b.position) for b in self.bodies]

    @property
    def parameter_symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(p.symbol for p in self.parameters)

    @property
    def input_symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(u.symbol for u in self.inputs)

    @property
    def parameter_values(self) -> dict:
        return {p.symbol: p.value for p in self.parameters}
