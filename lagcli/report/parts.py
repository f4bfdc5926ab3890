"""The derivation's parts as notebook objects: `system.parts.mass_matrix` and friends.

    >>> system.parts.mass_matrix           # a readable repr, in the spec language
    M = [[m, 0], [0, m]]
    >>> system.parts.mass_matrix.value     # the sympy object itself
    >>> system.parts.mass_matrix           # in Jupyter: LaTeX (_repr_latex_), M = \\begin{bmatrix}...

Each `Part` holds the sympy value from `lagcli.derive.result.Derivation` (nothing is
recomputed) and prints it with lagcli's own printers: the LaTeX one of the reports
(the spec's `latex:` names, multipliers as lambda_name) and the spec-language one
of the JSON report (`q_dot` names, parses back). `system.parts` lists what exists.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

# name -> (symbol in LaTeX, symbol in text, what it is)
PARTS = {
    "kinetic_energy": ("T", "T", "kinetic energy"),
    "potential_energy": ("V", "V", "potential energy"),
    "lagrangian": ("L", "L", "Lagrangian L = T - V"),
    "energy": ("E", "E", "total energy T + V"),
    "mass_matrix": ("M", "M", "mass matrix: T2 = q'^T M q' / 2"),
    "forcing": ("F", "F", "forcing: M q'' = F + A^T lambda"),
    "generalized_forces": ("Q", "Q", "generalized forces by virtual work"),
    "constraint_matrix": ("A", "A", "constraint matrix: A q' + d = 0"),
    "constraint_bias": ("b", "b", "constraint bias: A q'' = b"),
    "jacobi_integral": ("h", "h", "Jacobi integral h = T2 - T0 + V"),
    "equations": ("", "", "equations of motion (lhs = sum_j lambda_j a_ji)"),
    "constraints": ("", "", "constraints (each = 0)"),
}
_FIELDS = {"kinetic_energy": "T", "potential_energy": "V", "lagrangian": "L"}


@dataclass(frozen=True)
class Part:
    name: str
    what: str
    value: object             # sympy Expr, ImmutableMatrix, or a tuple of (lhs, rhs) pairs
    latex: str                # LaTeX, without the $$ delimiters
    text: str                 # spec language

    def _repr_latex_(self) -> str:
        return f"$${self.latex}$$"

    def __repr__(self) -> str:
        return self.text


class Parts:
    """The parts of one derivation (see the module docstring); made on first access."""

    def __init__(self, derivation):
        self._d = derivation
        self._made: dict[str, Part] = {}

    def __dir__(self):
        return [name for name in PARTS if self._exists(name)]

    def __repr__(self) -> str:
        return "parts: " + ", ".join(dir(self))

    def __getattr__(self, name: str) -> Part:
        if name.startswith("_") or name not in PARTS:
            raise AttributeError(f"no part {name!r}; parts are: {', '.join(dir(self))}")
        if not self._exists(name):
            raise AttributeError(f"{self._d.model.name} has no {PARTS[name][2]}")
        if name not in self._made:
            self._made[name] = self._part(name)
        return self._made[name]

    def _exists(self, name: str) -> bool:
        d = self._d
        if name in ("constraint_matrix", "constraint_bias", "constraints"):
            return bool(d.constraints)
        return name != "jacobi_integral" or d.jacobi_integral is not None

    def _part(self, name: str) -> Part:
        from lagcli.report.latex import latex_printer
        from lagcli.render.spec_printer import spec_str

        d, (tex_symbol, text_symbol, what) = self._d, PARTS[name]
        printer = latex_printer(d)
        if name in ("equations", "constraints"):
            pairs = (tuple((e.lhs, e.rhs) for e in d.equations) if name == "equations"
                     else tuple((c.expr, sp.S.Zero) for c in d.constraints))
            latex = aligned(printer, pairs)
            text = "\n".join(f"{spec_str(lhs)} = {spec_str(rhs)}" for lhs, rhs in pairs)
            return Part(name, what, pairs, latex, text)
        value = getattr(d, _FIELDS.get(name, name))
        if isinstance(value, sp.MatrixBase):
            rows = ("[" + ", ".join(spec_str(x) for x in row) + "]" for row in value.tolist())
            text = f"{text_symbol} = [{', '.join(rows)}]"
        else:
            text = f"{text_symbol} = {spec_str(value)}"
        return Part(name, what, value, f"{tex_symbol} = {printer.doprint(value)}", text)


def aligned(printer, pairs) -> str:
    """`lhs &= rhs` rows of (lhs, rhs) pairs in an aligned block."""
    rows = (f"{printer.doprint(lhs)} &= {printer.doprint(rhs)}" for lhs, rhs in pairs)
    return r"\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}"
