"""Every expression a generated module evaluates, grouped by use (`Outputs`).

`collect(d, layout)` gathers them from a `Derivation` (the invariants in the order of the
run interface's columns), `tidied` tidies each small one
(`lagcli.render.tidy`); the groups are then reduced by one CSE (`lagcli.targets.cse`).
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import sympy as sp

from lagcli.derive.result import Derivation
from lagcli.render.shapes import Shapes
from lagcli.render.tidy import tidy_expression
from lagcli.interface import Layout


@dataclass(frozen=True)
class Outputs:
    """Every expression a generated module evaluates, grouped by use (flat, row-major).

    mass_matrix          n*n   M (upper triangle mirrored: exactly symmetric)
    forcing              n     F, with M q'' = F + A^T lambda
    constraint_matrix    m*n   A
    constraint_bias      m     b = -(A' q' + d')
    constraint_velocity  m     A q' + d        (Baumgarte damping, residual)
    constraint_position  h     phi_j of the holonomic rows (Baumgarte, residual)
    invariants           k     energy T + V, the Jacobi integral (when it exists),
                               p_<q> for each ignorable coordinate
    """

    mass_matrix: tuple
    forcing: tuple
    constraint_matrix: tuple
    constraint_bias: tuple
    constraint_velocity: tuple
    constraint_position: tuple
    invariants: tuple
    invariant_names: tuple[str, ...]
    holonomic_rows: tuple[int, ...]   # row index j of each constraint_position entry

    def groups(self) -> dict[str, tuple]:
        return {name: getattr(self, name) for name in GROUPS}


GROUPS = ("mass_matrix", "forcing", "constraint_matrix", "constraint_bias",
          "constraint_velocity", "constraint_position", "invariants")


def collect(d: Derivation, layout: Layout, tidy: bool = True) -> Outputs:
    """The expressions of `d` that generated code evaluates (see `Outputs`; `layout`: its
    run interface), each small one simplified when that lowers its operation count
    (`tidied`) unless `tidy` is False."""
    outputs = _collect(d, layout)
    return tidied(outputs, d.model.qd) if tidy else outputs


def tidied(outputs: Outputs, velocities) -> Outputs:
    """`outputs` with every expression through `tidy_expression`, each distinct one once
    and each *shape* once (`lagcli.render.shapes`: a chain's mass matrix entries
    l_i l_j (m_j + ... + m_n) cos(q_i - q_j) differ only in their symbols; the result for
    one is renamed for the others, which is what tidying them gives, tests/test_shapes.py)."""
    cache: dict = {}
    by_shape = Shapes(lambda e: tidy_expression(e, velocities, cache), marked=velocities)
    return replace(outputs, **{name: tuple(by_shape(sp.sympify(e)) for e in exprs)
                               for name, exprs in outputs.groups().items()})


def _collect(d: Derivation, layout: Layout) -> Outputs:
    n, qd = d.n, d.model.qd
    M = d.mass_matrix
    mass = tuple(M[min(i, j), max(i, j)] for i in range(n) for j in range(n))
    rows = d.constraints
    velocity = tuple(sum((a * v for a, v in zip(r.a, qd)), sp.S.Zero) + r.d for r in rows)
    holonomic = tuple(j for j, r in enumerate(rows) if r.kind == "holonomic")
    names, invariants = invariant_columns(d, layout)
    return Outputs(
        mass_matrix=mass,
        forcing=tuple(d.forcing),
        constraint_matrix=tuple(d.constraint_matrix),
        constraint_bias=tuple(d.constraint_bias),
        constraint_velocity=velocity,
        constraint_position=tuple(rows[j].expr for j in holonomic),
        invariants=invariants,
        invariant_names=names,
        holonomic_rows=holonomic,
    )


def invariant_columns(d: Derivation, layout: Layout) -> tuple[tuple[str, ...], tuple]:
    """The CSV invariant columns that have an expression (all but the residual), in the
    layout's order, and their expressions."""
    momenta = {c.name: c.expr for c in d.conserved if c.kind == "momentum"}
    expression = {"energy": lambda c: d.energy, "jacobi": lambda c: d.jacobi_integral,
                  "momentum": lambda c: momenta[c.name]}
    columns = [c for c in layout.invariants if c.kind in expression]
    return tuple(c.name for c in columns), tuple(expression[c.kind](c) for c in columns)
