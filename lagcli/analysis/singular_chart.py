"""Points of rest where the coordinates, not the physics, are singular.

At theta = 0 z-x-z Euler angles turn psi and phi about one axis, and at the pole of
spherical angles phi moves nothing: some velocity v moves no mass (M v = 0), so the
mass matrix is singular and no linear model exists in these coordinates. The pose is
fine, and so are other descriptions of it: q0 + t v for t along a turn (kept where the
pose key says the pose is the same, `pose.py`). Together they decide what one chart
cannot:

1. Is it an equilibrium? Only when the equations at rest hold at every description:
   a chart that cannot move in the direction gravity pulls (a body whose centre of mass
   lies off its z axis, horizontal at theta = 0) is stationary there in its own
   coordinates only; such a point is no equilibrium.
2. Its stability, from a regular chart assembled from the descriptions: the pose key's
   Jacobian J_j at each maps that chart's velocities to pose velocities; their span is
   the tangent space of the configuration (it must have n dimensions). Its basis is the
   coordinates' own directions here, then those the other descriptions add (a primed
   name: theta' is theta in another description), so the chart's coordinates w read
   like the spec's. In w each chart's matrices at rest are C_j^T X C_j (J_j = B C_j, B
   the basis): M, and the Jacobians of the forcing in q and q', since the forcing
   vanishes at an equilibrium. Least squares over the charts gives X; the
   linear model in w gives the eigenvalues and the verdict (`stability.py`). A
   constrained system, or descriptions that do not reach every direction, are left
   undecided, and the note says so.

A constrained system is examined where the still velocities turn angles only (gimbal
lock: a coin lying with its axis vertical in z-x-y angles): step 1 with the multipliers,
each description's equations at rest F + A^T lambda = 0 solved for lambda by least
squares (a chart that cannot tilt the coin does not feel the torque of the contact
force about the missing axis, so the point is stationary in its own coordinates only);
its stability is left undecided.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

SINGULAR = 1e-10          # M is singular when its smallest singular value is below this * its largest
DESCRIPTIONS = 8          # other descriptions tried along each still velocity: a turn in eighths
AT_REST = 1e-8            # |equations at rest| of a description that is an equilibrium too
FIT = 1e-7                # relative misfit of the assembled chart's matrices that is accepted


@dataclass(frozen=True)
class CoordinateSingularity:
    """What lagcli can say at a point of rest where M is singular because of the coordinates."""

    still: tuple[str, ...]      # the coordinates of the velocities that move nothing
    equilibrium: bool           # the equations at rest hold at every description of the pose
    notes: tuple[str, ...]      # plain statements (shown under the point, one a line)
    linear: object = None       # LinearModel in the assembled chart's coordinates w1.. (None: undecided)
    stability: object = None    # its Stability


class Charts:
    """M, the forcing's Jacobians at rest and the pose key with its Jacobian, compiled."""

    def __init__(self, d, parameters: dict, pose_exprs: list):
        from lagcli.analysis.jacobians import CompiledJacobians

        model = d.model
        self.derivation, self.parameters = d, parameters
        numbers = {p.symbol: sp.Float(parameters[p.symbol.name], 30) for p in (*model.parameters, *model.inputs)}
        rest = {model.t: 0} | numbers
        q, qd = list(model.q), list(model.qd)
        M = sp.Matrix(d.mass_matrix).xreplace(rest).xreplace({v: 0 for v in qd})
        F = sp.Matrix(d.forcing).xreplace(rest)
        outputs = {"M": M, "F": F}
        if d.constraints:                       # the constraint rows at rest: step 1 only
            outputs["A"] = sp.Matrix(d.constraint_matrix).xreplace(rest).xreplace({v: 0 for v in qd})
        self._matrices = CompiledJacobians([*q, *qd], outputs, {"F_q": ("F", q), "F_qd": ("F", qd)})
        self._pose = CompiledJacobians(q, {"key": sp.Matrix(pose_exprs)}, {"key_q": ("key", q)})
        self.n = len(q)

    def at(self, q: np.ndarray) -> dict:
        """M, F, F_q, F_qd at rest at q."""
        return self._matrices([*q, *np.zeros(self.n)])

    def singular(self, q: np.ndarray) -> bool:
        with np.errstate(all="ignore"):
            s = np.linalg.svd(self.at(q)["M"], compute_uv=False)
        return bool(np.all(np.isfinite(s)) and s[-1] <= SINGULAR * max(s[0], 1e-300))

    def key(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        out = self._pose(list(q))
        return out["key"].reshape(-1), out["key_q"]


def examine(charts: Charts, q0: np.ndarray, angles: frozenset) -> CoordinateSingularity:
    """What the other descriptions of the pose at `q0` say (module docstring)."""
    from scipy.linalg import null_space

    from lagcli.analysis.pose import same_pose

    names = [s.name for s in charts.derivation.model.q]
    M0 = charts.at(q0)["M"]
    still_vectors = null_space(M0, rcond=SINGULAR)
    still = tuple(names[k] for k in range(len(q0)) if np.max(np.abs(still_vectors[k]), initial=0.0) > 1e-6)
    if charts.derivation.constraints and not (still and set(still) <= angles):
        raise ValueError("examine: a constrained system only where the still velocities turn angles")
    key0, _ = charts.key(q0)
    descriptions = [q0]
    for v in still_vectors.T:
        v = v / np.max(np.abs(v))
        for k in sorted(range(1, DESCRIPTIONS), key=lambda k: (k % 2, k)):   # quarter turns first
            q = q0 + 2 * math.pi * k / DESCRIPTIONS * v
            if same_pose(charts.key(q)[0], key0):
                descriptions.append(q)
    at_rest = [charts.at(q) for q in descriptions]
    what = _what(still, angles)
    if any(_unbalanced(m) > AT_REST for m in at_rest):
        return CoordinateSingularity(still, False, (f"stationary in these coordinates only ({what})",))
    notes = [what + ": the coordinates are singular, not the physics"]
    if charts.derivation.constraints:
        notes.append("a constrained system at a coordinate singularity: lagcli cannot decide the stability here")
        return CoordinateSingularity(still, True, tuple(notes))
    linear, where = _assembled(charts, q0, descriptions, at_rest)
    if linear is None:
        notes.append("the other descriptions of this pose do not reach every direction: "
                     "lagcli cannot decide the stability here")
    else:
        notes.append(f"stability at rest in a regular chart assembled from {len(descriptions)} "
                     f"descriptions of this pose, coordinates {', '.join(linear.coordinates)} "
                     f"({where}, the same pose)")
    if len(still) > 1 and all(s in angles for s in still):
        notes.append("a steady spin about that axis (the sleeping top) is not decided here: "
                     "see docs/analysis.md, \"Coordinate singularities\"")
    if linear is None:
        return CoordinateSingularity(still, True, tuple(notes))
    from lagcli.analysis.stability import stability

    return CoordinateSingularity(still, True, tuple(notes), linear, stability(linear))


def _unbalanced(at_rest: dict) -> float:
    """|F + A^T lambda| at rest, lambda by least squares (F itself when unconstrained)."""
    F = np.asarray(at_rest["F"], dtype=float).reshape(-1)
    if "A" in at_rest and at_rest["A"].size:
        At = np.asarray(at_rest["A"], dtype=float).reshape(-1, F.size).T
        F = F - At @ np.linalg.lstsq(At, F, rcond=None)[0]
    return float(np.max(np.abs(F), initial=0.0))


def _what(still, angles) -> str:
    if len(still) == 1:
        return f"{still[0]} moves nothing here"
    kind = "rotation" if all(s in angles for s in still) else "motion"
    return f"{', '.join(still[:-1])} and {still[-1]} describe the same {kind} here"


def _assembled(charts: Charts, q0: np.ndarray, descriptions: list, at_rest: list):
    """(the linear model in the chart assembled from the descriptions, a note naming its
    coordinates), or (None, "") when they do not reach every direction or misfit."""
    from lagcli.analysis.linearize import LinearModel, _jacobi_conserved_at
    from lagcli.analysis.operating_point import Point

    jacobians = [charts.key(q)[1] for q in descriptions]
    basis, names, where = _directions(charts, descriptions, jacobians)
    if len(names) != charts.n:
        return None, ""
    C = [np.linalg.lstsq(basis, J, rcond=None)[0] for J in jacobians]
    fitted = [_fit(C, [m[name] for m in at_rest]) for name in ("M", "F_q", "F_qd")]
    if any(X is None for X in fitted):
        return None, ""
    M, F_q, F_qd = fitted
    M = (M + M.T) / 2
    r = charts.n
    A = np.block([[np.zeros((r, r)), np.eye(r)], [np.linalg.solve(M, F_q), np.linalg.solve(M, F_qd)]])
    point = Point(0.0, q0, np.zeros(r), dict(charts.parameters))
    linear = LinearModel(point, tuple(names), tuple(f"{x}_dot" for x in names), (), A, np.zeros((2 * r, 0)), M,
                         -F_qd, -F_q, np.zeros((r, 0)), np.zeros(r), (), _jacobi_conserved_at(charts.derivation, point))
    return linear, where


def _directions(charts: Charts, descriptions: list, jacobians: list):
    """Pose directions of the coordinates, here first, then in the other descriptions, each
    kept when it is new: (basis, names: a coordinate, primed when from another description,
    a note saying where the primed ones are)."""
    model_names = [s.name for s in charts.derivation.model.q]
    columns, names, where = [], [], []
    scale = max(float(np.max(np.linalg.norm(J, axis=0), initial=0.0)) for J in jacobians)
    for q, J in zip(descriptions, jacobians):
        for k, name in enumerate(model_names):
            column = J[:, k]
            if columns:
                basis = np.column_stack(columns)
                column_left = column - basis @ np.linalg.lstsq(basis, column, rcond=None)[0]
            else:
                column_left = column
            if np.linalg.norm(column_left) <= 1e-6 * scale:        # moves nothing, or nothing new
                continue
            primes = sum(1 for n in names if n.rstrip("'") == name)
            names.append(name + "'" * primes)
            columns.append(column)
            if primes:
                at = ", ".join(f"{n} = {v:.6g}" for n, v in zip(model_names, q))
                where.append(f"{names[-1]} is {name} at {at}")
    basis = np.column_stack(columns) if columns else np.zeros((jacobians[0].shape[0], 0))
    return basis, names, "; ".join(where)


def _fit(C: list, matrices: list) -> np.ndarray | None:
    """X with C_j^T X C_j = matrices[j] for every j (least squares), or None when it misfits."""
    r = C[0].shape[0]
    system = np.vstack([np.kron(c.T, c.T) for c in C])
    target = np.concatenate([np.asarray(m).reshape(-1, order="F") for m in matrices])
    x = np.linalg.lstsq(system, target, rcond=None)[0]
    scale = float(np.max(np.abs(target), initial=0.0))
    if np.max(np.abs(system @ x - target), initial=0.0) > FIT * scale:
        return None
    return x.reshape(r, r, order="F")
