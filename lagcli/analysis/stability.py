"""Eigenvalues, modes and a stability verdict of a linear model (docs/analysis.md,
"Stability verdict": each word is defined there, with its theorem).

Zero modes that are there by structure are deflated before the eigenvalues are
computed: a coordinate nothing depends on (column of A zero: x, y, the spin angle of
a rolling disc), a speed whose rate is zero to first order (row zero), and a
direction of the coordinates along which nothing in the equations changes, anywhere
(`LinearModel.invariant`: the gantry crane's trolley and load moving together). Such
a direction is made a coordinate of its own first (A -> T^-1 A T, T = its basis
completed by unit vectors), and is then a zero column like the others. For a column
or row that is zero, det(A - s I) = -s det(A' - s I), so the other eigenvalues are
exactly those of A'. What is left are the "essential" eigenvalues; the deflated
states are the neutral modes, and `jordan.drifting_states` says which states of the
whole model grow linearly with time through them (x = x_dot t).

The verdict is on the essential eigenvalues (Lyapunov's indirect method; tolerance
relative to the largest eigenvalue), in this order:
  no verdict                  the point is no equilibrium or steady motion: the rates of
                              the essential states are not 0 there
  unstable                    some Re(s) > 0
  linearly unstable           none to the right, but one on the imaginary axis is repeated
                              with fewer eigenvectors (`jordan.defective`): the linear
                              solutions grow like t; the nonlinear terms decide
  asymptotically stable       every Re(s) < 0
  neutral                     every mode is neutral by structure (none left)
  stable                      at rest, h = T2 - T0 + V conserved, no damping, K of the
                              essential coordinates positive definite: a strict minimum of
                              h (Lagrange-Dirichlet)
  gyroscopically stabilized   at an equilibrium or steady motion, no damping, all on the
                              axis with their eigenvectors, although K of the essential
                              coordinates has a negative eigenvalue (Kelvin-Tait-Chetaev:
                              any damping destroys it)
  marginally stable           otherwise: all on or left of the axis, each on it with its
                              own eigenvectors; the linear model does not decide
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lagcli.analysis.jordan import clustered, defective, drifting_states
from lagcli.analysis.linearize import LinearModel
from lagcli.analysis.structure import STEADY, StructureBasis, structure_basis

STRUCTURAL_ZERO = 1e-12     # |entry| <= this * max|A| counts as a structural zero
MARGIN = 1e-9               # |Re s| <= this * max(1, max|s|) counts as on the imaginary axis
ROUNDING = 1000 * np.finfo(float).eps  # parts of s below this * rounding_scale(A) are noise: set to 0

NOT_AT_REST = "no verdict"


@dataclass(frozen=True)
class Mode:
    eigenvalue: complex
    natural_frequency: float    # |s| (rad/s)
    damping_ratio: float | None # -Re(s)/|s|; None for s = 0
    kind: str = ""              # what it does: `mode_kind`


@dataclass(frozen=True)
class Stability:
    eigenvalues: np.ndarray     # essential eigenvalues, sorted (Re descending, then Im)
    states: tuple[str, ...]     # the states they belong to (after deflation)
    neutral: tuple[str, ...]    # deflated states (zero modes by structure)
    verdict: str
    negative_stiffness: bool
    evidence: str = ""          # why: the numbers the verdict rests on
    drift: tuple[str, ...] = () # states growing linearly with time (s = 0 defective)
    defective: tuple[complex, ...] = ()   # essential eigenvalues on the axis with too few eigenvectors

    @property
    def modes(self) -> tuple[Mode, ...]:
        return modes_of(self.eigenvalues, self.defective)


def mode_kind(s: complex, scale: float, defective=()) -> str:
    """oscillation (on the axis, its own eigenvectors), growing oscillation (on the axis,
    defective), neutral (0), drift (0, defective), growing/decaying spiral (complex),
    growing/decaying (real)."""
    repeated = any(abs(s.imag - abs(d.imag)) <= MARGIN * scale or abs(s.imag + abs(d.imag)) <= MARGIN * scale
                   for d in defective)
    if abs(s.real) <= MARGIN * scale:
        if abs(s.imag) <= MARGIN * scale:
            return "drift" if repeated else "neutral"
        return "growing oscillation" if repeated else "oscillation"
    side = "growing" if s.real > 0 else "decaying"
    return f"{side} spiral" if s.imag != 0 else side


def modes_of(eigenvalues: np.ndarray, defective=()) -> tuple[Mode, ...]:
    """Each eigenvalue's natural frequency |s|, damping ratio -Re(s)/|s| and kind."""
    scale = max(1.0, np.max(np.abs(eigenvalues), initial=0.0))
    return tuple(Mode(complex(s), float(abs(s)), float(-s.real / abs(s)) if abs(s) > 0 else None,
                      mode_kind(complex(s), scale, defective))
                 for s in eigenvalues)


def oscillation_frequencies(modes) -> tuple[float, ...]:
    """Small-oscillation frequencies (rad/s): |s| of each pair on the imaginary axis with
    its own eigenvectors (never of a spiral, a real or a defective eigenvalue)."""
    return tuple(sorted({round(m.natural_frequency, 12) for m in modes
                         if m.kind == "oscillation" and m.eigenvalue.imag > 0}))


