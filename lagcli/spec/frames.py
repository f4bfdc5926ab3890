"""The spec format of frames and rolling contacts (docs/spec.md, "Frames, vectors and rolling").

A mixin of `schema._SpecChecker`: `frames:` (names, parents, no cycles, unit vector
names A_x, A_y, A_z declared), a body's `frame:` and `rolling:` entries. Their
expressions travel on as `Src`, parsed by lagcli/model/vectors.py at the model stage.
"""
from __future__ import annotations

from typing import Any

from lagcli.errors import Problem
from lagcli.spec import format as fmt
from lagcli.spec.checker import describe
from lagcli.spec.reader import KeyPath
from lagcli.spec.types import Frame, Rolling, Src, Surface

AXES = fmt.AXES


def rolling_row_prefix(body: str) -> str:
    """Constraint rows of a rolling body are `rolling_<body>_<axis>` (lagcli/model/rolling.py)."""
    return f"rolling_{body}_"


class FrameChecks:
    """`frames:`, `frame:` of a body and `rolling:`, for `schema._SpecChecker`."""

    frame_names: tuple[str, ...] = ()

    def frames(self, top: dict) -> tuple[Frame, ...]:
        frames = self.mapping_items(top, "frames", self.frame)
        self.frame_names = tuple(f.name for f in frames)
        if frames:
            self.note_dim(3, ("frames",))
        self.check_frame_cycles(frames)
        return frames

    def frame(self, name: str, path: KeyPath, value: Any) -> Frame | None:
        self.declare(name, "frame", path)
        for axis in AXES:
            self.declare(f"{name}_{axis}", f"unit vector of frame {name}", path)
        table = self.table(path, value, fmt.FRAME)
        if table is None:
            return None
        parent = self.reference(path + ("parent",), table["parent"], ("frame",)) if "parent" in table else None
        rotations = self.orientation(path + ("rotations",), table["rotations"]) if "rotations" in table else None
        if rotations is None:
            return None
        return Frame(name, parent, rotations, self.raw.loc(path, at_key=True))

    def check_frame_cycles(self, frames: tuple[Frame, ...]) -> None:
        parents, reported = {f.name: f.parent for f in frames}, set()
        for frame in frames:
            seen, name = [frame.name], frame.parent
            while name in parents and name not in seen:
                seen.append(name)
                name = parents[name]
            if name == frame.name and not reported & set(seen):
                reported.update(seen)
                self.fail(("frames", frame.name, "parent"),
                          f"frames form a cycle: {' -> '.join(seen + [name])}",
                          "every chain of parents must end at the inertial frame (a frame without parent)")

    def frame_body(self, path: KeyPath, table: dict) -> bool:
        """A body with `frame:` is spatial and oriented by that frame only."""
        for other in ("angle", "orientation"):
            if other in table:
                self.fail(path + (other,), f"a body has 'frame' or '{other}', not both",
                          "the frame gives the body's orientation")
        self.note_dim(3, path + ("frame",))
        return True

    def body_frame(self, path: KeyPath, table: dict) -> str | None:
        return self.reference(path + ("frame",), table["frame"], ("frame",)) if "frame" in table else None

    def torque_is_vector(self, value: Any) -> bool:
        """A torque string is a vector expression in a spec with frames, or when it has a [..] literal."""
        return isinstance(value, str) and (bool(self.frame_names) or "[" in value)

    def rolling(self, path: KeyPath, value: Any) -> Rolling | None:
        table = self.table(path, value, fmt.ROLLING)
        if table is None:
            return None
        self.note_dim(3, path)
        body = self.reference(path + ("body",), table["body"], ("body",)) if "body" in table else None
        if ("wheel" in table) == ("contact" in table):
            self.fail(path, "give exactly one of 'wheel' (a disc: {radius, axis}) or 'contact' "
                      "(the contact point's offset from the centre of mass)",
                      "e.g. wheel: {radius: r, axis: y}, or contact: [0, 0, -r] for a sphere")
        wheel = self.wheel(path + ("wheel",), table["wheel"]) if "wheel" in table else None
        contact = self.vector(path + ("contact",), table["contact"]) if "contact" in table else None
        surface = self.surface(path + ("surface",), table["surface"]) if "surface" in table else None
        if body is None or (wheel is None and contact is None):
            return None
        return Rolling(body, wheel, contact, surface, self.raw.loc(path))

    def wheel(self, path: KeyPath, value: Any) -> tuple[Src, str] | None:
        table = self.table(path, value, fmt.WHEEL)
        if table is None or "radius" not in table or "axis" not in table:
            return None
        if table["axis"] not in AXES:
            hint = "axes are lower-case x, y, z" if str(table["axis"]).lower() in AXES else ""
            self.fail(path + ("axis",), f"the wheel's axis (in body axes) is x, y or z; "
                      f"got {describe(table['axis'])} {table['axis']!r}", hint)
            return None
        radius = self.expr(path + ("radius",), table["radius"])
        return (radius, table["axis"]) if radius is not None else None

    def surface(self, path: KeyPath, value: Any) -> Surface | None:
        table = self.table(path, value, fmt.SURFACE)
        if table is None or "normal" not in table:
            return None
        normal = self.vector(path + ("normal",), table["normal"])
        height = self.expr(path + ("height",), table["height"]) if "height" in table else None
        rate = (self.expr(path + ("angular_velocity",), table["angular_velocity"])
                if "angular_velocity" in table else None)
        centre = self.vector(path + ("centre",), table["centre"]) if "centre" in table else None
        return Surface(normal, height, rate, centre) if normal is not None else None

    def check_rolling_names(self, rolling: tuple[Rolling, ...]) -> None:
        """Explicit constraint names must not take the rolling rows' names."""
        for item in rolling:
            prefix = rolling_row_prefix(item.body)
            for name in sorted(n for n in self.constraint_names if n):
                if name.startswith(prefix) and name[len(prefix):] in AXES:
                    self.problems.append(Problem(
                        item.loc, f"the rolling contact of '{item.body}' names its constraint rows "
                        f"{prefix}x, _y, _z, but a constraint is already called '{name}'",
                        "rename that constraint"))
