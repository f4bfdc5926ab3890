"""Check a `RawDoc` against the spec format (docs/spec.md) and build a `Spec`.

Every problem is collected, with its location, and reported in one `SpecError`.
Expressions are not parsed here: they travel as `Src` (text + location) to the
model stage, which parses them safely. Key sets, value shapes, names,
references, the spec's single dimension (2-D or 3-D) and the safe LaTeX subset
of `latex:` strings (latex_subset.py) are checked here.
"""
from __future__ import annotations

import dataclasses
import re
from pathlib import Path
from typing import Any, Callable

from lagcli.errors import SpecError
from lagcli.interface import METHODS
from lagcli.spec.checker import IDENTIFIER, Checker, describe, did_you_mean
from lagcli.spec.frames import FrameChecks
from lagcli.spec.latex_subset import HINT as LATEX_HINT
from lagcli.spec.latex_subset import latex_problem
from lagcli.spec.files import STDIN_NAME
from lagcli.spec.reader import KeyPath, RawDoc
from lagcli.spec.dampers import dissipation_fields
from lagcli.spec import format as fmt
from lagcli.spec.events import events_field, input_laws
from lagcli.spec.slips import axis_hint, misplaced_toml_keys, misplaced_toml_pairs
from lagcli.spec.types import (Body, Constraint, Coordinate, Force, Input, Named, Parameter, Particle,
                               SimulateSettings, Spec, Spring, Src, Vector, VectorSrc)

AXES = fmt.AXES
SPATIAL_INERTIA = "[I1, I2, I3], 6 values [Ixx, Iyy, Izz, Ixy, Iyz, Izx] or a 3x3 list"


def validate(raw: RawDoc) -> Spec:
    """Build the `Spec` for `raw`, or raise `SpecError` listing every problem found."""
    spec, problems = check(raw)
    if problems:
        raise SpecError(problems)
    return spec


def check(raw: RawDoc) -> tuple[Spec, list]:
    """The best-effort `Spec` for `raw` and the problems found (the spec is only
    trustworthy when there are none; later stages may still scan it for more problems)."""
    checker = _SpecChecker(_without(raw, misplaced_toml_pairs(raw, fmt.TOP.allowed)))
    spec = checker.spec()
    return spec, checker.problems + misplaced_toml_keys(raw, fmt.TOP.allowed)


def _without(raw: RawDoc, misplaced: list[tuple[str, str]]) -> RawDoc:
    """`raw` without the TOML keys that ended up in the table above them: checked as what
    they were meant to be, `kinetic = ...` below `[parameters]` would be a parameter whose
    value uses unknown names, a false second error after the true one."""
    if not misplaced:
        return raw
    data = {table: ({key: item for key, item in value.items()
                     if (table, key) not in misplaced}
                    if isinstance(value, dict) else value) for table, value in raw.data.items()}
    return dataclasses.replace(raw, data=data)


