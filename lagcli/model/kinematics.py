"""Frames, points and their motion, as the vector expressions of a spec see them.

A frame (a `frames:` entry, or a rigid body) is a chain of successive body-fixed
rotations from the inertial frame, R = R_1(a_1) R_2(a_2) ... R_k(a_k) (frame ->
inertial components). Its angular velocity, in inertial components, is one term
per rotation (the axis of rotation i is e_i of the frame rotated by the first i-1):

    w = sum_i (R_1 ... R_{i-1}) e_i  d(a_i)/dt

A point is a particle, a body's centre of mass, or `point(B, r)`: the material
point of body B at B's centre of mass + r at this instant, whose velocity is

    v = v_B + w_B x r                       (also when r is not fixed in B)

Every vector here has inertial components (a `Vector` of three sympy expressions);
`d/dt` is the model's total time derivative `lagcli.model.calculus.TimeDerivative`.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from lagcli.model.calculus import TimeDerivative
from lagcli.model.model_types import elementary_rotation

AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Vector:
    """A vector in inertial components (the value of a vector expression)."""

    components: tuple[sp.Expr, sp.Expr, sp.Expr]

    @property
    def matrix(self) -> sp.ImmutableMatrix:
        return sp.ImmutableMatrix(self.components)

    @staticmethod
    def of(matrix) -> "Vector":
        return Vector(tuple(sp.sympify(c) for c in matrix))

    def __add__(self, other: "Vector") -> "Vector":
        return Vector(tuple(a + b for a, b in zip(self.components, other.components)))

    def __sub__(self, other: "Vector") -> "Vector":
        return Vector(tuple(a - b for a, b in zip(self.components, other.components)))

    def __neg__(self) -> "Vector":
        return Vector(tuple(-a for a in self.components))

    def scaled(self, factor: sp.Expr) -> "Vector":
        return Vector(tuple(factor * a for a in self.components))

    def dot(self, other: "Vector") -> sp.Expr:
        return sum((a * b for a, b in zip(self.components, other.components)), sp.S.Zero)

    def cross(self, other: "Vector") -> "Vector":
        return Vector.of(self.matrix.cross(other.matrix))

    def rate(self, D: TimeDerivative) -> "Vector":
        """d/dt of the components (the motion of an expression, not of a material point)."""
        return Vector(tuple(D(c) for c in self.components))


ZERO = Vector((sp.S.Zero, sp.S.Zero, sp.S.Zero))


class Entity:
    """A named thing of the spec that vector expressions may refer to.

    kind "frame" (rotations only), "particle" (position only), "body" (both) or
    "point" (`point(B, r)`: position and velocity given)."""

    def __init__(self, kind: str, label: str, D: TimeDerivative,
                 rotations: tuple[tuple[str, sp.Expr], ...] | None = None,
                 position: Vector | None = None, velocity: Vector | None = None):
        self.kind, self.label, self.D = kind, label, D
        self.rotations, self.position = rotations, position
        self._velocity = velocity

    @property
    def is_frame(self) -> bool:
        return self.rotations is not None

    @property
    def is_point(self) -> bool:
        return self.position is not None

    @cached_property
    def rotation(self) -> sp.ImmutableMatrix:
        matrix = sp.eye(3)
        for axis, angle in self.rotations:
            matrix = matrix * elementary_rotation(axis, angle)
        return sp.ImmutableMatrix(matrix)

    def unit(self, axis: str) -> Vector:
        return Vector.of(self.rotation[:, AXES.index(axis)])

    @cached_property
    def angular_velocity(self) -> Vector:
        omega, partial = sp.zeros(3, 1), sp.eye(3)
        for axis, angle in self.rotations:
            omega += partial[:, AXES.index(axis)] * self.D(angle)
            partial = partial * elementary_rotation(axis, angle)
        return Vector.of(omega)

    @cached_property
    def velocity(self) -> Vector:
        return self._velocity if self._velocity is not None else self.position.rate(self.D)

    def material_point(self, offset: Vector) -> "Entity":
        """`point(self, offset)`: the point of this body at its centre of mass + offset."""
        velocity = self.velocity + self.angular_velocity.cross(offset)
        return Entity("point", f"point({self.label}, ...)", self.D,
                      position=self.position + offset, velocity=velocity)


def frame_chains(frames: dict[str, tuple[str | None, tuple]]) -> dict[str, tuple]:
    """name -> the whole rotation chain from the inertial frame, given name -> (parent,
    own rotations) with every parent known and no cycle (the spec checker sees to it)."""
    chains: dict[str, tuple] = {}

    def chain(name: str) -> tuple:
        if name not in chains:
            parent, own = frames[name]
            chains[name] = (chain(parent) if parent else ()) + tuple(own)
        return chains[name]

    for name in frames:
        chain(name)
    return chains
