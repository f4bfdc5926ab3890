"""`lagcli animate` / `System.animate`: the motion drawn from a trajectory.

What is drawn comes from the model, never from spec text: the positions lagcli built
as sympy expressions (particles, bodies' centres of mass, spring ends) and each
body's rotation matrix are lambdified once (`Scene`), then evaluated at the rows of a
trajectory (the CSV of `lagcli simulate`, or a run made on the spot).

    particle            a marker
    body                a marker at its centre of mass and its three body axes (planar:
                        its x axis) drawn as segments +-a_i, the half-extents of the
                        uniform box with the body's inertia (a_i^2 = 3 (I_jj + I_kk - I_ii)
                        / (2 m); planar: a_x^2 = 3 I_zz / m, a rod's half-length)
    disc                a body that is a wheel of a `rolling:` element (its radius and
                        axis), or whose inertia is a thin disc's (I_a = I_b + I_c, I_b = I_c:
                        radius sqrt(2 I_a / m)), is also drawn as its rim, a circle about that axis
    spring              a line between its ends; damper: a dashed line
    plane               the plane a `rolling:` element rolls on, translucent (3-D)
    surface             where an impact or stop event's gap is a point's coordinate plus a
                        constant (`when: y`, `when: y + h`: a floor, a wall), the gap's zero
                        set: a line across the view (planar), a translucent plane (3-D)
    --link A:B          a line between two points (particle or body names, or `origin`):
                        the massless rods of a pendulum, which the model does not hold
    --trace P           the path of a point so far (by default, each disc's centre's)

Planar specs are drawn in the x-y plane, spatial ones in 3-D (matplotlib's mplot3d).
Each particle and body has its own colour (a fixed palette in spec order); the title is
the spec's name, as in `simulate --plot`. The time is shown in the corner. Output: .gif (pillow), .mp4 (needs ffmpeg), or
.png, .svg or .pdf with `--frame T` (the frame at time T: the row nearest to T).
"""
from __future__ import annotations

import os
import shutil
import tempfile
from dataclasses import dataclass

import numpy as np

from lagcli.render.escape import plot_text
from lagcli.errors import UsageError
from lagcli.render.output import write_output

ORIGIN = "origin"
MAX_FRAMES = 600                 # a long run is thinned (every k-th row) to at most this many
FORMATS = (".gif", ".mp4", ".png", ".svg", ".pdf")
FRAME_FORMATS = (".png", ".svg", ".pdf")       # one frame (--frame T), as lagcli.viz.plot writes it
PALETTE = ("tab:blue", "tab:orange", "tab:purple", "tab:red", "tab:cyan", "tab:olive", "tab:pink",
           "tab:brown", "tab:gray", "tab:green")
RIM_POINTS = 49                  # points of a drawn disc's rim (the first repeated)


@dataclass(frozen=True)
class Scene:
    """Numeric position and orientation functions of a model's points and bodies."""

    dimension: int
    points: dict          # name -> f(t, y, p) -> (3,)   particles and body centres of mass
    bodies: dict          # name -> (f(t, y, p) -> (3, 3) rotation, half-extents f(p) -> (3,))
    springs: tuple        # (f_a, f_b) per spring
    dampers: tuple = ()   # (f_a, f_b) per damper
    discs: dict = None    # body name -> (axis index 0..2, radius f(p)) of the bodies drawn as discs
    planes: tuple = ()    # (unit normal f(p) -> (3,), height f(p)) of each rolling element's plane
    surfaces: tuple = ()  # (axis index 0..2, value f(p)) of each event surface r_axis = value

    def position(self, name: str, t: float, y, p) -> np.ndarray:
        if name == ORIGIN:
            return np.zeros(3)
        return np.asarray(self.points[name](t, y, p), dtype=float).reshape(3)

    def rim(self, name: str, t: float, y, p) -> np.ndarray:
        """The points of a disc's rim (RIM_POINTS x 3)."""
        axis, radius = self.discs[name]
        R = np.asarray(self.bodies[name][0](t, y, p), dtype=float).reshape(3, 3)
        e1, e2 = R[:, (axis + 1) % 3], R[:, (axis + 2) % 3]
        s = np.linspace(0.0, 2 * np.pi, RIM_POINTS)
        r = float(np.asarray(radius(p), dtype=float).reshape(-1)[0])
        return self.position(name, t, y, p) + r * (np.outer(np.cos(s), e1) + np.outer(np.sin(s), e2))

    def axes(self, name: str, t: float, y, p) -> list[tuple[np.ndarray, np.ndarray]]:
        """The body's axis segments (start, end) through its centre of mass."""
        rotation, extents = self.bodies[name]
        centre = self.position(name, t, y, p)
        R = np.asarray(rotation(t, y, p), dtype=float).reshape(3, 3)
        half = np.asarray(extents(p), dtype=float).reshape(3)
        count = 1 if self.dimension == 2 else 3
        return [(centre - half[i] * R[:, i], centre + half[i] * R[:, i]) for i in range(count)]