def default_name(file: str) -> str:
    """The file stem made into an identifier: `double-pendulum.yaml` -> `double_pendulum`
    (`<stdin>` -> `stdin`)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", "stdin" if file == STDIN_NAME else Path(file).stem)
    return name if IDENTIFIER.fullmatch(name) else f"_{name}"


class _SpecChecker(FrameChecks, Checker):
    """The spec format, section by section; names are declared before they are referenced."""

    def __init__(self, raw: RawDoc):
        super().__init__(raw)
        self.constraint_names: set[str | None] = set()

    def spec(self) -> Spec:
        top = self.table((), self.raw.data, fmt.TOP) or {}
        fields = dict(  # in this order: declarations first, then the sections that use them
            coordinates=self.coordinates(top.get("coordinates")),
            parameters=self.mapping_items(top, "parameters", self.parameter),
            inputs=self.inputs(top.get("inputs")),
            known=self.mapping_items(top, "known", self.named("known function")),
            frames=self.frames(top),
            definitions=self.mapping_items(top, "definitions", self.named("definition")),
            particles=self.mapping_items(top, "particles", self.particle),
            bodies=self.mapping_items(top, "bodies", self.body),
            gravity=self.vector(("gravity",), top["gravity"]) if "gravity" in top else None,
            forces=self.list_items(top, "forces", self.force),
            springs=self.list_items(top, "springs", self.spring),
            potential=self.expr(("potential",), top["potential"]) if "potential" in top else None,
            kinetic=self.expr(("kinetic",), top["kinetic"]) if "kinetic" in top else None,
            generalized_forces=self.mapping_items(top, "generalized_forces",
                                                  self.keyed_by(self.coordinate_names, "coordinate")),
            constraints=self.list_items(top, "constraints", self.constraint),
            rolling=self.list_items(top, "rolling", self.rolling),
            initial=self.mapping_items(top, "initial",
                                       self.keyed_by(self.state_names(), "coordinate or velocity")),
            simulate=self.simulate(top.get("simulate")),
            **dissipation_fields(self, top),
            events=events_field(self, top),
            name=self.identifier(("name",), top["name"]) if "name" in top else None,
            description=self.optional_string(top, (), "description") or "",
        )
        self.check_rolling_names(fields["rolling"])
        self.check_references()
        fields["name"] = fields["name"] or default_name(self.raw.file)
        return Spec(file=self.raw.file, dimension=self.dimension(), **fields)

    # --- declarations --------------------------------------------------------------------

    def coordinates(self, value: Any) -> tuple[Coordinate, ...]:
        """Parse the whole list first, so `<q>_dot` names are known when declaring."""
        path: KeyPath = ("coordinates",)
        if not isinstance(value, list) or not value:
            if value is not None or path in self.raw.texts:  # given, even if empty (`coordinates:`)
                self.fail(path, f"expected a non-empty list of coordinate names; got {describe(value)}")
            return ()
        entries = [(i, self.coordinate(path + (i,), item)) for i, item in enumerate(value)]
        entries = [(i, c) for i, c in entries if c is not None]
        self.coordinate_names = {c.name for _, c in entries}
        for i, coordinate in entries:
            self.declare(coordinate.name, "coordinate", path + (i,), at_key=False)
        return tuple(c for _, c in entries)

    def coordinate(self, path: KeyPath, item: Any) -> Coordinate | None:
        if isinstance(item, str):
            return Coordinate(item, None, self.raw.loc(path))
        if not isinstance(item, dict):
            self.fail(path, f"expected a coordinate name or {{name, latex}}; got {describe(item)}")
            return None
        table = self.table(path, item, fmt.COORDINATE)
        name = self.string(path + ("name",), table["name"], "a name") if "name" in table else None
        latex = self.latex_symbol(table, path)
        unit = self.optional_string(table, path, "unit")
        return Coordinate(name, latex, self.raw.loc(path), unit) if name is not None else None

    def parameter(self, name: str, path: KeyPath, value: Any) -> Parameter | None:
        self.declare(name, "parameter", path)
        if not isinstance(value, dict):
            src = self.expr(path, value)
            return Parameter(name, src, None, None, self.raw.loc(path, at_key=True)) if src else None
        table = self.table(path, value, fmt.PARAMETER)
        src = self.expr(path + ("value",), table["value"]) if "value" in table else None
        latex = self.latex_symbol(table, path)
        description = self.optional_string(table, path, "description")
        unit = self.optional_string(table, path, "unit")
        return Parameter(name, src, latex, description, self.raw.loc(path, at_key=True), unit) if src else None

    def inputs(self, value: Any) -> tuple[Input, ...]:
        """`inputs:` is a list of names (`[F, tau]`, defaults 0) or a mapping like
        `parameters:` (`{tau: 0.5}` or `{tau: {value: 0.5, latex: ..., description: ...}}`)."""
        if value is not None and not isinstance(value, (list, dict)):
            self.fail(("inputs",), f"expected a list of names or a mapping name: default; got {describe(value)}",
                      "e.g. inputs: [F, tau] or inputs: {tau: 0.5}")
            return ()
        if not isinstance(value, list):
            return self.mapping_items({"inputs": value}, "inputs", self.input)
        names = [(("inputs", i), self.identifier(("inputs", i), item)) for i, item in enumerate(value)]
        return tuple(item for path, name in names if name is not None
                     for item in [self.input(name, path, None, at_key=False)] if item is not None)

    def input(self, name: str, path: KeyPath, value: Any, at_key: bool = True) -> Input | None:
        self.declare(name, "input", path, at_key)
        loc = self.raw.loc(path, at_key=at_key)
        if not isinstance(value, dict):
            src = self.expr(path, value) if value is not None else None
            return Input(name, src, None, None, loc) if src or value is None else None
        table = self.table(path, value, fmt.INPUT)
        src = self.expr(path + ("value",), table["value"]) if "value" in table else None
        return Input(name, src, self.latex_symbol(table, path),
                     self.optional_string(table, path, "description"), loc,
                     self.optional_string(table, path, "unit"))

    def latex_symbol(self, table: dict, path: KeyPath) -> str | None:
        """The item's `latex:`, when it is in the safe subset of lagcli/spec/latex_subset.py."""
        latex = self.optional_string(table, path, "latex")
        problem = latex_problem(latex) if latex is not None else None
        if problem:
            self.fail(path + ("latex",), problem, LATEX_HINT)
            return None
        return latex

    def named(self, kind: str) -> Callable[[str, KeyPath, Any], Named | None]:
        """Builder for `name: expression` sections that declare `name` (known, definitions)."""
        def build(name: str, path: KeyPath, value: Any) -> Named | None:
            self.declare(name, kind, path)
            src = self.expr(path, value)
            return Named(name, src, self.raw.loc(path, at_key=True)) if src else None
        return build

    def particle(self, name: str, path: KeyPath, value: Any) -> Particle | None:
        self.declare(name, "particle", path)
        table = self.table(path, value, fmt.PARTICLE)
        if table is None:
            return None
        mass = self.expr(path + ("mass",), table["mass"]) if "mass" in table else None
        position = self.vector(path + ("position",), table["position"]) if "position" in table else None
        if mass is None or position is None:
            return None
        return Particle(name, mass, position, self.raw.loc(path, at_key=True))

    def body(self, name: str, path: KeyPath, value: Any) -> Body | None:
        self.declare(name, "body", path)
        table = self.table(path, value, fmt.BODY)
        if table is None:
            return None
        spatial = self.body_is_spatial(path, table)
        mass = self.expr(path + ("mass",), table["mass"]) if "mass" in table else None
        position = self.vector(path + ("position",), table["position"]) if "position" in table else None
        inertia = self.inertia(path + ("inertia",), table["inertia"], spatial) if "inertia" in table else None
        angle = self.expr(path + ("angle",), table["angle"]) if "angle" in table and not spatial else None
        orientation = (self.orientation(path + ("orientation",), table["orientation"])
                       if "orientation" in table and spatial else ())
        frame = self.body_frame(path, table)
        if None in (mass, position, inertia, orientation) or (angle is None and not spatial):
            return None
        return Body(name, mass, inertia, position, angle, orientation, self.raw.loc(path, at_key=True), frame)

    def body_is_spatial(self, path: KeyPath, table: dict) -> bool:
        """`angle` means planar, `orientation` (or `frame`) spatial; with neither, the inertia's shape says."""
        if "frame" in table:
            return self.frame_body(path, table)
        both = "angle" in table and "orientation" in table
        if both:
            self.fail(path, "a body has 'angle' (planar) or 'orientation' (spatial), not both")
        undecided = both or set(table).isdisjoint(("angle", "orientation"))
        spatial = isinstance(table.get("inertia"), list) if undecided else "orientation" in table
        key = "orientation" if spatial else "angle"
        if key not in table:
            hint = ("a spatial body needs orientation: [[axis, angle], ...] (possibly [])" if spatial
                    else "a planar body needs its rotation angle (a body that does not turn is a particle)")
            self.fail(path, f"missing required key '{key}'", hint)
        self.note_dim(3 if spatial else 2, path + (key,) if key in table else path)
        return spatial

    def inertia(self, path: KeyPath, value: Any, spatial: bool) -> tuple[Src, ...] | None:
        if not spatial:
            if isinstance(value, list):
                self.fail(path, f"a planar body's inertia is one expression; got {describe(value)}")
                return None
            src = self.expr(path, value)
            return (src,) if src else None
        if isinstance(value, list) and len(value) == 3 and all(isinstance(row, list) for row in value):
            if all(len(row) == 3 for row in value):
                items = [self.expr(path + (i, j), value[i][j]) for i in range(3) for j in range(3)]
                return None if None in items else tuple(items)
        elif isinstance(value, list) and len(value) in (3, 6):
            items = [self.expr(path + (i,), v) for i, v in enumerate(value)]
            return None if None in items else tuple(items)
        self.fail(path, f"a spatial body's inertia is {SPATIAL_INERTIA}; got {describe(value)}")
        return None

    def orientation(self, path: KeyPath, value: Any) -> tuple[tuple[str, Src], ...] | None:
        if not isinstance(value, list):
            self.fail(path, f"expected a list of [axis, angle] rotations; got {describe(value)}")
            return None
        rotations = []
        for i, item in enumerate(value):
            if not (isinstance(item, list) and len(item) == 2 and item[0] in AXES):
                self.fail(path + (i,), "a rotation is [axis, angle] with axis x, y or z; "
                          f"got {describe(item)}", axis_hint(item[0] if isinstance(item, list) and item else None))
                continue
            angle = self.expr(path + (i, 1), item[1])
            if angle is not None:
                rotations.append((item[0], angle))
        return tuple(rotations) if len(rotations) == len(value) else None

    # --- sections that use the names ----------------------------------------------------

    def force(self, path: KeyPath, value: Any) -> Force | None:
        table = self.table(path, value, fmt.FORCE)
        if table is None:
            return None
        places = [key for key in ("at", "point", "body") if key in table]
        if len(places) != 1:
            found = " and ".join(f"'{p}'" for p in places) if places else "none"
            self.fail(path, f"give exactly one of 'at', 'point' or 'body' (found {found})")
        if "force" not in table and "torque" not in table:
            self.fail(path, "give a 'force', a 'torque' or both")
        if "body" in table and "force" in table:
            self.fail(path + ("force",), "'body:' takes a torque only",
                      "to apply a force at the body's centre of mass use 'at: <body>'")
        if "point" in table and "torque" in table:
            self.fail(path + ("torque",), "a torque acts on a body, not at a point",
                      "use 'body: <body>' (or 'at: <body>')")
        torque_kinds = ("body",) if "torque" in table else ("particle", "body")
        at = self.reference(path + ("at",), table["at"], torque_kinds) if "at" in table else None
        body = self.reference(path + ("body",), table["body"], ("body",)) if "body" in table else None
        point = self.vector(path + ("point",), table["point"]) if "point" in table else None
        force = self.vector(path + ("force",), table["force"]) if "force" in table else None
        torque = self.torque(path + ("torque",), table["torque"]) if "torque" in table else None
        return Force(at, point, body, force, torque, self.raw.loc(path))

    def torque(self, path: KeyPath, value: Any) -> tuple[Src, ...] | None:
        """A scalar (planar, about z) or a 3-vector (spatial, inertial axes)."""
        if self.torque_is_vector(value):
            return self.vector(path, value)
        if isinstance(value, list):
            if len(value) != 3:
                self.fail(path, f"a torque is one expression (planar) or [Tx, Ty, Tz] (spatial); "
                          f"got {describe(value)}")
                return None
            return self.vector(path, value)
        src = self.expr(path, value)
        if src is not None:
            self.note_dim(2, path)
        return (src,) if src else None

    def spring(self, path: KeyPath, value: Any) -> Spring | None:
        table = self.table(path, value, fmt.SPRING)
        if table is None:
            return None
        ends = self.spring_ends(path + ("between",), table["between"]) if "between" in table else None
        stiffness = self.expr(path + ("stiffness",), table["stiffness"]) if "stiffness" in table else None
        rest = (self.expr(path + ("rest_length",), table["rest_length"]) if "rest_length" in table
                else Src("0", self.raw.loc(path)))
        if ends is None or stiffness is None or rest is None:
            return None
        return Spring(ends, stiffness, rest, self.raw.loc(path))

    def spring_ends(self, path: KeyPath, value: Any) -> tuple[str | Vector, str | Vector] | None:
        if not isinstance(value, list) or len(value) != 2:
            self.fail(path, f"expected [end, end] (a particle, body or fixed point [x, y(, z)] each); "
                      f"got {describe(value)}")
            return None
        ends = [self.reference(path + (i,), end, ("particle", "body")) if self.names_a_point(end)
                else self.vector(path + (i,), end) for i, end in enumerate(value)]
        return None if None in ends else (ends[0], ends[1])

    def names_a_point(self, end: Any) -> bool:
        """A spring end written as a name is a particle or body, unless it names a
        definition (a vector expression, like any other string that is not a name)."""
        return isinstance(end, str) and IDENTIFIER.fullmatch(end) is not None and \
            self.names.get(end, ("",))[0] != "definition"

    def constraint(self, path: KeyPath, value: Any) -> Constraint | None:
        if not isinstance(value, dict):
            src = self.expr(path, value)
            return Constraint(None, src, self.raw.loc(path)) if src else None
        table = self.table(path, value, fmt.CONSTRAINT)
        name = self.identifier(path + ("name",), table["name"]) if "name" in table else None
        if name is not None and name in self.constraint_names:
            self.fail(path + ("name",), f"duplicate constraint name '{name}' (multiplier lambda_{name})")
        self.constraint_names.add(name)
        src = self.expr(path + ("expr",), table["expr"]) if "expr" in table else None
        return Constraint(name, src, self.raw.loc(path)) if src else None

    def keyed_by(self, allowed: set[str], what: str) -> Callable[[str, KeyPath, Any], Named | None]:
        """Builder for `name: expression` sections whose keys must be in `allowed`."""
        def build(name: str, path: KeyPath, value: Any) -> Named | None:
            if name not in allowed:
                choices = sorted(allowed)
                hint = did_you_mean(name, choices) or f"allowed here: {', '.join(choices)}"
                self.fail(path, f"'{name}' is not a {what}", hint, at_key=True)
            src = self.expr(path, value)
            return Named(name, src, self.raw.loc(path, at_key=True)) if src else None
        return build

    def state_names(self) -> set[str]:
        return self.coordinate_names | {f"{q}_dot" for q in self.coordinate_names}

    def simulate(self, value: Any) -> SimulateSettings:
        path: KeyPath = ("simulate",)
        table = self.table(path, value, fmt.SIMULATE) if value is not None else None
        if not table:
            return SimulateSettings()
        numbers = {key: self.expr(path + (key,), table[key]) for key in fmt.SIMULATE.allowed
                   if key in table and key not in ("method", "inputs")}
        method = self.method(path + ("method",), table["method"]) if "method" in table else None
        laws = input_laws(self, path + ("inputs",), table["inputs"]) if "inputs" in table else ()
        return SimulateSettings(method=method, inputs=laws, **numbers)

    def method(self, path: KeyPath, value: Any) -> str | None:
        if value in METHODS:
            return value
        by_case = {m.lower(): m for m in METHODS}
        guess = by_case.get(str(value).lower())
        hint = f"did you mean '{guess}'?" if guess else "methods are: " + ", ".join(METHODS)
        self.fail(path, f"unknown integration method {value!r}", hint)
        return None

