"""`lagcli generate --lang python`: one self-contained module needing only numpy.

The module's interface is docs/design.md ("Generated Python module"). Scalar code
uses `math` on Python floats (fast for small systems); numpy is used for the
arrays it returns and `numpy.linalg.solve`; scipy only inside `simulate`. The
module never imports sympy.
"""
from __future__ import annotations

from sympy.printing.pycode import PythonCodePrinter

from lagcli.derive.result import Derivation
from lagcli.emit import codegen
from lagcli.emit.templates import render


class PythonPrinter(codegen.SlotPrinter, PythonCodePrinter):
    """Python 3 on floats: `math` functions imported by name (`from math import sin`)."""

    power_format = "{base}**{exp}"

    def __init__(self, table: dict):
        super().__init__(table, {"fully_qualified_modules": False, "standard": "python3"})

    def _print_sign(self, expr):
        """1.0, -1.0 or 0.0 (0.0 for NaN too, as in the generated C)."""
        x = self._print(expr.args[0])
        return f"(1.0 if ({x}) > 0 else (-1.0 if ({x}) < 0 else 0.0))"

    def sqrt_name(self) -> str:
        return self._module_format("math.sqrt")

    def import_lines(self) -> list[str]:
        return [f"from {module} import {', '.join(sorted(names))}"
                for module, names in sorted(self.module_imports.items())]


def literal(value) -> str:
    """A Python literal for a number or string of the interface."""
    if isinstance(value, str):
        return repr(value)
    value = float(value)
    return repr(value) if value == value and abs(value) != float("inf") else f"float({str(value)!r})"


def python_module(d: Derivation) -> str:
    """The text of the generated module for `d`."""
    outputs = codegen.collect(d)
    reduced = codegen.eliminate(outputs)
    printer = PythonPrinter(codegen.slots(d, reduced))
    blocks = _blocks(reduced, printer)
    n, m = d.n, len(d.constraints)
    system = blocks["system"]
    return render(
        "python/module.py.jinja",
        i=codegen.interface(d, outputs), n=n, m=m, literal=literal,
        imports=printer.import_lines(), blocks=blocks,
        mass_rows=_rows(blocks["mass"].values["mass_matrix"], n),
        constraint_rows=_rows(blocks["constraint_matrix"].values["constraint_matrix"], n),
        system_rows=_augmented_rows(system, n, m),
        system_rhs=system.values["forcing"] + system.values["constraint_bias"],
        stabilization=_stabilization(blocks, outputs, n),
        residual=_residual(blocks["invariants"]),
    )


def _blocks(reduced: codegen.Reduced, printer: PythonPrinter) -> dict:
    """One printed block per function body (groups of an unconstrained system are empty)."""
    system = codegen.print_block(reduced, printer, ("mass_matrix", "forcing", "constraint_matrix",
                                                    "constraint_bias"), negated=("constraint_matrix",))
    position = ("constraint_velocity", "constraint_position")
    return {
        "mass": codegen.print_block(reduced, printer, ("mass_matrix",)),
        "forcing": codegen.print_block(reduced, printer, ("forcing",)),
        "constraint_matrix": codegen.print_block(reduced, printer, ("constraint_matrix",)),
        "constraint_bias": codegen.print_block(reduced, printer, ("constraint_bias",)),
        "system": system,
        "stabilization": codegen.print_block(reduced, printer, position, exclude=system),
        "invariants": codegen.print_block(reduced, printer, ("invariants",) + position),
    }


def _rows(values: tuple[str, ...], cols: int) -> list[str]:
    """Row-major printed entries -> one '[a, b, ...]' string per row."""
    return [f"[{', '.join(values[r * cols:(r + 1) * cols])}]" for r in range(len(values) // cols)] \
        if cols else []


def _augmented_rows(system: codegen.Block, n: int, m: int) -> list[str]:
    """Rows of [[M, -A^T], [A, 0]] as printed lists."""
    M = system.values["mass_matrix"]
    if not m:
        return _rows(M, n)
    A, negA = system.values["constraint_matrix"], system.negated["constraint_matrix"]
    top = [M[i * n:(i + 1) * n] + tuple(negA[j * n + i] for j in range(m)) for i in range(n)]
    bottom = [A[j * n:(j + 1) * n] + ("0",) * m for j in range(m)]
    return [f"[{', '.join(row)}]" for row in top + bottom]


def _stabilization(blocks: dict, outputs: codegen.Outputs, n: int) -> list[str]:
    """Statements r[n + j] -= 2 alpha (A q' + d)_j + beta^2 phi_j (phi for holonomic rows)."""
    values = blocks["stabilization"].values
    phi = dict(zip(outputs.holonomic_rows, values["constraint_position"]))
    lines = []
    for j, w in enumerate(values["constraint_velocity"]):
        term = f"2.0*alpha*({w})" + (f" + beta*beta*({phi[j]})" if j in phi else "")
        lines.append(f"r[{n + j}] -= {term}")
    return lines


def _residual(block: codegen.Block) -> list[str]:
    """abs() of every velocity-level and holonomic position-level constraint value."""
    values = block.values
    return [f"abs({v})" for v in values.get("constraint_position", ()) + values.get("constraint_velocity", ())]
