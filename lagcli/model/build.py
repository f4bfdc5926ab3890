"""Spec -> Model: every expression parsed (safely) into sympy, vectors made 3-D.

Name resolution follows the spec's order: parameters and coordinates first,
then `known` functions of t (each may use earlier ones), then `frames` (their
angles may use all of these), then `definitions` (each may use everything before
it; a definition may be a vector). Particles and bodies are named points and
frames for the sections after them (forces, springs, constraints; lagcli/model/vectors.py).
Known functions and definitions are substituted, so model expressions contain
only t, q, q', q'' and parameters. All problems are collected and raised
together as one `SpecError`.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping

import sympy as sp

from lagcli.model.calculus import TimeDerivative, free_symbols, numerically_zero, shared_terms
from lagcli.errors import Problem, SpecError
from lagcli.model.expr import Scope, parse, parse_constant
from lagcli.interface import acceleration_name, velocity_name
from lagcli.model.model_types import (AppliedForce, ConstraintSpec, InputInfo, LinearDamper, LinearSpring,
                                Model, ParameterInfo, PointMass, RigidBody, Settings)
from lagcli.model.hybrid_model import hybrid_fields
from lagcli.model.kinematics import AXES, Entity, Vector, frame_chains
from lagcli.model.redundancy import independent_rows
from lagcli.model.rolling import rolling_constraints, rolling_contact
from lagcli.spec.types import Body, Spec, Src, VectorSrc
from lagcli.model.symbols import Acceleration, Velocity
from lagcli.model.vectors import VectorBuilder


def build_model(spec: Spec) -> Model:
    """Turn a validated spec into sympy objects (raises SpecError with every problem)."""
    return _ModelBuilder(spec).build()


class _ModelBuilder:
    def __init__(self, spec: Spec):
        self.spec = spec
        self.problems: list[Problem] = []
        self.constants: dict[str, float] = {}     # constant texts parsed without error -> their values
        self.t = sp.Symbol("t", real=True)
        names = [c.name for c in spec.coordinates]
        self.q = tuple(sp.Symbol(n, real=True) for n in names)
        self.qd = tuple(Velocity(velocity_name(n), real=True) for n in names)      # print as q̇
        self.qdd = tuple(Acceleration(acceleration_name(n), real=True) for n in names)
        self.u = tuple(sp.Symbol(u.name, real=True) for u in spec.inputs)
        self.D = TimeDerivative(self.t, self.q, self.qd, self.qdd)
        self.terms: dict = {}       # the terms of the positions' sums met so far (`_position`)
        # the symbol sets every check asks about, formed once (per check they made a spec of
        # n coordinates cost n^2)
        self.rates = frozenset(self.qd) | frozenset(self.qdd)
        self.configuration = frozenset(self.q) | {self.t}     # what moves a point
        self.moving = self.rates | self.configuration
        self.scope = Scope({"pi": sp.pi}, self.t, self._time_derivative, VectorBuilder)
        self.frames: dict[str, tuple] = {}  # frame name -> its whole rotation chain
        self._value_names: dict | None = None   # parameter and input names -> "a parameter" / "an input"

    # -- helpers ---------------------------------------------------------------
    def _time_derivative(self, expr: sp.Expr) -> sp.Expr:
        if expr.free_symbols & self.D.accelerations:
            raise SpecError(Problem(self._current_loc, "diff(expr, t) of an expression that "
                                    "already contains accelerations is not supported"))
        return self.D(expr)

    def expr(self, src: Src | None, default: sp.Expr | None = None,
             check: Callable[[sp.Expr, Src], None] | None = None, vector: bool | None = False):
        """Parse one expression, recording (not raising) its problems; a `Vector` when
        `vector` is true, either kind when it is None."""
        if src is None:
            return default
        self._current_loc = src.loc
        try:
            value = parse(src.text, self.scope, src.loc, vector)
            if check:
                for part in value.components if isinstance(value, Vector) else (value,):
                    check(part, src)
            return value
        except SpecError as exc:
            self.problems.extend(exc.problems)
            return Vector((sp.Symbol("_invalid_"),) * 3) if vector else sp.Symbol("_invalid_")

    def vector(self, srcs, check=None) -> sp.ImmutableMatrix:
        if len(srcs) == 1 and isinstance(srcs[0], VectorSrc):
            return self.expr(srcs[0], check=check, vector=True).matrix
        parts = [self.expr(s, check=check) for s in srcs]
        return sp.ImmutableMatrix(parts + [sp.S.Zero] * (3 - len(parts)))

    def _position(self, srcs) -> sp.ImmutableMatrix:
        """A particle's or body's position, each term of its sums the same object as the equal
        term of an earlier position (`shared_terms`)."""
        return shared_terms(self.vector(srcs, self.no_velocities), self.terms)

    def constant(self, src: Src | None, default: float | None, extra=None, elsewhere=None) -> float | None:
        if src is None:
            return default
        if not extra and src.text in self.constants:      # a value written before (a chain's 1.0s)
            return self.constants[src.text]
        try:
            value = parse_constant(src.text, src.loc, extra, elsewhere)
            if not extra:      # the value of a text without extra names is the text's alone
                self.constants[src.text] = value
            return value
        except SpecError as exc:
            self.problems.extend(exc.problems)
            return default

    def no_inputs(self, value: sp.Expr, src: Src) -> None:
        """Inputs are applied loads: only forces, torques and generalized forces take them."""
        used = free_symbols(value, self.D.free) & set(self.u)
        if used:
            raise SpecError(Problem(src.loc, f"{src.text!r} uses the input(s) "
                                    f"{', '.join(sorted(map(str, used)))}, but inputs may appear only in "
                                    "forces, torques and generalized_forces",
                                    "declare a constant as a parameter; a prescribed motion of t as "
                                    "a known function"))

    def no_velocities(self, value: sp.Expr, src: Src) -> None:
        self.no_inputs(value, src)
        used = free_symbols(value, self.D.free) & self.rates     # positions share their terms: walked once
        if used:
            raise SpecError(Problem(src.loc, f"{src.text!r} must not depend on velocities or "
                                    f"accelerations (uses {', '.join(sorted(map(str, used)))})"))

    def constant_in_motion(self, value: sp.Expr, src: Src) -> None:
        self.no_inputs(value, src)
        used = value.free_symbols & self.moving
        if used:
            raise SpecError(Problem(src.loc, f"{src.text!r} must be constant (uses "
                                    f"{', '.join(sorted(map(str, used)))}); masses, inertias and "
                                    "stiffnesses cannot change during the motion"))

    def at_most_quadratic(self, value: sp.Expr, src: Src) -> None:
        """The extra kinetic energy must split as T2 + T1 + T0: a polynomial of degree <= 2 in q'."""
        self.no_inputs(value, src)
        self.no_accelerations(value, src)
        velocities = set(self.qd)
        hessian = [value.diff(u).diff(v) for u in self.qd for v in self.qd]
        if any(h.free_symbols & velocities for h in hessian) and \
                not numerically_zero([h.diff(w) for h in hessian for w in self.qd]):
            raise SpecError(Problem(src.loc, f"{src.text!r} must be a polynomial of degree at most 2 "
                                    "in the velocities (T = T2 + T1 + T0)"))

    def no_accelerations(self, value: sp.Expr, src: Src) -> None:
        """Forces, torques and generalized forces: anything but accelerations (inputs too)."""
        if value.free_symbols & self.D.accelerations:
            raise SpecError(Problem(src.loc, f"{src.text!r} must not contain accelerations"))

    # -- stages ----------------------------------------------------------------
    def build(self) -> Model:
        spec = self.spec
        parameters = self._parameters()
        self.parameter_values = {p.symbol: p.value for p in parameters}
        inputs = self._inputs()
        self.scope.names.update({p.symbol.name: p.symbol for p in parameters})
        self.scope.names.update({u.symbol.name: u.symbol for u in inputs})
        self.scope.names.update({q.name: q for q in self.q})
        self.scope.names.update({v.name: v for v in self.qd})
        known = self._named(spec.known, self._only_time)
        self._frames()
        definitions = self._named(spec.definitions, None, vector=None)
        particles = tuple(PointMass(p.name, self.expr(p.mass, check=self.constant_in_motion),
                                    self._position(p.position), p.loc)
                          for p in spec.particles)
        bodies = tuple(self._body(b) for b in spec.bodies)
        self._name_points(particles, bodies)
        where = {p.name: p.position for p in particles} | {b.name: b.position for b in bodies}
        model = Model(
            name=spec.name, description=spec.description, source=spec.file,
            dimension=spec.dimension, t=self.t, q=self.q, qd=self.qd, qdd=self.qdd,
            coordinate_latex={q: c.latex for q, c in zip(self.q, spec.coordinates) if c.latex},
            parameters=parameters, known=known, definitions=definitions,
            particles=particles, bodies=bodies,
            gravity=self.vector(spec.gravity, self.constant_in_motion) if spec.gravity else None,
            forces=tuple(self._force(f, where, bodies) for f in spec.forces),
            springs=tuple(self._spring(s, where) for s in spec.springs),
            potential=self.expr(spec.potential, sp.S.Zero, self.no_velocities),
            kinetic=self.expr(spec.kinetic, sp.S.Zero, self.at_most_quadratic),
            generalized_forces=self._generalized_forces(),
            constraints=self._independent(
                tuple(ConstraintSpec(c.name, self.expr(c.expr, check=self.constraint_expr), c.loc)
                      for c in spec.constraints)
                + tuple(row for item in spec.rolling for row in rolling_constraints(item, self))),
            initial=self._initial(parameters),
            settings=self._settings(),
            dampers=tuple(self._damper(d, where) for d in spec.dampers),
            dissipation=self.expr(spec.dissipation, sp.S.Zero, self.no_accelerations),
            units={item.name: (item.unit, item.loc.child("unit")) for item in (*spec.coordinates, *spec.parameters,
                                                                          *spec.inputs)
                   if item.unit is not None},
            locs=_item_locs(spec),
            inputs=inputs,
            **hybrid_fields(self),
            rolling=tuple(rolling_contact(item, self) for item in spec.rolling),
        )
        if self.problems:
            raise SpecError(self.problems)
        return model

    def _independent(self, constraints: tuple) -> tuple:
        """The constraint rows without those that repeat earlier ones (lagcli/model/redundancy.py)."""
        if self.problems:
            return constraints
        return independent_rows(constraints, self.q, self.qd, self.t, dict(self.parameter_values), self.spec.file)

    def _parameters(self) -> tuple[ParameterInfo, ...]:
        return tuple(ParameterInfo(sp.Symbol(p.name, real=True), self.constant(p.value, 0.0, None,
                                                                               self._in_a_value(p)),
                                   p.latex, p.description) for p in self.spec.parameters)

    def _in_a_value(self, item) -> "_NamedInAValue":
        """What to say of a parameter or input named in `item`'s value: values are constants."""
        if self._value_names is None:
            self._value_names = {other.name: kind for kind, group in (("a parameter", self.spec.parameters),
                                                                        ("an input", self.spec.inputs))
                                 for other in group}
        return _NamedInAValue(self._value_names, item)

    def _inputs(self) -> tuple[InputInfo, ...]:
        return tuple(InputInfo(symbol, self.constant(u.value, 0.0, None, self._in_a_value(u)), u.latex, u.description)
                     for symbol, u in zip(self.u, self.spec.inputs))

    def constraint_expr(self, value: sp.Expr, src: Src) -> None:
        self.no_inputs(value, src)
        self.no_accelerations(value, src)

    def _only_time(self, value: sp.Expr, src: Src) -> None:
        used = value.free_symbols & (self.moving - {self.t} | set(self.u))
        if used:
            raise SpecError(Problem(src.loc, f"known function {src.text!r} may depend on t and "
                                    f"parameters only (uses {', '.join(sorted(map(str, used)))})"))

    def _named(self, items, check, vector: bool | None = False) -> tuple[tuple[str, sp.Expr], ...]:
        """The scalar items (vector definitions live in the scope only)."""
        result = []
        for item in items:
            value = self.expr(item.expr, check=check, vector=vector)
            self.scope.names[item.name] = value
            if not isinstance(value, Vector):
                result.append((item.name, value))
        return tuple(result)

    def _frames(self) -> None:
        """Each frame (with its unit vectors A_x, A_y, A_z) into the scope."""
        own = {f.name: (f.parent, tuple((axis, self.expr(a, check=self.no_velocities)) for axis, a in f.rotations))
               for f in self.spec.frames}
        self.frames = frame_chains(own)
        for name, chain in self.frames.items():
            frame = Entity("frame", name, self.D, rotations=chain)
            self.scope.names[name] = frame
            self.scope.names.update({f"{name}_{axis}": frame.unit(axis) for axis in AXES})

    def _name_points(self, particles, bodies) -> None:
        """Particles and bodies as named points (and frames) of later expressions."""
        for p in particles:
            self.scope.names[p.name] = Entity("particle", p.name, self.D, position=Vector.of(p.position))
        for b in bodies:
            self.scope.names[b.name] = Entity("body", b.name, self.D, rotations=b.rotations,
                                              position=Vector.of(b.position))

    def _body(self, body: Body) -> RigidBody:
        inertia = [self.expr(s, check=self.constant_in_motion) for s in body.inertia]
        if body.frame is not None:
            rotations, tensor = self.frames[body.frame], _inertia_tensor(inertia)
        elif body.angle is not None:
            rotations = (("z", self.expr(body.angle, check=self.no_velocities)),)
            tensor = sp.diag(0, 0, inertia[0])
        else:
            rotations = tuple((axis, self.expr(a, check=self.no_velocities)) for axis, a in body.orientation)
            tensor = _inertia_tensor(inertia)
        return RigidBody(body.name, self.expr(body.mass, check=self.constant_in_motion),
                         sp.ImmutableMatrix(tensor), self._position(body.position),
                         rotations, body.loc)

    def _force(self, force, where, bodies) -> AppliedForce:
        point = None
        if force.at is not None:
            point = where.get(force.at)
        elif force.point is not None:
            point = self.vector(force.point, self.no_velocities)
        body_name = force.body or (force.at if any(b.name == force.at for b in bodies) else None)
        torque = None
        if force.torque is not None:
            torque = (sp.ImmutableMatrix([0, 0, self.expr(force.torque[0], check=self.no_accelerations)])
                      if len(force.torque) == 1 and not isinstance(force.torque[0], VectorSrc)
                      else self.vector(force.torque, self.no_accelerations))
        vector = self.vector(force.force, self.no_accelerations) if force.force is not None else None
        return AppliedForce(point, vector, body_name if torque is not None else None, torque, force.loc)

    def _spring(self, spring, where) -> LinearSpring:
        ends = self._ends(spring, where, "spring")
        return LinearSpring(ends[0], ends[1], self.expr(spring.stiffness, check=self.constant_in_motion),
                            self.expr(spring.rest_length, sp.S.Zero, self.constant_in_motion), spring.loc)

    def _damper(self, damper, where) -> LinearDamper:
        ends = self._ends(damper, where, "damper")
        return LinearDamper(ends[0], ends[1], self.expr(damper.damping, check=self.constant_in_motion), damper.loc)

    def _ends(self, item, where, what: str) -> list:
        """The ends of a spring or damper: a particle, a body, or a point whose position may
        move with the coordinates (a point of a body off its centre). Refused when neither end
        moves (it does nothing) or both are the same point (no direction: 0/0)."""
        ends = [where[e] if isinstance(e, str) else self.vector(e, self.no_velocities) for e in item.ends]
        loc = item.loc.child("between") if item.loc else None
        if not any(sp.ImmutableMatrix(end).free_symbols & self.configuration for end in ends):
            self.problems.append(Problem(loc, f"a {what} between two fixed points does nothing",
                                         "one end must be a particle or body, or a point that moves "
                                         "with the coordinates, e.g. [x + l*cos(theta), l*sin(theta)]"))
        elif numerically_zero(list(sp.ImmutableMatrix(ends[0]) - sp.ImmutableMatrix(ends[1]))):
            self.problems.append(Problem(loc, f"the two ends of this {what} are the same point: it has no "
                                         "length and no direction", "attach its ends to two different points"))
        return ends

    def _generalized_forces(self) -> tuple[sp.Expr, ...]:
        given = {g.name: self.expr(g.expr, check=self.no_accelerations) for g in self.spec.generalized_forces}
        return tuple(given.get(q.name, sp.S.Zero) for q in self.q)

    def spec_initial_values(self) -> dict[str, float]:
        """The spec's `initial:` values at the parameters' values (built once)."""
        if not hasattr(self, "_initial_values"):
            self._initial_values = self._initial(self._parameters())
        return self._initial_values

    def _initial(self, parameters) -> dict:
        values = {p.symbol.name: sp.Float(p.value) for p in parameters}
        return {item.name: self.constant(item.expr, 0.0, values) for item in self.spec.initial}

    def _settings(self) -> Settings:
        s, d = self.spec.simulate, Settings()
        return Settings(t_end=self.positive(s.t_end, d.t_end), dt=self.positive(s.dt, d.dt),
                        method=s.method or d.method, rtol=self.positive(s.rtol, d.rtol),
                        atol=self.positive(s.atol, d.atol))

    def positive(self, src: Src | None, default: float) -> float:
        value = self.constant(src, default)
        if src is not None and value is not None and not value > 0:
            self.problems.append(Problem(src.loc, f"must be positive, got {value:g}"))
        return value


