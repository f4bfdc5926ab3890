"""Eigenvalues, modes and a stability verdict of a linear model.

Zero modes that are there by structure — a coordinate nothing depends on (column
of A zero: x, y, the spin angle of a rolling disc) or a speed whose rate is zero
to first order (row zero) — are deflated before the eigenvalues are computed:
det(A - s I) = -s det(A' - s I) for A' the matrix without that row and column,
so the other eigenvalues are exactly those of A'. What is left are the
"essential" eigenvalues; the deflated ones are counted as neutral modes.

Verdict (tolerance `tol` relative to the largest eigenvalue):
  asymptotically stable   every essential Re(s) < -tol
  unstable                some Re(s) > tol
  stable                  all on the imaginary axis at a point of rest (q' = 0) where the
                          Jacobi integral h = T2 - T0 + V is conserved, no damping, and K
                          (the Hessian of V - T0) is positive definite: h has a strict
                          minimum there (Lagrange-Dirichlet)
  marginally stable       otherwise all on the imaginary axis (the linear model does not decide)
  gyroscopically stabilized   marginally stable although the stiffness matrix
                          K (the Hessian of the fictitious potential for a
                          scleronomic system) has a negative eigenvalue.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lagcli.analysis.linearize import LinearModel

STRUCTURAL_ZERO = 1e-12     # |entry| <= this * max|A| counts as a structural zero
MARGIN = 1e-9               # |Re s| <= this * max(1, max|s|) counts as on the imaginary axis
ROUNDING = 1000 * np.finfo(float).eps  # parts of s below this * rounding_scale(A) are noise: set to 0


@dataclass(frozen=True)
class Mode:
    eigenvalue: complex
    natural_frequency: float    # |s| (rad/s)
    damping_ratio: float | None # -Re(s)/|s|; None for s = 0


@dataclass(frozen=True)
class Stability:
    eigenvalues: np.ndarray     # essential eigenvalues, sorted (Re descending, then Im)
    states: tuple[str, ...]     # the states they belong to (after deflation)
    neutral: tuple[str, ...]    # deflated states (zero modes by structure)
    verdict: str
    negative_stiffness: bool

    @property
    def modes(self) -> tuple[Mode, ...]:
        return modes_of(self.eigenvalues)


def modes_of(eigenvalues: np.ndarray) -> tuple[Mode, ...]:
    """Each eigenvalue's natural frequency |s| and damping ratio -Re(s)/|s|."""
    return tuple(Mode(complex(s), float(abs(s)), float(-s.real / abs(s)) if abs(s) > 0 else None)
                 for s in eigenvalues)


def essential(A: np.ndarray, states) -> tuple[np.ndarray, list[str], list[str]]:
    """A without its structurally zero rows and columns (repeatedly), and the states kept/dropped."""
    keep = list(range(A.shape[0]))
    scale = np.max(np.abs(A), initial=0.0)
    small = np.abs(A) <= STRUCTURAL_ZERO * scale
    changed = True
    while changed:
        changed = False
        for k in list(keep):
            rest = [j for j in keep if j != k]
            if all(small[k, rest]) and small[k, k] or all(small[rest, k]) and small[k, k]:
                keep.remove(k)
                changed = True
    dropped = [states[k] for k in range(A.shape[0]) if k not in keep]
    return A[np.ix_(keep, keep)], [states[k] for k in keep], dropped


def sorted_eigenvalues(A: np.ndarray) -> np.ndarray:
    values = np.linalg.eigvals(A).astype(complex) if A.size else np.zeros(0, dtype=complex)
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    noise = ROUNDING * rounding_scale(A)   # so the same model prints the same eigenvalues everywhere
    values = np.where(np.abs(values.real) <= noise, 0.0, values.real) \
        + 1j * np.where(np.abs(values.imag) <= noise, 0.0, values.imag)
    # round away the last bits so conjugate pairs and ties sort the same on every machine
    real = np.round(values.real / (MARGIN * scale)) * MARGIN * scale
    order = np.lexsort((-values.imag, -real))
    return values[order]


def rounding_scale(A: np.ndarray) -> float:
    """The size eigenvalue errors of A scale with (backward-stable eigensolver: eps |A|)."""
    return max(1.0, A.shape[0] * np.max(np.abs(A), initial=0.0))


def stability(model: LinearModel) -> Stability:
    reduced, kept, dropped = essential(model.A, model.states)
    values = sorted_eigenvalues(reduced)
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    largest = np.max(values.real, initial=-np.inf)
    K = model.square_stiffness
    negative = bool(K is not None and K.size and np.min(np.linalg.eigvalsh((K + K.T) / 2)) < -MARGIN * np.max(np.abs(K)))
    if values.size and largest > MARGIN * scale:
        verdict = "unstable"
    elif values.size and largest < -MARGIN * scale:
        verdict = "asymptotically stable"
    elif negative:
        verdict = "gyroscopically stabilized"
    elif _energy_minimum(model, K):
        verdict = "stable"
    else:
        verdict = "marginally stable"
    return Stability(values, tuple(kept), tuple(dropped), verdict, negative)


def _energy_minimum(model: LinearModel, K: np.ndarray | None) -> bool:
    """Lagrange-Dirichlet: at rest, h conserved, no damping, K symmetric positive definite."""
    if not model.energy_conserved or K is None or not K.size or np.any(model.point.qd != 0):
        return False
    if model.square_stiffness.shape[1] != model.K.shape[1]:
        return False       # coordinates without a speed (nonholonomic): K is not V's Hessian
    scale = max(np.max(np.abs(K)), np.max(np.abs(model.C), initial=0.0))
    symmetric = np.allclose(K, K.T, atol=MARGIN * scale) and np.allclose(model.damping, 0, atol=MARGIN * scale)
    return symmetric and np.min(np.linalg.eigvalsh((K + K.T) / 2)) > MARGIN * scale


def on_imaginary_axis(values: np.ndarray) -> int:
    """How many of `values` lie on the imaginary axis (|Re s| within the verdict's margin)."""
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    return int(np.sum(np.abs(values.real) <= MARGIN * scale))


def unstable_count(values: np.ndarray) -> int:
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    return int(np.sum(values.real > MARGIN * scale))
