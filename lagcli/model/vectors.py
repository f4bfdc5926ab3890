"""Vector expressions: the safe parser of lagcli/model/expr.py, extended with vectors.

Still a whitelist walk over Python's `ast` (nothing is evaluated); on top of the
scalar language it accepts

    [a, b, c]                      a vector literal (inertial components)
    A_x, A_y, A_z                  unit vectors of a frame A of `frames:`
    u + v, u - v, -u, s*u, u*s, u/s
    dot(u, v), cross(u, v)
    diff(u, t)                     the time derivative of each component
    position(P), velocity(P)       of a particle, a body's centre of mass or point(B, r)
    point(B, r)                    the material point of body B at its CM + r
    angular_velocity(A)            of a frame or a body (inertial components)

Frames, bodies and particles are names of their own kind: they are only arguments
of these functions, never operands. A vector where a scalar is needed (and the
reverse) is an error naming the place, with a hint.
"""
from __future__ import annotations

import ast
import difflib
import re

import sympy as sp

from lagcli.model.expr import FUNCTIONS, _Builder
from lagcli.model.kinematics import Entity, Vector
from lagcli.model.sums import total

VECTOR_FUNCTIONS = {  # name: (argument kinds, what it gives)
    "dot": (("vector", "vector"), "scalar"),
    "cross": (("vector", "vector"), "vector"),
    "position": (("point",), "vector"),
    "velocity": (("point",), "vector"),
    "angular_velocity": (("frame",), "vector"),
    "point": (("body", "vector"), "point"),
}
SCALAR_HINT = "take a component: dot(v, [1, 0, 0]) or dot(v, A_x) for a frame A"
VECTOR_HINT = "write a vector as [a, b, c] or from frame unit vectors, e.g. r*A_z + [x, y, 0]"
_UNIT = re.compile(r"(.+)_([xyz])")


