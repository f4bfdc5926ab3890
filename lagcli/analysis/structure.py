"""The linear model in a basis where its neutral directions by structure are coordinates.

`LinearModel.invariant` holds directions v of the independent coordinates along which
nothing in the equations changes (checked at the point and at a generic one): the
gantry crane's trolley and load moving together, (x, xl) = (1, 1). With T_c = [v,
unit vectors completing the basis] the coordinates become (s, rest), q = T_c q~, and
when every speed is the rate of a coordinate (holonomic speeds, possibly reordered)
the speeds follow, u = T_s u~ with T_s = T_c's rows in speed order; then

    A~ = T^-1 A T,   T = diag(T_c, T_s),     K~ = T_s^T K T_c,   C~ = T_s^T C T_s

(the second-order form multiplied by T_s^T: the energy's quadratic forms in the new
coordinates). s has a zero column in A~, so `stability.essential` deflates it like a
coordinate nothing depends on. A direction is named by its coordinates, "x + xl".
Without such a direction, or with speeds that are not the coordinates' rates (a
nonholonomic model), T = I and the names are the states'.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lagcli.analysis.linearize import LinearModel, gyroscopic_part

STEADY = 1e-9               # |rate| above this: the point is no equilibrium or steady motion

_CLEAN = 1e-9       # entries of a direction below this (of its largest) are 0


@dataclass(frozen=True)
class StructureBasis:
    A: np.ndarray
    states: tuple[str, ...]             # names of the new states: coordinates, then speeds
    coordinates: tuple[str, ...]
    speeds: tuple[str, ...]
    K: np.ndarray                       # speeds x coordinates, new basis
    C: np.ndarray
    pairs: dict                         # coordinate name -> its speed's name (when square)
    Tc: np.ndarray
    Ts: np.ndarray
    generic_A: np.ndarray = None        # A at scaled parameters, same basis (`linearize.generic_state_matrix`)

    @property
    def gyroscopic(self) -> np.ndarray:
        return gyroscopic_part(self.C)

    @property
    def symmetric_stiffness(self) -> bool:
        """K is square over the coordinates with speeds, and symmetric (a Hessian)."""
        K = self.square(self.coordinates)
        if K is None:
            return False
        return bool(np.allclose(K, K.T, atol=1e-9 * max(1.0, np.max(np.abs(K), initial=0.0))))

    def coordinates_of(self, kept) -> list[str]:
        """The kept coordinates that have a kept speed."""
        return [q for q in self.coordinates if q in kept and self.pairs.get(q) in kept]

    def square(self, coordinates) -> np.ndarray | None:
        """K over `coordinates` and their speeds (None when one has no speed)."""
        if not all(q in self.pairs for q in coordinates):
            return None
        rows = [self.speeds.index(self.pairs[q]) for q in coordinates]
        cols = [self.coordinates.index(q) for q in coordinates]
        return self.K[np.ix_(rows, cols)]

    def stiffness(self, kept) -> np.ndarray | None:
        """K of the essential coordinates (kept, with a kept speed); None when a kept
        coordinate has no speed of its own (K is then no potential's Hessian)."""
        coordinates = [q for q in self.coordinates if q in kept]
        if any(q not in self.pairs for q in coordinates):
            return None
        return self.square(self.coordinates_of(kept))

    def rates(self, model: LinearModel, kept) -> list[tuple[str, float]]:
        """(state, rate) of each speed that changes and each kept coordinate that moves at
        the point: none at an equilibrium or a steady motion (where only coordinates
        neutral by structure move, at constant speeds)."""
        limit = STEADY * max(1.0, float(np.max(np.abs(model.point.qd), initial=0.0)))
        qd = model.coordinate_rates if model.coordinate_rates.size else np.zeros(len(model.coordinates))
        moving = np.linalg.solve(self.Tc, qd) if self.Tc.size else qd
        return ([(_rate_name(q), float(r)) for q, r in zip(self.coordinates, moving) if q in kept and abs(r) > limit]
                + [(f"{u}'", float(r)) for u, r in zip(model.speeds, model.speed_rates) if abs(r) > limit])


def _rate_name(coordinate: str) -> str:
    return f"({coordinate})'" if " " in coordinate else f"{coordinate}'"


def structure_basis(model: LinearModel) -> StructureBasis:
    nc = len(model.coordinates)
    order = _speed_order(model)
    V = _readable(model.invariant) if model.invariant.size else np.zeros((nc, 0))
    Tc, name = _completed(V)
    if order is None:       # speeds that are not the coordinates' rates stay as they are
        coordinates = name(model.coordinates)
        pairs = {q: q + "_dot" for q in coordinates if q + "_dot" in model.speeds}
        return _basis(model, Tc, np.eye(len(model.speeds)), coordinates, model.speeds, pairs)
    coordinates, speeds = name(model.coordinates), name(tuple(q + "_dot" for q in model.coordinates))
    return _basis(model, Tc, Tc[order, :], coordinates, speeds, dict(zip(coordinates, speeds)))


def _basis(model, Tc, Ts, coordinates, speeds, pairs: dict) -> StructureBasis:
    T = np.block([[Tc, np.zeros((Tc.shape[0], Ts.shape[1]))], [np.zeros((Ts.shape[0], Tc.shape[1])), Ts]])
    A = np.linalg.solve(T, model.A @ T) if T.size else model.A
    generic = model.generic_A
    if generic.shape == model.A.shape and T.size:
        generic = np.linalg.solve(T, generic @ T)
    return StructureBasis(A, (*coordinates, *speeds), tuple(coordinates), tuple(speeds),
                          Ts.T @ model.K @ Tc, Ts.T @ model.C @ Ts, pairs, Tc, Ts,
                          generic if generic.shape == A.shape else None)


def _speed_order(model: LinearModel) -> list[int] | None:
    """Speed j is the rate of coordinate order[j] (None when the speeds are not the rates of
    the coordinates, one each)."""
    names = [s.removesuffix("_dot") for s in model.speeds]
    if len(names) != len(model.coordinates) or set(names) != set(model.coordinates):
        return None
    return [model.coordinates.index(n) for n in names]


def _readable(V: np.ndarray) -> np.ndarray:
    """A basis of the span of V's columns in reduced echelon form (pivots 1), tiny entries 0."""
    R = V.T.copy()
    rows, cols = R.shape
    r = 0
    for c in range(cols):
        if r == rows:
            break
        p = r + int(np.argmax(np.abs(R[r:, c])))
        if abs(R[p, c]) <= _CLEAN * np.max(np.abs(R), initial=0.0):
            continue
        R[[r, p]] = R[[p, r]]
        R[r] /= R[r, c]
        for i in range(rows):
            if i != r:
                R[i] -= R[i, c] * R[r]
        r += 1
    R[np.abs(R) <= _CLEAN] = 0.0
    return R[:r].T


def _completed(V: np.ndarray):
    """T_c = [V, unit vectors of the coordinates that complete it], and a function naming
    its columns from names of the coordinates (or of their speeds): V's columns by their
    coordinates ("x + xl"), the unit vectors by their coordinate."""
    nc, r = V.shape
    columns = [V[:, k] for k in range(r)]
    for k in range(nc):
        e = np.eye(nc)[:, k]
        if np.linalg.matrix_rank(np.column_stack([*columns, e]), tol=1e-9) > len(columns):
            columns.append(e)
    # in the coordinates' order (by each column's first coordinate), a direction before a unit vector
    order = sorted(range(len(columns)), key=lambda k: (int(np.flatnonzero(columns[k])[0]), k >= r))
    T = np.column_stack([columns[k] for k in order])
    invariant = [order.index(k) for k in range(r)]
    measured = np.linalg.inv(T)
    measured[np.abs(measured) <= _CLEAN] = 0.0

    def name(names) -> tuple[str, ...]:
        """A neutral direction by the coordinates it moves ("x + xl"), every other new
        coordinate by what it measures (a row of T_c^-1: "x - xl")."""
        return tuple(_direction_name(T[:, k] if k in invariant else measured[k], names) for k in range(T.shape[1]))

    return T, name


def _direction_name(v: np.ndarray, coordinates) -> str:
    terms = []
    for x, q in zip(v, coordinates):
        if x == 0:
            continue
        sign = "-" if x < 0 else "+"
        weight = "" if abs(abs(x) - 1) <= 1e-12 else f"{abs(x):.6g} "
        terms.append(f"{sign} {weight}{q}")
    text = " ".join(terms)
    return text[2:] if text.startswith("+ ") else "-" + text[2:]