def scene_of(model) -> Scene:
    import sympy as sp

    args = [model.t, list(model.q) + list(model.qd), list(model.parameter_symbols)]

    def numeric(expr):
        return sp.lambdify(args, sp.Matrix(expr), "numpy")

    points = {p.name: numeric(p.position) for p in model.particles}
    bodies = {}
    for body in model.bodies:
        points[body.name] = numeric(body.position)
        bodies[body.name] = (numeric(body.rotation),
                             sp.lambdify([list(model.parameter_symbols)], _half_extents(body, model.dimension)))
    springs = tuple((numeric(s.end_a), numeric(s.end_b)) for s in model.springs)
    dampers = tuple((numeric(d.end_a), numeric(d.end_b)) for d in model.dampers)
    constant = lambda expr: sp.lambdify([list(model.parameter_symbols)], sp.Matrix([expr]), "numpy")
    discs = {name: (axis, constant(radius)) for name, (axis, radius) in _discs(model).items()}
    planes = tuple((constant(sp.Matrix(r.normal).T), constant(r.height)) for r in model.rolling)
    surfaces = tuple((axis, constant(value)) for axis, value in _event_surfaces(model))
    return Scene(model.dimension, points, bodies, springs, dampers, discs, planes, surfaces)


def _event_surfaces(model) -> list:
    """(axis, value) of each impact or stop event whose gap g is +-(a point's coordinate
    r_axis) plus a constant: the event happens on the surface r_axis = value (a floor where
    a ball bounces, where a projectile lands). Other gaps (an angle, a distance) are not drawn."""
    moving = set(model.q) | {model.t}
    found = []
    for event in (e for e in model.events if e.action in ("impact", "stop")):
        for _, position in model.mass_points:
            for axis in range(model.dimension):
                r = position[axis]
                rest = [(sign, event.when - sign * r) for sign in (1, -1) if r.free_symbols & moving]
                match = next(((sign, c) for sign, c in rest if not c.free_symbols & moving), None)
                if match and (axis, -match[1] / match[0]) not in found:
                    found.append((axis, -match[1] / match[0]))
    return found


def _discs(model) -> dict:
    """{body name: (axis index, radius)} of the bodies drawn as discs: the wheels of the
    `rolling:` elements, then the bodies whose inertia is a thin disc's about a body axis."""
    import sympy as sp

    if model.dimension != 3:
        return {}
    found = {r.body: ("xyz".index(r.axis), r.radius) for r in model.rolling if r.radius is not None}
    values = model.parameter_values
    for body in model.bodies:
        if body.name in found:
            continue
        I = [float(sp.sympify(body.inertia[k, k]).xreplace(values)) if body.inertia[k, k].free_symbols
             <= set(values) else 0.0 for k in range(3)]
        for a in range(3):
            b, c = I[(a + 1) % 3], I[(a + 2) % 3]
            if I[a] > 0 and abs(I[a] - b - c) <= 1e-9 * I[a] and abs(b - c) <= 1e-9 * I[a]:
                found[body.name] = (a, sp.sqrt(2 * body.inertia[a, a] / body.mass))
    return found


