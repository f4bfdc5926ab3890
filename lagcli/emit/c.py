"""`lagcli generate --lang c`: `<name>.h`, `<name>.c` (C99 + libm) and the driver `<name>_main.c`.

The interface is docs/design.md ("Generated C"). The right-hand side assembles the
augmented system [[M, -A^T], [A, 0]] [q''; lambda] = [F; b - 2 alpha (A q' + d) -
beta^2 phi] in fixed-size arrays on the stack and solves it by LU with partial
pivoting in place: no allocation. Everything compiles with
`cc -std=c99 -O2 -Wall -Wextra -Werror -pedantic ... -lm`.

The printer never emits the non-C99 `M_PI`-style macros: constants print as
21-digit literals, small integer powers as products.
"""
from __future__ import annotations

import math

from sympy.printing.c import C99CodePrinter

from lagcli.derive.result import Derivation
from lagcli.emit import codegen
from lagcli.emit.templates import render
from lagcli.simulate.options import CONSTRAINT_TOLERANCE

INTEGRATOR_PREFIX = "lagcli_ode"     # names of the integrator fragment: lagcli_ode_integrate, ...


class CPrinter(codegen.SlotPrinter, C99CodePrinter):
    """C99 doubles: math.h functions, no math macros (M_PI is not C99)."""

    power_format = "pow({base}, {exp})"

    def __init__(self, table: dict):
        super().__init__(table, {"math_macros": {}})

    def _print_sign(self, expr):
        """A double (sympy's `(x > 0) - (x < 0)` is an int: sign(x)/sign(y) would divide
        integers); 0 for 0 and NaN, like copysign-free C99 code should."""
        x = self._print(expr.args[0])
        return f"(({x}) > 0 ? 1.0 : (({x}) < 0 ? -1.0 : 0.0))"


def literal(value) -> str:
    """A C double literal (C99 has no literal for inf or nan: HUGE_VAL and NAN from math.h)."""
    value = float(value)
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "HUGE_VAL" if value > 0 else "(-HUGE_VAL)"
    text = repr(value)
    return text if any(c in text for c in ".e") else text + ".0"


def c_files(d: Derivation) -> dict[str, str]:
    """{file name: text} of `<name>.h`, `<name>.c` and `<name>_main.c`."""
    context = c_context(d)
    name = d.model.name
    return {
        f"{name}.h": render("c/model.h.jinja", **context),
        f"{name}.c": render("c/model.c.jinja", **context),
        f"{name}_main.c": render("c/main.c.jinja", **context),
    }


def c_context(d: Derivation) -> dict:
    """Everything the C templates need, pre-printed."""
    outputs = codegen.collect(d)
    reduced = codegen.eliminate(outputs)
    printer = CPrinter(codegen.slots(d, reduced))
    n, m = d.n, len(d.constraints)
    nsys = n + m
    system = codegen.print_block(reduced, printer, ("mass_matrix", "forcing", "constraint_matrix",
                                                    "constraint_bias"), negated=("constraint_matrix",))
    position = ("constraint_velocity", "constraint_position")
    stabilization = codegen.print_block(reduced, printer, position, exclude=system)
    invariants = codegen.print_block(reduced, printer, ("invariants",) + position)
    name = d.model.name
    return dict(
        i=codegen.interface(d, outputs), prefix=name, PREFIX=name.upper(), n=n, m=m, nsys=nsys,
        literal=literal, integrator_prefix=INTEGRATOR_PREFIX, constraint_tolerance=literal(CONSTRAINT_TOLERANCE),
        mass=codegen.print_block(reduced, printer, ("mass_matrix",)),
        forcing=codegen.print_block(reduced, printer, ("forcing",)),
        system=system, system_entries=_augmented_entries(system, n, m),
        stabilization=stabilization, stabilization_lines=_stabilization(stabilization, outputs, n),
        invariants=invariants, residual=_residual(invariants),
    )


def _augmented_entries(system: codegen.Block, n: int, m: int) -> list[str]:
    """Row-major entries of K = [[M, -A^T], [A, 0]] and of r = [F; b], as printed code."""
    M, F = system.values["mass_matrix"], system.values["forcing"]
    A, negA = system.values["constraint_matrix"], system.negated["constraint_matrix"]
    rows = [list(M[i * n:(i + 1) * n]) + [negA[j * n + i] for j in range(m)] for i in range(n)]
    rows += [list(A[j * n:(j + 1) * n]) + ["0"] * m for j in range(m)]
    return [code for row in rows for code in row]


def _stabilization(block: codegen.Block, outputs: codegen.Outputs, n: int) -> list[str]:
    """Statements r[n + j] -= 2 alpha (A q' + d)_j + beta^2 phi_j (phi for holonomic rows)."""
    phi = dict(zip(outputs.holonomic_rows, block.values["constraint_position"]))
    lines = []
    for j, w in enumerate(block.values["constraint_velocity"]):
        term = f"2.0*alpha*({w})" + (f" + beta*beta*({phi[j]})" if j in phi else "")
        lines.append(f"r[{n + j}] -= {term};")
    return lines


def _residual(block: codegen.Block) -> list[str]:
    values = block.values
    return list(values["constraint_position"] + values["constraint_velocity"])