class VectorBuilder(_Builder):
    """`_Builder` with vectors and the kinematic functions (values: sympy scalars,
    `Vector`s and `Entity`s, the last only as function arguments)."""

    # --- the kinds of values ------------------------------------------------------------

    def scalar(self, node: ast.AST) -> sp.Expr:
        return self.as_scalar(self.build(node), node)

    def as_scalar(self, value, node: ast.AST | None = None):
        if isinstance(value, Vector):
            self.fail(f"{self.written(node)} is a vector where a scalar is needed", SCALAR_HINT)
        if isinstance(value, Entity):
            self.entity_misused(value)
        return value

    def as_vector(self, value, node: ast.AST | None = None) -> Vector:
        if isinstance(value, Entity):
            self.entity_misused(value)
        if not isinstance(value, Vector):
            self.fail(f"{self.written(node)} is a scalar where a vector is needed", VECTOR_HINT)
        return value

    def entity_misused(self, entity: Entity) -> None:
        uses = {"frame": f"its unit vectors {entity.label}_x, {entity.label}_y, {entity.label}_z "
                         f"or angular_velocity({entity.label})",
                "particle": f"position({entity.label}) or velocity({entity.label})",
                "body": f"position({entity.label}), velocity({entity.label}), "
                        f"angular_velocity({entity.label}) or point({entity.label}, r)"}
        self.fail(f"'{entity.label}' is a {entity.kind}, not a value",
                  "use " + uses.get(entity.kind, "velocity(...) or position(...) of it"))

    def written(self, node: ast.AST | None) -> str:
        text = ast.get_source_segment(self.source, node) if node is not None else None
        return repr(text) if text else "the expression"

    def finish(self, value, vector: bool | None):
        """A vector when `vector`, a scalar when False, either when None (definitions)."""
        if vector is None and isinstance(value, Vector):
            return value
        return self.as_vector(value) if vector else self.as_scalar(value)

    def guarded(self, value, node: ast.AST):
        if isinstance(value, Vector):
            return Vector(tuple(super(VectorBuilder, self).guarded(c, node) for c in value.components))
        if isinstance(value, Entity):
            return value
        return super().guarded(value, node)

    # --- syntax ---------------------------------------------------------------------------

    def _List(self, node: ast.List):
        if len(node.elts) != 3:
            self.fail(f"a vector literal has 3 components [x, y, z]; got {len(node.elts)}")
        return Vector(tuple(self.scalar(item) for item in node.elts))

    def _Name(self, node: ast.Name):
        unit = _UNIT.fullmatch(node.id)
        if node.id not in self.scope.names and unit and unit.group(1) not in self.scope.names:
            frames = sorted(v.label for v in self.scope.names.values()
                            if isinstance(v, Entity) and v.kind == "frame")
            if frames:  # in a spec without frames, the scalar language's did-you-mean
                self.fail(f"unknown name '{node.id}' (no frame '{unit.group(1)}')",
                          f"frames are: {', '.join(frames)}")
        return super()._Name(node)

    def _UnaryOp(self, node: ast.UnaryOp):
        operand = self.build(node.operand)
        if isinstance(operand, Vector) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return -operand if isinstance(node.op, ast.USub) else operand
        return self.unary(node.op, self.as_scalar(operand, node.operand))

    def add(self, values: list, nodes: list[ast.AST], negated: list[bool]):
        """A sum of scalars, or of vectors (component by component, each added at once)."""
        if not any(isinstance(v, Vector) for v in values):
            return super().add(values, nodes, negated)
        vectors = [self.as_vector(v, n) for v, n in zip(values, nodes)]
        return Vector(tuple(total([-v.components[k] if minus else v.components[k]
                                   for v, minus in zip(vectors, negated)]) for k in range(3)))

    def _BinOp(self, node: ast.BinOp):
        if isinstance(node.op, (ast.Add, ast.Sub)):
            return self._sum(node)       # the scalar or vector sum, flat (lagcli/expr.py)
        left, right = self.build(node.left), self.build(node.right)
        if not isinstance(left, Vector) and not isinstance(right, Vector):
            return self.binary(node.op, self.as_scalar(left, node.left), self.as_scalar(right, node.right))
        if isinstance(node.op, ast.Mult) and isinstance(left, Vector) and isinstance(right, Vector):
            self.fail("the product of two vectors is dot(u, v) or cross(u, v)")
        if isinstance(node.op, ast.Mult):
            vector, factor = (left, right) if isinstance(left, Vector) else (right, left)
            return vector.scaled(self.as_scalar(factor))
        if isinstance(node.op, ast.Div) and isinstance(left, Vector):
            return left.scaled(self.binary(node.op, sp.S.One, self.as_scalar(right, node.right)))
        self.fail(f"operator '{type(node.op).__name__}' does not apply to vectors", SCALAR_HINT)

    def _Call(self, node: ast.Call):
        name = node.func.id if isinstance(node.func, ast.Name) else None
        if name is not None and name not in FUNCTIONS and name not in VECTOR_FUNCTIONS \
                and not name.startswith("__"):
            close = difflib.get_close_matches(name, [*FUNCTIONS, *VECTOR_FUNCTIONS], n=1)
            self.fail(f"unknown function '{name}'", f"did you mean '{close[0]}'?" if close else
                      "functions: " + ", ".join(sorted([*FUNCTIONS, *VECTOR_FUNCTIONS])))
        if name not in VECTOR_FUNCTIONS:
            return super()._Call(node)
        kinds, _ = VECTOR_FUNCTIONS[name]
        if node.keywords or len(node.args) != len(kinds):
            self.fail(f"{name}() takes {len(kinds)} positional argument(s): {name}({', '.join(kinds)})")
        args = [self.argument(kind, arg, name) for kind, arg in zip(kinds, node.args)]
        if name == "dot":
            return args[0].dot(args[1])
        if name == "cross":
            return args[0].cross(args[1])
        if name == "position":
            return args[0].position
        if name == "velocity":
            return args[0].velocity
        if name == "angular_velocity":
            return args[0].angular_velocity
        return args[0].material_point(args[1])

    def argument(self, kind: str, node: ast.AST, function: str):
        value = self.build(node)
        if kind == "vector":
            return self.as_vector(value, node)
        wanted = {"point": "is_point", "frame": "is_frame", "body": "is_frame"}[kind]
        if isinstance(value, Entity) and getattr(value, wanted) and (kind != "body" or value.is_point):
            return value
        names = {"point": "a particle, a body or point(B, r)", "frame": "a frame or a body",
                 "body": "a body"}[kind]
        self.fail(f"{function}() needs {names}; {self.written(node)} is not one",
                  "frames are declared under frames:, bodies under bodies:, particles under particles:")

    def _diff(self, node: ast.Call):
        if not (isinstance(node.args[1], ast.Name) and node.args[1].id == "t"):
            self.fail("diff(expr, t) differentiates with respect to time t only")
        if self.scope.time_derivative is None:
            self.fail("diff(expr, t) is not available here")
        value = self.build(node.args[0])
        if isinstance(value, Vector):
            return Vector(tuple(self.scope.time_derivative(c) for c in value.components))
        return self.scope.time_derivative(self.as_scalar(value, node.args[0]))