def _half_extents(body, dimension: int):
    import sympy as sp

    I, m = body.inertia, body.mass
    if dimension == 2:
        return sp.Matrix([sp.sqrt(3 * I[2, 2] / m), 0, 0])
    diag = [I[k, k] for k in range(3)]
    return sp.Matrix([sp.sqrt(sp.Max(0, 3 * (diag[(i + 1) % 3] + diag[(i + 2) % 3] - diag[i]) / (2 * m)))
                      for i in range(3)])


@dataclass(frozen=True)
class Request:
    links: tuple[tuple[str, str], ...] = ()
    traces: tuple[str, ...] = ()
    fps: float = 25.0
    frame: float | None = None           # one frame (PNG) at this time


def point_names(model) -> list[str]:
    return [p.name for p in model.particles] + [b.name for b in model.bodies]


def check_names(model, request: Request) -> None:
    known = [*point_names(model), ORIGIN]
    for name in [n for link in request.links for n in link] + list(request.traces):
        if name not in known:
            raise UsageError(f"animate: unknown point {name!r}; points are: {', '.join(known)}")


def parse_links(items) -> tuple[tuple[str, str], ...]:
    links = []
    for item in items:
        a, sep, b = item.partition(":")
        if not sep or not a.strip() or not b.strip():
            raise UsageError(f"--link {item!r}: expected A:B (particle or body names, or origin)")
        links.append((a.strip(), b.strip()))
    return tuple(links)


