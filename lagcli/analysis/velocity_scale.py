"""Judging a velocity repair in the spec's scale (issue 25).

A least-squares repair always returns *some* velocities; whether they are an answer
depends on the system. Velocities of different coordinates have different units
(m/s, rad/s), so they are compared through the kinetic energy, which has one:

    E      = max(T(q0, q'_given), T(q0, q'_nearest))      T(q0, v) = v' M(q0) v / 2
    v_k    = sqrt(2 E / M_kk(q0))                        the natural velocity of q_k

q'_nearest are the given velocities moved onto the constraint rows as little as
possible (all of them free): the velocities the rows allow near the given state.
v_k is the speed q_k alone would have with the state's kinetic energy (sqrt(g/l)-like
for a pendulum started with the energy of a swing). Two rules follow:

- a velocity solved for may change by at most `NATURAL_FACTOR` times its natural
  velocity: an ill-conditioned row (a wheel upright to 1e-10 rad, its spin axis
  barely moving the contact) would otherwise "solve" a spin of 1e13 rad/s;
- when nothing was overridden for the run (no --init, no --set), the spec's own
  `initial:` velocities may be moved by at most `ROUNDING` of the scale
  (sqrt(T(change) / E)): a few mm/s on a wheel rolling at 1 m/s is a rounded value,
  a reversed direction is a wrong state, refused with its rows named.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NATURAL_FACTOR = 10.0    # |change of a solved velocity| <= this * its natural velocity
ROUNDING = 0.1           # the spec's own velocities move by at most this fraction of the scale


@dataclass(frozen=True)
class VelocityScale:
    """The kinetic-energy scale E of the given state and M(q0) (see the module's doc)."""

    mass_matrix: np.ndarray
    energy: float

    @classmethod
    def of(cls, mass_matrix, given, rows, residual) -> "VelocityScale":
        """`given` velocities, `rows` A(q0) and their `residual` A q' + d."""
        nearest = given - np.linalg.lstsq(rows, residual, rcond=None)[0]
        M = np.asarray(mass_matrix, dtype=float)
        energies = [e for e in (_kinetic(M, given), _kinetic(M, nearest)) if np.isfinite(e)]
        return cls(M, max(energies, default=0.0))

    def natural(self) -> np.ndarray:
        """v_k = sqrt(2 E / M_kk); infinite where M_kk is not positive (no scale there)."""
        diagonal = np.diag(self.mass_matrix)
        with np.errstate(divide="ignore", invalid="ignore"):
            speed = np.sqrt(2.0 * self.energy / diagonal)
        return np.where((diagonal > 0) & np.isfinite(speed) & (self.energy > 0), speed, np.inf)

    def too_fast(self, change, free) -> list[tuple[int, float, float]]:
        """(k, change_k, v_k) for each free velocity whose change exceeds NATURAL_FACTOR v_k."""
        natural = self.natural()
        return [(k, float(change[k]), float(natural[k])) for k in free
                if not abs(change[k]) <= NATURAL_FACTOR * natural[k]]

    def relative(self, change) -> float:
        """sqrt(T(change) / E): the size of a change in the scale of the state (0 without one)."""
        if not self.energy > 0:
            return 0.0
        energy = _kinetic(self.mass_matrix, change)
        return float(np.sqrt(max(energy, 0.0) / self.energy)) if np.isfinite(energy) else np.inf


def _kinetic(M: np.ndarray, v: np.ndarray) -> float:
    with np.errstate(all="ignore"):
        return 0.5 * float(v @ M @ v)
