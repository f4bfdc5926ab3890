"""The spec format as data: every mapping a spec may hold, its keys and the shape of each value.

One source for two readers. The checker (schema.py and its helpers frames.py,
dissipation.py, ...) takes each mapping's allowed and required keys from a `Table`
here (`Checker.table(path, value, TABLE)`), and `lagcli schema` turns the same tables
into a JSON Schema (json_schema.py), so the two cannot disagree on which keys exist,
which are required, or what shape a value has. A new key is added here, once.

A value's shape is a small JSON Schema fragment (`EXPRESSION`, `VECTOR`, a `Table`, ...).
What a JSON Schema cannot see stays in the checker alone: what an expression means
(its names, its syntax), references between items, reserved names, the spec's single
dimension and rules that join two keys ("exactly one of at, point, body").
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Union

from lagcli.interface import METHODS

Shape = Union["Table", dict]


@dataclass(frozen=True)
class Table:
    """A mapping with these keys (in the order messages list them) and shapes."""

    name: str                                   # its name in the JSON Schema's $defs
    description: str
    keys: dict[str, Shape] = field(hash=False)
    required: tuple[str, ...] = ()

    @property
    def allowed(self) -> tuple[str, ...]:
        return tuple(self.keys)


def ref(name: str) -> dict:
    return {"$ref": f"#/$defs/{name}"}


def one_of(*shapes: Shape) -> dict:
    return {"anyOf": list(shapes)}


def nullable(shape: Shape) -> dict:
    """A section that may be written empty (`parameters:` with nothing after it)."""
    return one_of({"type": "null"}, shape)


def list_of(shape: Shape, least: int = 0, most: int | None = None) -> dict:
    out: dict[str, Any] = {"type": "array", "items": shape}
    if least:
        out["minItems"] = least
    if most is not None:
        out["maxItems"] = most
    return out


def mapping_of(shape: Shape, names: bool = True) -> dict:
    """`name: value` entries; `names`: the keys declare names (a letter or '_' first)."""
    out: dict[str, Any] = {"type": "object", "additionalProperties": shape}
    if names:
        out["propertyNames"] = ref("name")
    return out


AXES = ("x", "y", "z")
NAME = ref("name")
EXPRESSION = ref("expression")
VECTOR = ref("vector")
STRING = {"type": "string"}
BOOLEAN = {"type": "boolean"}

# The shapes every table uses, by name ($defs of the JSON Schema).
SHAPES: dict[str, dict] = {
    "name": {"type": "string", "pattern": "^[A-Za-z_][A-Za-z0-9_]*$",
             "description": "a letter or '_' followed by letters, digits or '_'"},
    "expression": {"anyOf": [{"type": "number"}, {"type": "string", "pattern": "\\S"}],
                   "description": "a number, or an expression of the spec language as a string"},
    "vector": {"anyOf": [{"type": "string", "pattern": "\\S"}, list_of(EXPRESSION, 2, 3)],
               "description": "[x, y] (planar) or [x, y, z] (spatial), or one vector expression"},
    "rotations": {"type": "array", "description": "successive body-fixed rotations [axis, angle]",
                  "items": {"type": "array", "prefixItems": [{"enum": list(AXES)}, EXPRESSION],
                            "minItems": 2, "maxItems": 2}},
}
ROTATIONS = ref("rotations")
INERTIA = one_of(EXPRESSION, list_of(EXPRESSION, 3, 3), list_of(EXPRESSION, 6, 6),
                 list_of(list_of(EXPRESSION, 3, 3), 3, 3))
TORQUE = one_of(EXPRESSION, list_of(EXPRESSION, 3, 3))
ENDS = list_of(VECTOR, 2, 2)     # a particle or body name, or a fixed point

COORDINATE = Table("coordinate", "a coordinate with its LaTeX symbol or unit",
                   {"name": NAME, "latex": STRING, "unit": STRING}, ("name",))
PARAMETER = Table("parameter", "a parameter's default value with its symbol, description or unit",
                  {"value": EXPRESSION, "latex": STRING, "description": STRING, "unit": STRING}, ("value",))
INPUT = Table("input", "an input's default value with its symbol, description or unit",
              {"value": EXPRESSION, "latex": STRING, "description": STRING, "unit": STRING})
PARTICLE = Table("particle", "a point mass", {"mass": EXPRESSION, "position": VECTOR}, ("mass", "position"))
BODY = Table("body", "a rigid body: planar with angle, spatial with orientation or frame",
             {"mass": EXPRESSION, "inertia": INERTIA, "position": VECTOR, "angle": EXPRESSION,
              "orientation": ROTATIONS, "frame": STRING}, ("mass", "inertia", "position"))
FORCE = Table("force", "a force at a particle, body or point, or a torque on a body",
              {"at": STRING, "point": VECTOR, "body": STRING, "force": VECTOR, "torque": TORQUE})
SPRING = Table("spring", "a linear spring between two particles, bodies or fixed points",
               {"between": ENDS, "stiffness": EXPRESSION, "rest_length": EXPRESSION}, ("between", "stiffness"))
DAMPER = Table("damper", "a linear dashpot between two particles, bodies or fixed points",
               {"between": ENDS, "damping": EXPRESSION}, ("between", "damping"))
CONSTRAINT = Table("constraint", "a constraint expression with a name for its multiplier",
                   {"name": NAME, "expr": EXPRESSION}, ("expr",))
SIMULATE = Table("simulate", "the default run settings, and a law per input",
                 {"t_end": EXPRESSION, "dt": EXPRESSION, "method": {"enum": list(METHODS)},
                  "rtol": EXPRESSION, "atol": EXPRESSION, "inputs": mapping_of(EXPRESSION)})
DIRECTIONS = ("falling", "rising", "either")     # of an event's g through zero; the first is the default
ACTIONS = ("impact", "reset", "stop")
EVENT = Table("event", "what happens where g = `when` crosses zero: an impact, a reset or a stop",
              {"name": NAME, "when": EXPRESSION, "direction": {"enum": list(DIRECTIONS)},
               "action": {"enum": list(ACTIONS)}, "restitution": EXPRESSION,
               "reset": mapping_of(EXPRESSION, names=False), "rest": BOOLEAN}, ("when", "action"))
FRAME = Table("frame", "a frame: rotations from its parent (default: the inertial frame)",
              {"parent": STRING, "rotations": ROTATIONS}, ("rotations",))
WHEEL = Table("wheel", "a disc rolling on its rim", {"radius": EXPRESSION, "axis": {"enum": list(AXES)}},
              ("radius", "axis"))
SURFACE = Table("surface", "the surface rolled on",
                {"normal": VECTOR, "height": EXPRESSION, "angular_velocity": EXPRESSION, "centre": VECTOR},
                ("normal",))
ROLLING = Table("rolling", "a body rolling without slipping",
                {"body": STRING, "wheel": WHEEL, "contact": VECTOR, "surface": SURFACE}, ("body",))

TOP = Table("spec", "a lagcli spec: a mechanical system for Lagrange's method (docs/spec.md)", {
    "name": NAME,
    "description": STRING,
    "coordinates": list_of(one_of(NAME, COORDINATE), 1),
    "parameters": nullable(mapping_of(one_of(EXPRESSION, PARAMETER))),
    "inputs": nullable(one_of(list_of(NAME), mapping_of(one_of({"type": "null"}, EXPRESSION, INPUT)))),
    "known": nullable(mapping_of(EXPRESSION)),
    "definitions": nullable(mapping_of(EXPRESSION)),
    "gravity": VECTOR,
    "particles": nullable(mapping_of(PARTICLE)),
    "bodies": nullable(mapping_of(BODY)),
    "forces": nullable(list_of(FORCE)),
    "springs": nullable(list_of(SPRING)),
    "potential": EXPRESSION,
    "kinetic": EXPRESSION,
    "generalized_forces": nullable(mapping_of(EXPRESSION, names=False)),
    "constraints": nullable(list_of(one_of(EXPRESSION, CONSTRAINT))),
    "initial": nullable(mapping_of(EXPRESSION, names=False)),
    "simulate": nullable(SIMULATE),
    "frames": nullable(mapping_of(FRAME)),
    "rolling": nullable(list_of(ROLLING)),
    "dampers": nullable(list_of(DAMPER)),
    "dissipation": EXPRESSION,
    "events": nullable(list_of(EVENT)),
}, ("coordinates",))