class _NamedInAValue(Mapping):
    """name -> (message, hint) for a parameter or input named in the value of `item`, each
    said only when asked (a dict of every name for each of 2 000 parameters was 4 million
    messages: most of `check` of 1 000 uncoupled coordinates)."""

    def __init__(self, kinds: dict, item):
        self.kinds, self.item = kinds, item

    def __getitem__(self, name: str) -> tuple[str, str]:
        item = self.item
        example = f"definitions: {{{item.name}: {item.value.text if item.value else '...'}}}"
        return (f"'{name}' is {self.kinds[name]}, and the value of {item.name} must be a constant "
                "(numbers and pi)", f"a quantity computed from parameters goes in `definitions:` "
                f"instead, e.g. {example}")

    def __iter__(self):
        return iter(self.kinds)

    def __len__(self) -> int:
        return len(self.kinds)


def _item_locs(spec: Spec) -> dict:
    """Where the coordinates and the whole-spec expressions were written, by key path."""
    locs = {c.loc.path: c.loc for c in spec.coordinates}
    locs.update({g.loc.path: g.loc for g in spec.gravity or ()})
    locs.update({src.loc.path: src.loc for src in (spec.potential, spec.kinetic, spec.dissipation)
                 if src is not None})
    locs.update({g.loc.path: g.loc for g in spec.generalized_forces})
    return locs


def _inertia_tensor(values: list[sp.Expr]) -> sp.Matrix:
    """3 principal moments, 6 (Ixx, Iyy, Izz, Ixy, Iyz, Izx) or 9 row-major entries."""
    if len(values) == 3:
        return sp.diag(*values)
    if len(values) == 6:
        xx, yy, zz, xy, yz, zx = values
        return sp.Matrix([[xx, xy, zx], [xy, yy, yz], [zx, yz, zz]])
    return sp.Matrix(3, 3, values)

