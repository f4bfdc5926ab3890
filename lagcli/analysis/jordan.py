"""How many eigenvectors an eigenvalue on the imaginary axis has: the Jordan structure
that decides whether the linear model stays bounded there.

An eigenvalue s of A repeated k times (algebraic multiplicity k) with fewer than k
independent eigenvectors (geometric multiplicity n - rank(A - s I)) is *defective*:
the linear solutions grow like t^j e^(s t). On the imaginary axis that is the
difference between bounded and growing: the gantry crane's trolley and load at rest
have s = 0 twice with one eigenvector, (x, xl) = (1, 1); a push of both makes them
drift together, x = xl = v t.

The ranks are numerical: singular values of (A - s I) / |A| below `RANK_TOL` count as 0
(A is normalised, so the tolerance is relative to its size). The repeats of s are the
eigenvalues within `CLUSTER` |A| of it: a defective pair splits by about
sqrt(eps) |A| ~ 1.5e-8 |A| in floating point, so a tolerance tighter than that would
miss it. Both are far from what a mechanical model of a few bodies gives as distinct
frequencies (sympy's exact `Matrix.jordan_form` agrees on the bundled specs and
textbook blocks: tests/test_verdicts.py).
"""
from __future__ import annotations

import numpy as np

RANK_TOL = 1e-9     # singular values of (A - s I)/|A| below this are 0
CLUSTER = 1e-6      # eigenvalues within this * |A| of each other are one repeated eigenvalue
DRIFT_TOL = 1e-6    # a state takes part in a drift when its share of the drift vector is above this


def norm(A: np.ndarray) -> float:
    return max(1.0, float(np.linalg.norm(A, 2))) if A.size else 1.0


def repeats(values: np.ndarray, s: complex, scale: float) -> int:
    """How many of `values` are the eigenvalue `s` (within `CLUSTER` of the scale)."""
    return int(np.sum(np.abs(values - s) <= CLUSTER * scale))


def clustered(A: np.ndarray, values: np.ndarray) -> np.ndarray:
    """`values` (A's eigenvalues) with each cluster near the imaginary axis made one value:
    a defective eigenvalue splits by ~sqrt(eps) |A| in floating point, so the members of
    a cluster (`repeats` > 1, |Re| within `CLUSTER`) get real part 0 and their mean
    imaginary part."""
    scale = norm(A)
    out = values.copy()
    for k, s in enumerate(values):
        near = np.abs(values - complex(0.0, s.imag)) <= CLUSTER * scale
        if abs(s.real) <= CLUSTER * scale and np.sum(near) > 1:
            out[k] = complex(0.0, float(np.mean(values[near].imag)))
    return out


def geometric_multiplicity(A: np.ndarray, s: complex) -> int:
    """n - rank(A - s I): the number of independent eigenvectors of `s`."""
    n = A.shape[0]
    scale = norm(A)
    singular = np.linalg.svd((A - s * np.eye(n)) / scale, compute_uv=False)
    return int(np.sum(singular <= RANK_TOL))


def defective(A: np.ndarray, values: np.ndarray, on_axis) -> tuple[complex, ...]:
    """The eigenvalues in `values` (those of A) on the imaginary axis (`on_axis(s)`) with
    fewer eigenvectors than repeats; each pair listed by its member with Im >= 0."""
    scale = norm(A)
    found: list[complex] = []
    for s in values:
        s = complex(0.0, s.imag) if on_axis(s) else None
        if s is None or s.imag < 0 or any(abs(s - f) <= CLUSTER * scale for f in found):
            continue
        k = repeats(values, s, scale)
        if k > 1 and geometric_multiplicity(A, s) < k:
            found.append(s)
    return tuple(found)


def drifting_states(A: np.ndarray, states, values: np.ndarray) -> tuple[str, ...]:
    """The states that grow linearly in t because s = 0 is defective: the support of A Z,
    Z the generalized eigenvectors of 0 (the null space of A^k, k its repeats)."""
    scale = norm(A)
    k = repeats(values, 0.0, scale)
    if k < 2 or geometric_multiplicity(A, 0.0) >= k:
        return ()
    power = np.linalg.matrix_power(A / scale, k)
    _, singular, vh = np.linalg.svd(power)
    rank = int(np.sum(singular > RANK_TOL))
    Z = vh[rank:].conj().T                     # generalized eigenvectors of 0
    drift = A @ Z                               # what grows like t: the eigenvectors they reach
    if not drift.size:
        return ()
    share = np.max(np.abs(drift), axis=1)
    return tuple(s for s, x in zip(states, share) if x > DRIFT_TOL * max(np.max(share), 1e-300))