def essential(A: np.ndarray, states, generic: np.ndarray | None = None) -> tuple[np.ndarray, list[str], list[str]]:
    """A without its structurally zero rows and columns (repeatedly), and the states kept/dropped.
    An entry is a structural zero when it is zero in A and, given, in `generic` (A with the
    parameters scaled: `linearize.generic_state_matrix`), so a zero that only a coincidence
    of the parameters' values makes (a stiffness vanishing at a bifurcation) stays."""
    keep = list(range(A.shape[0]))
    scale = np.max(np.abs(A), initial=0.0)
    small = np.abs(A) <= STRUCTURAL_ZERO * scale
    if generic is not None and generic.shape == A.shape:
        small &= np.abs(generic) <= STRUCTURAL_ZERO * max(scale, np.max(np.abs(generic), initial=0.0))
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
    noise = ROUNDING * rounding_scale(A)   # so the same model prints the same eigenvalues everywhere
    values = np.where(np.abs(values.real) <= noise, 0.0, values.real) \
        + 1j * np.where(np.abs(values.imag) <= noise, 0.0, values.imag)
    return in_order(values)


def in_order(values: np.ndarray) -> np.ndarray:
    """Re descending, then Im descending; the last bits rounded away first so conjugate
    pairs and ties sort the same on every machine."""
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    real = np.round(values.real / (MARGIN * scale)) * MARGIN * scale
    return values[np.lexsort((-values.imag, -real))]


def rounding_scale(A: np.ndarray) -> float:
    """The size eigenvalue errors of A scale with (backward-stable eigensolver: eps |A|)."""
    return max(1.0, A.shape[0] * np.max(np.abs(A), initial=0.0))


def stability(model: LinearModel) -> Stability:
    basis = structure_basis(model)
    reduced, kept, dropped = essential(basis.A, basis.states, basis.generic_A)
    values = in_order(clustered(reduced, sorted_eigenvalues(reduced)))
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    bad = defective(reduced, values, lambda s: abs(s.real) <= MARGIN * scale)
    K = basis.stiffness(kept)
    negative = bool(K is not None and K.size and _smallest(K) < -MARGIN * max(1.0, np.max(np.abs(K))))
    verdict, evidence = _verdict(model, basis, kept, values, bad, K)
    drift = drifting_states(model.A, model.states, sorted_eigenvalues(model.A))
    return Stability(values, tuple(kept), tuple(dropped), verdict, negative, evidence, drift, bad)


def _verdict(model, basis: StructureBasis, kept, values, bad, K) -> tuple[str, str]:
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    rates = basis.rates(model, kept)
    if rates:
        return NOT_AT_REST, "not an equilibrium or steady motion: " + ", ".join(
            f"{name} = {value:.10g}" for name, value in rates) + "; Lyapunov's indirect method needs one"
    largest = np.max(values.real, initial=-np.inf)
    axis = int(np.sum(np.abs(values.real) <= MARGIN * scale))
    if values.size and largest > MARGIN * scale:
        count = int(np.sum(values.real > MARGIN * scale))
        return "unstable", f"{count} of {values.size} eigenvalues to the right of the imaginary axis"
    if bad:
        return "linearly unstable", ("repeated on the imaginary axis with fewer eigenvectors: "
                                     + ", ".join(_pair(s) for s in bad)
                                     + "; the linear solutions grow like t, the nonlinear terms decide")
    if values.size and largest < -MARGIN * scale:
        return "asymptotically stable", f"all {values.size} eigenvalues left of the imaginary axis"
    if not values.size:
        return "neutral", "every mode is neutral by structure"
    undamped = _undamped(model)
    if (undamped and basis.symmetric_stiffness and _at_rest(model) and model.energy_conserved
            and K is not None and K.size and _smallest(K) > MARGIN * _size(K)):
        return "stable", (f"at rest on a strict minimum of the conserved h = T2 - T0 + V: K of "
                          f"{', '.join(basis.coordinates_of(kept))} positive definite, smallest eigenvalue "
                          f"{_smallest(K):.6g} (Lagrange-Dirichlet)")
    if (model.energy_conserved and K is not None and K.size and _smallest(K) < -MARGIN * _size(K)
            and np.max(np.abs(basis.gyroscopic), initial=0.0) > MARGIN * _size(basis.C)):
        negative = int(np.sum(np.linalg.eigvalsh((K + K.T) / 2) < -MARGIN * _size(K)))
        return "gyroscopically stabilized", (
            f"K of {', '.join(basis.coordinates_of(kept))} has {negative} negative eigenvalue"
            f"{'s' if negative > 1 else ''} (smallest {_smallest(K):.6g}), yet the gyroscopic G keeps all "
            f"{values.size} eigenvalues on the imaginary axis, each with its own eigenvectors "
            "(Kelvin-Tait-Chetaev: damping would destroy it)")
    where = (f"all {values.size} eigenvalues on the imaginary axis" if axis == values.size
             else f"{axis} of {values.size} eigenvalues on the imaginary axis, the others to its left")
    return "marginally stable", f"{where}, each with its own eigenvectors: the linear model does not decide"


def _pair(s: complex) -> str:
    return "0" if s == 0 else f"+-{abs(s.imag):.10g}i"


def _smallest(K: np.ndarray) -> float:
    return float(np.min(np.linalg.eigvalsh((K + K.T) / 2)))


def _size(K: np.ndarray) -> float:
    return max(1.0, float(np.max(np.abs(K), initial=0.0)))


def _at_rest(model: LinearModel) -> bool:
    return not np.any(model.point.qd != 0)


def _undamped(model: LinearModel) -> bool:
    """No damping: C's symmetric part is 0."""
    scale = max(np.max(np.abs(model.C), initial=0.0), np.max(np.abs(model.K), initial=0.0), 1e-300)
    return bool(np.allclose(model.damping, 0, atol=MARGIN * scale))


def unstable_count(values: np.ndarray) -> int:
    scale = max(1.0, np.max(np.abs(values), initial=0.0))
    return int(np.sum(values.real > MARGIN * scale))