def frame_rows(t: np.ndarray, request: Request) -> list[int]:
    """The trajectory rows drawn: the one nearest `request.frame`, or every k-th row
    at about `fps` frames per second of simulated time (at most MAX_FRAMES)."""
    if request.frame is not None:
        return [int(np.argmin(np.abs(t - request.frame)))]
    if len(t) < 2:
        return list(range(len(t)))
    dt = float(np.median(np.diff(t)))
    stride = max(1, round(1.0 / (request.fps * dt)) if dt > 0 else 1, -(-len(t) // MAX_FRAMES))
    return list(range(0, len(t), stride))


class Drawing:
    """The figure and its artists; `draw(row)` moves them to one trajectory row."""

    def __init__(self, scene: Scene, times, states, p, request: Request, title: str, unit: str | None = None):
        from matplotlib.figure import Figure

        self.scene, self.times, self.states, self.p, self.request = scene, times, states, p, request
        self.unit = unit
        self.figure = Figure(figsize=(6, 6), dpi=100)
        three = scene.dimension == 3
        self.ax = self.figure.add_subplot(projection="3d" if three else None)
        self.ax.set_title(plot_text(title), usetex=False)
        self._limits(three)
        plot = self.ax.plot
        colours = {name: PALETTE[k % len(PALETTE)] for k, name in enumerate(scene.points)}
        if three:
            self._planes()
        self._surfaces(three)
        self.links = [plot(*self._xyz([]), "-", color="0.35", lw=2)[0] for _ in request.links]
        self.springs = [plot(*self._xyz([]), "-", color="tab:green", lw=1.5)[0] for _ in scene.springs]
        self.dampers = [plot(*self._xyz([]), "--", color="0.2", lw=1.5)[0] for _ in scene.dampers]
        self.rims = {name: plot(*self._xyz([]), "-", color=colours[name], lw=2)[0] for name in (scene.discs or {})}
        self.axes = {name: [plot(*self._xyz([]), "-", color=c, lw=2)[0] for c in ("tab:red", "tab:green",
                                                                                 "tab:blue")[:1 + 2 * three]]
                     for name in scene.bodies}
        # a disc's path is what explains a rolling motion: traced unless the caller chose traces
        self.trace_names = tuple(request.traces) or tuple(scene.discs or ())
        self.traces = [plot(*self._xyz([]), "-", lw=1, alpha=0.6, color=colours.get(name))[0]
                       for name in self.trace_names]
        self.markers = {name: plot(*self._xyz([]), "o", ms=8, color=colours[name])[0] for name in scene.points}
        self.clock = self.ax.text2D(0.02, 0.95, "", transform=self.ax.transAxes) if three else \
            self.ax.text(0.02, 0.95, "", transform=self.ax.transAxes)

    def _planes(self) -> None:
        """Each rolling element's plane as a translucent square over the view (fixed: it
        does not move; a turntable's rotation is not drawn)."""
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        low, high = (np.array([getattr(self.ax, f"get_{a}lim")()[k] for a in "xyz"]) for k in (0, 1))
        centre, half = (low + high) / 2, float((high - low).max()) / 2
        for normal_of, height_of in self.scene.planes:
            n = np.asarray(normal_of(self.p), dtype=float).reshape(3)
            h = float(np.asarray(height_of(self.p), dtype=float).reshape(-1)[0])
            foot = centre - (n @ centre - h) * n              # the view's centre projected on the plane
            u = np.cross(n, np.eye(3)[int(np.argmin(np.abs(n)))])
            u /= np.linalg.norm(u)
            v = np.cross(n, u)
            corners = [foot + half * (a * u + b * v) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            self.ax.add_collection3d(Poly3DCollection([corners], alpha=0.15, facecolor="tab:gray",
                                                      edgecolor="0.6"))

    def _surfaces(self, three: bool) -> None:
        """Each event surface: a dark line across the view (planar), a plane (3-D)."""
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        for axis, value_of in self.scene.surfaces:
            value = float(np.asarray(value_of(self.p), dtype=float).reshape(-1)[0])
            if not three:
                (self.ax.axhline if axis == 1 else self.ax.axvline)(value, color="0.25", lw=2.5)
                continue
            low, high = (np.array([getattr(self.ax, f"get_{a}lim")()[k] for a in "xyz"]) for k in (0, 1))
            u, v = ((low[i], high[i]) for i in range(3) if i != axis)
            corners = [np.insert(np.array(c, dtype=float), axis, value) for c in
                       ((u[0], v[0]), (u[1], v[0]), (u[1], v[1]), (u[0], v[1]))]
            self.ax.add_collection3d(Poly3DCollection([corners], alpha=0.2, facecolor="0.4", edgecolor="0.3"))

    def _xyz(self, points):
        data = np.array(points, dtype=float).reshape(-1, 3)
        return [data[:, 0], data[:, 1], data[:, 2]] if self.scene.dimension == 3 else [data[:, 0], data[:, 1]]

    def _set(self, line, points) -> None:
        xyz = self._xyz(points)
        if self.scene.dimension == 3:
            line.set_data_3d(*xyz)
        else:
            line.set_data(*xyz)

    def _limits(self, three: bool) -> None:
        """Fixed, equal-scaled limits around every point of the whole run (and the origin)."""
        every = [np.zeros(3)]
        for k in range(0, len(self.times), max(1, len(self.times) // 200)):
            every += [self.scene.position(n, self.times[k], self.states[k], self.p) for n in self.scene.points]
            every += [end for b in self.scene.bodies for seg in self.scene.axes(b, self.times[k], self.states[k],
                                                                                 self.p) for end in seg]
            every += [point for b in (self.scene.discs or {}) for point in
                      self.scene.rim(b, self.times[k], self.states[k], self.p)[::12]]
        for axis, value_of in self.scene.surfaces:          # the surface is in view
            every.append(np.insert(np.zeros(2), axis, float(np.asarray(value_of(self.p), dtype=float).reshape(-1)[0])))
        box = np.array(every)
        centre, half = (box.max(0) + box.min(0)) / 2, max(float((box.max(0) - box.min(0)).max()) / 2, 1e-9) * 1.1
        for k, axis in enumerate("xyz"[:3 if three else 2]):
            getattr(self.ax, f"set_{axis}lim")(centre[k] - half, centre[k] + half)
            getattr(self.ax, f"set_{axis}label")(f"{axis} [{self.unit}]" if self.unit else axis)
        if three:
            self.ax.set_box_aspect((1, 1, 1))
        else:
            self.ax.set_aspect("equal")
            self.ax.grid(True, alpha=0.3)

    def draw(self, row: int) -> list:
        scene, t, y, p = self.scene, self.times[row], self.states[row], self.p
        for name, marker in self.markers.items():
            self._set(marker, [scene.position(name, t, y, p)])
        for (a, b), line in zip(self.request.links, self.links):
            self._set(line, [scene.position(a, t, y, p), scene.position(b, t, y, p)])
        for (fa, fb), line in zip(scene.springs, self.springs):
            self._set(line, [np.asarray(fa(t, y, p), dtype=float).reshape(3),
                             np.asarray(fb(t, y, p), dtype=float).reshape(3)])
        for (fa, fb), line in zip(scene.dampers, self.dampers):
            self._set(line, [np.asarray(fa(t, y, p), dtype=float).reshape(3),
                             np.asarray(fb(t, y, p), dtype=float).reshape(3)])
        for name, line in self.rims.items():
            self._set(line, list(scene.rim(name, t, y, p)))
        for name, lines in self.axes.items():
            for line, segment in zip(lines, scene.axes(name, t, y, p)):
                self._set(line, list(segment))
        for name, line in zip(self.trace_names, self.traces):
            self._set(line, [scene.position(name, self.times[k], self.states[k], p) for k in range(row + 1)])
        self.clock.set_text(f"t = {t:.2f}")
        return [*self.markers.values(), *self.links, *self.springs, *self.dampers, *self.rims.values(),
                *self.traces, self.clock,
                *(line for lines in self.axes.values() for line in lines)]


def animate(system, times, states, parameters: dict, path: str | None, request: Request):
    """Draw the trajectory (times, states [q, q'] per row) of `system`; write `path`
    (.gif, .mp4, or .png, .svg, .pdf with request.frame) when given. Returns the `Drawing`."""
    suffix = os.path.splitext(str(path))[1].lower() if path is not None else None
    if path is not None and suffix not in FORMATS:
        raise UsageError(f"animate -o {path}: expected a .gif, .mp4, or a .png, .svg or .pdf (one frame) file name")
    if suffix in FRAME_FORMATS and request.frame is None:
        raise UsageError(f"animate: a {suffix} output is one frame: give --frame T")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise UsageError("animate: .mp4 needs ffmpeg, which is not installed; write a .gif instead "
                         "(or install ffmpeg)")
    check_names(system.model, request)
    scene = scene_of(system.model)
    p = [parameters[name] for name in system.layout.parameter_names]
    drawing = Drawing(scene, np.asarray(times, dtype=float), np.asarray(states, dtype=float), p, request,
                      system.name, length_unit(system.model))
    rows = frame_rows(drawing.times, request)
    if path is None or suffix in FRAME_FORMATS:
        drawing.draw(rows[0])
        if path is not None:
            from lagcli.viz.plot import figure_bytes, figure_format

            write_output(path, figure_bytes(drawing.figure, figure_format(path, "animate -o")))
        return drawing
    _save_movie(drawing, rows, path, suffix, request.fps)
    return drawing


def length_unit(model) -> str | None:
    """The unit of the view's axes: when the spec gives units, the points' positions are
    lengths by them (lagcli/model/units.py) and every length the spec declares is in one
    unit (units are dimensions to lagcli, not scales: the numbers drawn are the spec's),
    that unit's text ("m", "mm"); None otherwise (no unit shown)."""
    from lagcli.model.units import LENGTH, Mismatch, dimension_of, symbol_dimensions, unit_dimension

    dims = symbol_dimensions(model)
    if not dims:
        return None
    found = set()
    for position in [*(p.position for p in model.particles), *(b.position for b in model.bodies)]:
        for component in position:
            try:
                found.add(dimension_of(component, dims))
            except Mismatch:
                return None
    found.discard(())
    texts = {text.replace(" ", "") for text, loc in model.units.values() if unit_dimension(text, loc) == LENGTH}
    return next(iter(texts)) if found == {LENGTH} and len(texts) == 1 else None


def _save_movie(drawing: Drawing, rows, path: str, suffix: str, fps: float) -> None:
    """Render every frame and write the file atomically (through a private temporary file)."""
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter

    movie = FuncAnimation(drawing.figure, drawing.draw, frames=rows, blit=False)
    writer = FFMpegWriter(fps=fps) if suffix == ".mp4" else PillowWriter(fps=fps)
    with tempfile.TemporaryDirectory(prefix="lagcli-animate-") as work:
        scratch = os.path.join(work, "motion" + suffix)
        movie.save(scratch, writer=writer)
        with open(scratch, "rb") as handle:
            write_output(path, handle.read())
