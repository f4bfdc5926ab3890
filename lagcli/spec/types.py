"""The validated spec: plain strings and numbers, each item with its `Loc`.

`Src` is the source text of one expression (never evaluated here: `lagcli/model/build.py`
parses it with the safe expression parser). Numbers written in the file arrive as
their `repr` text, so every expression field is a `Src`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from lagcli.errors import Loc


@dataclass(frozen=True)
class Src:
    """An expression as written in the spec, and where."""

    text: str
    loc: Loc


@dataclass(frozen=True)
class VectorSrc(Src):
    """A vector written as one expression, e.g. `r*A_z + [x, y, 0]` (3-D; lagcli/model/vectors.py)."""


Vector = tuple[Src, ...]  # 2 or 3 components (one dimension per spec), or one VectorSrc


@dataclass(frozen=True)
class Coordinate:
    """A generalized coordinate q: its name, LaTeX and unit."""

    name: str
    latex: str | None
    loc: Loc
    unit: str | None = None    # a unit expression (lagcli/model/units.py); None: dimensionless


@dataclass(frozen=True)
class Parameter:
    """A named constant of the system and its value."""

    name: str
    value: Src  # a constant expression (numbers, pi, other parameters are NOT allowed)
    latex: str | None
    description: str | None
    loc: Loc
    unit: str | None = None    # a unit expression (lagcli/model/units.py); None: dimensionless


@dataclass(frozen=True)
class Input:
    """An input signal u_k: a name usable in forces, torques and generalized forces,
    held at `value` (its default, 0 when not given) unless a run sets it."""

    name: str
    value: Src | None
    latex: str | None
    description: str | None
    loc: Loc
    unit: str | None = None    # a unit expression (lagcli/units.py); None: dimensionless


@dataclass(frozen=True)
class Named:
    """`name: expression` items: known functions, definitions, generalized forces, initial values."""

    name: str
    expr: Src
    loc: Loc


@dataclass(frozen=True)
class Particle:
    """A point mass at `position`."""

    name: str
    mass: Src
    position: Vector
    loc: Loc


@dataclass(frozen=True)
class Body:
    """A rigid body; position is its centre of mass.

    Planar (dimension 2): `inertia` has one entry (about the CM) and `angle` is set.
    Spatial (dimension 3): `inertia` has 3 (principal), 6 (Ixx,Iyy,Izz,Ixy,Iyz,Izx) or
    9 (row-major 3x3) entries in body axes, and `orientation` lists successive
    body-fixed rotations (axis letter, angle).
    """

    name: str
    mass: Src
    inertia: tuple[Src, ...]
    position: Vector
    angle: Src | None
    orientation: tuple[tuple[str, Src], ...]
    loc: Loc
    frame: str | None = None  # a frame of `frames:` instead of `orientation`


@dataclass(frozen=True)
class Force:
    """An applied force and/or torque. Exactly one of `at` (particle or body name),
    `point` (inertial position), `body` (for a torque) says where it acts."""

    at: str | None
    point: Vector | None
    body: str | None
    force: Vector | None
    torque: tuple[Src, ...] | None  # 1 entry (planar) or 3 (spatial, inertial axes)
    loc: Loc


@dataclass(frozen=True)
class Spring:
    """A linear spring; each end is a particle/body name or a fixed point."""

    ends: tuple[str | Vector, str | Vector]
    stiffness: Src
    rest_length: Src
    loc: Loc


@dataclass(frozen=True)
class Damper:
    """A linear dashpot; each end is a particle/body name or a fixed point (see Spring)."""

    ends: tuple[str | Vector, str | Vector]
    damping: Src
    loc: Loc


@dataclass(frozen=True)
class Constraint:
    """An item of `constraints:`: `expr` = 0 (holonomic; nonholonomic when linear in the velocities)."""

    name: str | None
    expr: Src
    loc: Loc


@dataclass(frozen=True)
class Frame:
    """A named frame: successive body-fixed rotations from `parent` (None: inertial)."""

    name: str
    parent: str | None
    rotations: tuple[tuple[str, Src], ...]
    loc: Loc


@dataclass(frozen=True)
class Surface:
    """The plane n.X = height, turning at `angular_velocity` about n through `centre`."""

    normal: Vector
    height: Src | None = None
    angular_velocity: Src | None = None
    centre: Vector | None = None


@dataclass(frozen=True)
class Rolling:
    """A body rolling without slipping on a surface: its contact point is the wheel's
    (`wheel` = (radius, axis letter)) or the offset `contact` from its centre of mass."""

    body: str
    wheel: tuple[Src, str] | None
    contact: Vector | None
    surface: Surface | None
    loc: Loc


@dataclass(frozen=True)
class SimulateSettings:
    """The spec's `simulate:` (None: not given, the run interface's default applies)."""

    t_end: Src | None = None
    dt: Src | None = None
    method: str | None = None
    rtol: Src | None = None
    atol: Src | None = None
    inputs: tuple[Named, ...] = ()           # input laws: input name -> expression of t, q, q'


@dataclass(frozen=True)
class Event:
    """An item of `events:` (docs/spec.md, "events"): where `when` crosses zero in
    `direction`, `action` happens (impact with `restitution`, reset of states, stop)."""

    name: str
    when: Src
    direction: str                           # "falling" | "rising" | "either"
    action: str                              # "impact" | "reset" | "stop"
    restitution: Src | None                  # impact only
    reset: tuple[Named, ...]                 # reset only: state name -> new value
    loc: Loc
    rest: bool = False                       # impact only: hold the contact after an accumulation


@dataclass(frozen=True)
class Spec:
    """A whole validated spec (docs/spec.md)."""

    file: str
    name: str
    description: str
    dimension: int  # 2 or 3
    coordinates: tuple[Coordinate, ...]
    parameters: tuple[Parameter, ...] = ()
    inputs: tuple[Input, ...] = ()
    known: tuple[Named, ...] = ()
    definitions: tuple[Named, ...] = ()
    gravity: Vector | None = None
    particles: tuple[Particle, ...] = ()
    bodies: tuple[Body, ...] = ()
    forces: tuple[Force, ...] = ()
    springs: tuple[Spring, ...] = ()
    potential: Src | None = None
    kinetic: Src | None = None
    generalized_forces: tuple[Named, ...] = ()
    constraints: tuple[Constraint, ...] = ()
    initial: tuple[Named, ...] = ()
    simulate: SimulateSettings = field(default_factory=SimulateSettings)
    frames: tuple[Frame, ...] = ()
    rolling: tuple[Rolling, ...] = ()
    dampers: tuple[Damper, ...] = ()
    dissipation: Src | None = None           # a Rayleigh dissipation function R(q, q', t)
    events: tuple[Event, ...] = ()
