"""The numeric search for points of rest: equations E(z) = 0 in unknowns z = (q, lambda).

A least-squares solve (scipy's `least_squares`) runs from every starting point of a
deterministic set built around each guess:

- an angle takes the guess's value and a quarter, a half and three quarters of a turn
  more, so the hanging and the upright positions are both tried whatever the guess;
- any other coordinate takes the guess's value and its mirror image (-value), so a
  Cartesian pendulum started at (0.6, -0.8) is also started at (0.6, 0.8);
- the multipliers start at 0.

The combinations are tried in order of how many coordinates differ from the guess
(the guess itself first), at most `MAX_STARTS` per guess: every single angle turned is
always among them.

An equilibrium is often one of a family: a disc rests upright at any position,
heading and spin angle, and a coin at rest on an incline anywhere along the slope (y
and z together). Each solution slides along its family to the member nearest the
first guess: the family's directions are the null space of dE/dz there (each checked by
a small step that stays a solution), the step is the coordinates' distance to the
guess projected onto them (at most `STEP_LIMIT` long, halved until the solve from its
end stays within `BEND` of it), until the step vanishes or the distance grows. The coordinates
those directions move are reported. Repeats are merged last: two solutions are one when
they put the system in one pose (`pose.py`: positions and rotation matrices, so an
angle a turn on, or Euler angles (psi + pi, -theta, phi + pi), is the same pose), or,
for equations with no pose (Routh's), when their coordinates agree with angles compared
modulo 2 pi. Angles are reported in [0, 2 pi).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np

MAX_STARTS = 64            # starting points per guess
RESIDUAL = 1e-10           # max |E(z)| of a solution
SAME = 1e-7                # solutions this close (max norm over q, angles modulo 2 pi) are one
SLIDE_STEPS = 60           # steps along a family, at most
HALVINGS = 30              # a step along a curved family is halved at most this often
BEND = 0.1                 # a step may bend this much (of its length) back onto the family
_PROBE = 1e-3              # the step that checks a family direction
_TURN = 2 * math.pi


@dataclass(frozen=True)
class Stationary:
    values: tuple[float, ...]           # the unknowns' values (q first)
    symbolic: tuple | None = None       # closed forms (sympy; None: found numerically)
    free: tuple[int, ...] = ()          # coordinates (indices) along which it is one of a family


@dataclass(frozen=True)
class RestProblem:
    """E(z) = 0 compiled: `residual(z)`, `jacobian(z)`; the first `n` unknowns are the
    coordinates, `angles` their indices that are angles; `pose(q)`: the pose key of
    coordinates q (`pose.pose_function`), or None."""

    residual: object
    jacobian: object
    n: int
    angles: frozenset
    pose: object = None


def search(problem: RestProblem, guesses: list[list[float]], vary: bool = True) -> list[Stationary]:
    """Every distinct solution reached from the starting points around `guesses`, each
    the member of its family nearest the first guess (from the guesses alone, and no
    families, when not `vary`)."""
    found = []
    for guess in guesses:
        for start in (starting_points(problem, guess) if vary else [guess]):
            z = solve(problem, np.asarray(start, dtype=float))
            if z is not None:
                found.append(Stationary(tuple(float(v) for v in z)))
    if not vary:
        return distinct(found, problem)
    reference = guesses[0] if guesses else [0.0] * problem.n
    return distinct([nearest_member(problem, s, reference) for s in distinct(found, problem)], problem)


def starting_points(problem: RestProblem, guess: list[float]) -> list[list[float]]:
    """The guess, then its variations (module docstring), fewest changed coordinates first."""
    choices = []
    for k, value in enumerate(guess[:problem.n]):
        if k in problem.angles:
            choices.append([value + turn * math.pi / 2 for turn in range(4)])
        else:
            choices.append([value, -value] if value != 0 else [value])
    combos = sorted(itertools.product(*(range(len(c)) for c in choices)),
                    key=lambda pick: (sum(1 for p in pick if p), pick))
    tail = list(guess[problem.n:])
    return [[c[p] for c, p in zip(choices, pick)] + tail for pick in combos[:MAX_STARTS]]


def solve(problem: RestProblem, start: np.ndarray, fixed: dict | None = None) -> np.ndarray | None:
    """A solution of E(z) = 0 from `start` with the unknowns in `fixed` {index: value}
    held, or None when the solve does not reach RESIDUAL."""
    from scipy.optimize import least_squares

    z = start.copy()
    for k, v in (fixed or {}).items():
        z[k] = v
    moving = [k for k in range(len(z)) if k not in (fixed or {})]

    def full(part):
        out = z.copy()
        out[moving] = part
        return out

    with np.errstate(all="ignore"):   # a start at a singular point just fails
        if not np.all(np.isfinite(problem.residual(z))):
            return None
        result = least_squares(lambda p: problem.residual(full(p)), z[moving],
                               jac=lambda p: problem.jacobian(full(p))[:, moving],
                               xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
    if not (np.all(np.isfinite(result.fun)) and np.max(np.abs(result.fun), initial=0.0) < RESIDUAL):
        return None
    return full(np.where(np.abs(result.x) < 1e-13, 0.0, result.x))


def nearest_member(problem: RestProblem, s: Stationary, reference: list[float]) -> Stationary:
    """`s` slid along its family (module docstring) to the member nearest `reference`."""
    z = np.array(s.values)
    for _ in range(SLIDE_STEPS):
        directions = family_directions(problem, z)
        step = directions @ (directions.T @ _gap(problem, z, reference))
        if not directions.size or np.linalg.norm(step) < 1e-12:
            break
        moved = _follow(problem, z, step)
        if moved is None or _distance(problem, moved, reference) > _distance(problem, z, reference) + 1e-12:
            break
        z = moved
    moving = np.abs(family_directions(problem, z)[:problem.n]).max(axis=1, initial=0.0) > 1e-6
    return replace(s, values=tuple(float(v) for v in z), free=tuple(int(k) for k in np.flatnonzero(moving)))


def family_directions(problem: RestProblem, z: np.ndarray) -> np.ndarray:
    """Columns: the directions along which the solution `z` is one of a family (the null
    space of dE/dz, each checked by a small step that stays a solution)."""
    from scipy.linalg import null_space

    with np.errstate(all="ignore"):
        jacobian = problem.jacobian(z)
    if not np.all(np.isfinite(jacobian)):
        return np.zeros((len(z), 0))
    checked = [v for v in null_space(jacobian, rcond=1e-9).T if _follow(problem, z, _PROBE * v, halvings=0) is not None]
    return np.array(checked).T if checked else np.zeros((len(z), 0))


def _follow(problem: RestProblem, z: np.ndarray, step: np.ndarray, halvings: int = HALVINGS) -> np.ndarray | None:
    """The solution reached from z + step when it is within BEND of it (the step halved
    until it is, at most `halvings` times), else None."""
    for _ in range(halvings + 1):
        moved = solve(problem, z + step)
        if moved is not None and np.linalg.norm(moved - z - step) <= BEND * np.linalg.norm(step):
            return moved
        step = step / 2
    return None


def _gap(problem: RestProblem, z: np.ndarray, reference: list[float]) -> np.ndarray:
    """reference - z over the coordinates (angles the shorter way round), 0 for the multipliers."""
    gap = np.zeros(len(z))
    gap[:problem.n] = [-_difference(z[k], reference[k], k in problem.angles) for k in range(problem.n)]
    return gap


def _distance(problem: RestProblem, z: np.ndarray, reference: list[float]) -> float:
    return float(np.linalg.norm(_gap(problem, z, reference)))


def distinct(found: list[Stationary], problem: RestProblem) -> list[Stationary]:
    """`found` with angles in [0, 2 pi), without repeats (the first of each kept), sorted."""
    unique: list[tuple[Stationary, object]] = []
    for s in (wrapped(s, problem) for s in found):
        key = problem.pose(s.values[:problem.n]) if problem.pose else np.array(s.values)
        match = next((k for k, (u, other) in enumerate(unique)
                      if _same(key, other, problem) or _one_family(problem, u, key)), None)
        if match is None:
            unique.append((s, key))
        elif s.free and not unique[match][0].free:      # a closed form keeps the family's coordinates
            unique[match] = (replace(unique[match][0], free=s.free), unique[match][1])
    return sorted((s for s, _ in unique), key=lambda s: s.values[:problem.n])


def _one_family(problem: RestProblem, s: Stationary, key: np.ndarray) -> bool:
    """Some member of the family of `s` (a straight line or plane along its family
    directions) has the pose `key`: started from the projection of the way there and from
    each direction turned a quarter, half and three quarters of a turn on."""
    from scipy.optimize import least_squares

    from lagcli.analysis.pose import same_pose

    if not (s.free and problem.pose):
        return False
    z = np.array(s.values)
    directions = family_directions(problem, z)[:problem.n]
    if not directions.size:
        return False
    q = z[:problem.n]
    miss = lambda c: problem.pose(q + directions @ c) - key   # noqa: E731 (a one-line residual)
    for start in _family_starts(problem, directions):
        with np.errstate(all="ignore"):
            c = least_squares(miss, start, xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=100).x
        if same_pose(problem.pose(q + directions @ c), key):
            return True
    return False


def _family_starts(problem: RestProblem, directions: np.ndarray) -> list[np.ndarray]:
    """0, and each family direction moved so that its largest angle turns by quarter turns."""
    starts = [np.zeros(directions.shape[1])]
    for k, column in enumerate(directions.T):
        angle = max((abs(column[j]) for j in problem.angles), default=0.0)
        for turn in (1, 2, 3) if angle > 1e-6 else ():
            start = np.zeros(directions.shape[1])
            start[k] = turn * math.pi / 2 / angle
            starts.append(start)
    return starts


def wrapped(s: Stationary, problem: RestProblem) -> Stationary:
    """`s` with every angle in [0, 2 pi) (whole turns taken off; a closed form too)."""
    values, symbolic = list(s.values), list(s.symbolic) if s.symbolic else None
    for k in problem.angles:
        turns = math.floor(values[k] / _TURN)
        rest = values[k] - turns * _TURN
        if abs(rest - _TURN) < 1e-12 or abs(rest) < 1e-13:
            turns, rest = round(values[k] / _TURN), 0.0
        values[k] = rest
        if symbolic is not None and turns:
            import sympy as sp
            symbolic[k] = symbolic[k] - 2 * sp.pi * turns
    return replace(s, values=tuple(values), symbolic=tuple(symbolic) if symbolic is not None else None)


def _difference(a: float, b: float, angle: bool) -> float:
    """a - b, for angles the shorter way round."""
    return math.remainder(a - b, _TURN) if angle else a - b


def _same(a: np.ndarray, b: np.ndarray, problem: RestProblem) -> bool:
    """`a` and `b` (pose keys, or the unknowns when there is no pose) are one solution."""
    if problem.pose:
        from lagcli.analysis.pose import same_pose

        return same_pose(a, b)
    return all(abs(_difference(a[k], b[k], k in problem.angles)) < SAME for k in range(problem.n))
