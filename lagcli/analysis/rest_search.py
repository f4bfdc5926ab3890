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

An equilibrium is often one of a family: a disc rests upright at any position and
heading. A coordinate that neither F(q, 0) nor the holonomic rows contain is tried for
this: it is moved to its value in the first guess (through two intermediate values, and
half a unit beyond), the other unknowns solved again each time; when every solve
succeeds with the other coordinates unchanged, the solution is that member of the
family and the coordinate is reported as free. Repeats are merged last, angles compared
modulo 2 pi and reported in [0, 2 pi).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np

MAX_STARTS = 64            # starting points per guess
RESIDUAL = 1e-10           # max |E(z)| of a solution
SAME = 1e-7                # solutions this close (max norm over q, angles modulo 2 pi) are one
_FAMILY_STEPS = (2 / 3, 1 / 3, 0.0)   # the way to the family's reference value
_FAMILY_BEYOND = 0.5       # and this far past it (times 1 + |reference|)
_TURN = 2 * math.pi


@dataclass(frozen=True)
class Stationary:
    values: tuple[float, ...]           # the unknowns' values (q first)
    symbolic: tuple | None = None       # closed forms (sympy; None: found numerically)
    free: tuple[int, ...] = ()          # coordinates (indices) the equilibrium holds for any value of


@dataclass(frozen=True)
class RestProblem:
    """E(z) = 0 compiled: `residual(z)`, `jacobian(z)`; the first `n` unknowns are the
    coordinates, `angles` their indices that are angles, `family` the indices of those
    neither F(q, 0) nor the holonomic rows contain."""

    residual: object
    jacobian: object
    n: int
    angles: frozenset
    family: tuple[int, ...]


def search(problem: RestProblem, guesses: list[list[float]], vary: bool = True) -> list[Stationary]:
    """Every distinct solution reached from the starting points around `guesses` (from
    the guesses alone when not `vary`)."""
    found = []
    for guess in guesses:
        for start in (starting_points(problem, guess) if vary else [guess]):
            z = solve(problem, np.asarray(start, dtype=float))
            if z is not None:
                found.append(Stationary(tuple(float(v) for v in z)))
    reference = guesses[0] if guesses else [0.0] * problem.n
    return distinct([one_of_family(problem, s, reference) for s in distinct(found, problem)], problem)


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


def one_of_family(problem: RestProblem, s: Stationary, reference: list[float]) -> Stationary:
    """`s` moved, along each family coordinate it is free in, to the reference value."""
    z, free = np.array(s.values), []
    for k in problem.family:
        target = reference[k]
        gap = _difference(z[k], target, k in problem.angles)
        probes = dict.fromkeys([target + gap * step for step in _FAMILY_STEPS]
                               + [target + _FAMILY_BEYOND * (1 + abs(target))])
        members = {p: solve(problem, z, {k: p}) for p in probes}
        if all(m is not None and _close(m, z, problem, skip=k) for m in members.values()):
            z, free = members[target], free + [k]
    if not free:
        return s
    return replace(s, values=tuple(float(v) for v in z), free=tuple(free))


def distinct(found: list[Stationary], problem: RestProblem) -> list[Stationary]:
    """`found` with angles in [0, 2 pi), without repeats (the first of each kept), sorted."""
    unique: list[Stationary] = []
    for s in (wrapped(s, problem) for s in found):
        if not any(_close(np.array(s.values), np.array(u.values), problem) for u in unique):
            unique.append(s)
    return sorted(unique, key=lambda s: s.values[:problem.n])


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


def _close(a: np.ndarray, b: np.ndarray, problem: RestProblem, skip: int = -1) -> bool:
    """The coordinates of `a` and `b` (all but `skip`) agree within SAME."""
    return all(abs(_difference(a[k], b[k], k in problem.angles)) < SAME
               for k in range(problem.n) if k != skip)
