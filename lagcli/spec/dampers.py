"""The spec's dissipative elements: `dampers:` (linear dashpots) and `dissipation:` (Rayleigh).

    dampers:
      - {between: [A, B], damping: c}      # particles/bodies, or a particle and a fixed point
    dissipation: c*x_dot**2/2              # R(q, q', t); Q'_j = -dR/dq'_j

A damper's ends are written like a spring's (`between:`); lagcli/derive/dissipation.py
turns both into generalized forces.
"""
from __future__ import annotations

from typing import Any

from lagcli.spec import format as fmt
from lagcli.spec.reader import KeyPath
from lagcli.spec.types import Damper


def dissipation_fields(checker, top: dict) -> dict:
    """The `Spec` fields `dampers` and `dissipation` of the top-level table `top`."""
    return dict(
        dampers=checker.list_items(top, "dampers", lambda path, value: _damper(checker, path, value)),
        dissipation=checker.expr(("dissipation",), top["dissipation"]) if "dissipation" in top else None,
    )


def _damper(checker, path: KeyPath, value: Any) -> Damper | None:
    table = checker.table(path, value, fmt.DAMPER)
    if table is None:
        return None
    ends = checker.spring_ends(path + ("between",), table["between"]) if "between" in table else None
    damping = checker.expr(path + ("damping",), table["damping"]) if "damping" in table else None
    if ends is None or damping is None:
        return None
    return Damper(ends, damping, checker.raw.loc(path))
