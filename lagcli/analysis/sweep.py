"""Linearize along one variable (`--sweep v=START:STOP:COUNT`) and find where stability changes.

A critical value is where the number of essential eigenvalues with Re(s) > 0
changes between two neighbouring sweep values. With k the smaller of the two
counts, the k-th largest real part (0-based) is positive on one side and not on
the other, and is continuous in the variable: Brent's method (scipy's brentq)
finds its zero to `xtol`. A complex pair crossing the imaginary axis (a Hopf
point: the bicycle's weave speed) and a real eigenvalue crossing zero (its
capsize speed) are both found this way. Real parts within rounding of zero are
0 (`sorted_eigenvalues`) and count as the stable side, so an undamped system's
critical value (imaginary eigenvalues meeting at 0 and turning real) is found too.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lagcli.analysis.linearize import CompiledSystem, linearize
from lagcli.analysis.operating_point import Assignments, evaluate
from lagcli.analysis.stability import Stability, stability, unstable_count

_XTOL = 1e-13


@dataclass(frozen=True)
class SweepRange:
    name: str
    values: np.ndarray


def parse_sweep(text: str) -> SweepRange:
    """`v=0:10:101` -> 101 values from 0 to 10 (both ends included)."""
    from lagcli.run.options import parse_range

    name, start, stop, count = parse_range(text, "--sweep", 2, 100_000, example="v=0:10:101")
    return SweepRange(name, np.linspace(start, stop, count))


@dataclass(frozen=True)
class SweepPoint:
    value: float
    stability: Stability


@dataclass(frozen=True)
class Critical:
    value: float
    unstable_below: int     # unstable eigenvalues just below and just above
    unstable_above: int


@dataclass(frozen=True, eq=False)
class LinearizationSweep:
    """`System.linearize_sweep`: the stability at each value of `variable`, and the
    critical values found between them (when asked for)."""

    variable: str
    points: tuple[SweepPoint, ...]
    critical: tuple[Critical, ...]

    @property
    def values(self) -> np.ndarray:
        return np.array([p.value for p in self.points])

    @property
    def verdicts(self) -> tuple[str, ...]:
        return tuple(p.stability.verdict for p in self.points)

    @property
    def eigenvalues(self) -> tuple[np.ndarray, ...]:
        return tuple(p.stability.eigenvalues for p in self.points)

    def __repr__(self) -> str:
        found = "; ".join(f"critical {self.variable} = {c.value:.10g}" for c in self.critical)
        return f"<LinearizationSweep over {self.variable}: {len(self.points)} points" + (f"; {found}" if found else "") + ">"

    def _repr_html_(self) -> str:
        from html import escape

        from lagcli.analysis.wording import complex_text, number

        rows = "".join(f"<tr><td>{number(p.value)}</td><td>{escape(p.stability.verdict)}</td><td>"
                       + escape(", ".join(complex_text(s, 8) for s in p.stability.eigenvalues)) + "</td></tr>"
                       for p in self.points)
        critical = "".join(f"<p>critical {escape(self.variable)} = {c.value:.15g}: unstable eigenvalues "
                           f"{c.unstable_below} &#8594; {c.unstable_above}</p>" for c in self.critical)
        return (f"<div><table><tr><th>{escape(self.variable)}</th><th>verdict</th><th>eigenvalues</th></tr>"
                f"{rows}</table>{critical}</div>")


def sweep(system: CompiledSystem, at: Assignments, values, independent=()) -> list[SweepPoint]:
    return [SweepPoint(float(v), _stability_at(system, at, v, independent)) for v in values]


def _stability_at(system, at, value, independent) -> Stability:
    return stability(linearize(system, evaluate(system.derivation, at, value), independent))


def critical_values(system: CompiledSystem, at: Assignments, points: list[SweepPoint],
                    independent=()) -> list[Critical]:
    from scipy.optimize import brentq

    found = []
    for left, right in zip(points, points[1:]):
        below, above = unstable_count(left.stability.eigenvalues), unstable_count(right.stability.eigenvalues)
        if below == above:
            continue
        rank = min(below, above)

        def real_part(v, rank=rank):
            values = np.sort(_stability_at(system, at, v, independent).eigenvalues.real)[::-1]
            value = values[rank] if rank < values.size else -1.0
            return value if value != 0 else -1e-300   # on the axis counts as the stable side

        root = brentq(real_part, left.value, right.value, xtol=_XTOL, rtol=4 * np.finfo(float).eps)
        found.append(Critical(float(root), below, above))
    return found
