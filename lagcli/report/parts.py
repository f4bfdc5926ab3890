"""The derivation's parts as notebook objects: `system.parts.mass_matrix` and friends.

    >>> system.parts.mass_matrix           # a readable repr, in the spec language
    M = [[m, 0], [0, m]]
    >>> system.parts.mass_matrix.value     # the sympy object itself
    >>> system.parts.mass_matrix           # in Jupyter: LaTeX (_repr_latex_), M = \\begin{pmatrix}...

Each `Part` holds the sympy value from `lagcli.derive.result.Derivation` (nothing is
recomputed) and shows what the reports show: the LaTeX rows of `lagcli derive --latex`
(the same tidying, q'' terms first, big expressions through the named quantities the
report defines, listed under the part) and the spec-language strings of the JSON
report (`q_dot` names, parse back). A part the report has no section for (the total
energy, the constraint bias) is printed from its value. `system.parts` lists what exists.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field

import sympy as sp

# name -> (symbol, what it is)
PARTS = {
    "kinetic_energy": ("T", "kinetic energy"),
    "potential_energy": ("V", "potential energy"),
    "lagrangian": ("L", "Lagrangian L = T - V"),
    "energy": ("E", "total energy T + V"),
    "mass_matrix": ("M", "mass matrix: T2 = q'^T M q' / 2"),
    "forcing": ("F", "forcing: M q'' = F + A^T lambda"),
    "generalized_forces": ("Q", "generalized forces by virtual work"),
    "constraint_matrix": ("A", "constraint matrix: A q' + d = 0"),
    "constraint_bias": ("b", "constraint bias: A q'' = b"),
    "jacobi_integral": ("h", "Jacobi integral h = T2 - T0 + V"),
    "equations": ("", "equations of motion (lhs = sum_j lambda_j a_ji)"),
    "constraints": ("", "constraints (each = 0)"),
}
_FIELDS = {"kinetic_energy": "T", "potential_energy": "V", "lagrangian": "L"}


@dataclass(frozen=True)
class Part:
    name: str
    what: str
    value: object             # sympy Expr, ImmutableMatrix, or a tuple of (lhs, rhs) pairs
    latex: str                # LaTeX, without the $$ delimiters
    text: str = field(repr=False)   # spec language
    rows: tuple[str, ...] = ()      # its rows of `lagcli derive --latex` (named quantities apart)

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
            raise AttributeError(f"{self._d.model.name} has no {PARTS[name][1]}")
        if name not in self._made:
            self._made[name] = self._part(name)
        return self._made[name]

    def _exists(self, name: str) -> bool:
        d = self._d
        if name in ("constraint_matrix", "constraint_bias", "constraints"):
            return bool(d.constraints)
        return name != "jacobi_integral" or d.jacobi_integral is not None

    @functools.cached_property
    def _report(self):
        """The LaTeX report's content and rows, and the JSON report's strings: made once."""
        from lagcli.report.latex import latex_content, latex_context
        from lagcli.report.content import report_content, spec_printer

        tex = latex_content(self._d)
        return tex, latex_context(self._d, tex), report_content(self._d, spec_printer())

    @functools.cached_property
    def _notation(self):
        """The report's letters as this derivation's reports show them (the user's names win)."""
        from lagcli.report.notation import notation_of

        return notation_of(self._d, also=("E", "A", "b"))

    def _part(self, name: str) -> Part:
        d = self._d
        if name == "equations":
            value = tuple((e.lhs, e.rhs) for e in d.equations)
        elif name == "constraints":
            value = tuple((c.expr, sp.S.Zero) for c in d.constraints)
        else:
            value = getattr(d, _FIELDS.get(name, name))
        latex_rows, text = self._rows(name, value)
        return Part(name, PARTS[name][1], value, self._with_named(latex_rows), text,
                    tuple(str(row) for row in latex_rows))

    def latex_of(self, *names: str) -> str:
        """The LaTeX rows of several parts in one aligned block (the named quantities they
        use listed once, after them): `System._repr_latex_` shows equations and constraints."""
        return self._with_named([row for name in names if self._exists(name)
                                 for row in self._rows(name, None)[0]])

    def _rows(self, name: str, value):
        latex_rows, text = self._shown(name)
        return (latex_rows, text) if latex_rows is not None else self._printed(name, value)

    def _shown(self, name: str):
        """(LaTeX rows, text) of a part as the reports show it, or (None, None)."""
        from lagcli.report.latex import matrix_block, rows

        tex, ctx, r = self._report
        n, letter = self._notation, PARTS[name][0]
        symbol = n.text(letter) if letter else letter
        coordinates = r["coordinates"]
        if name == "kinetic_energy":
            return ctx["energy_rows"], f"{symbol} = {r['kinetic_energy']['T']}"
        if name == "potential_energy":
            return rows(n.latex("V"), tex["potential_energy"]), f"{symbol} = {r['potential_energy']}"
        if name == "lagrangian":
            return (rows(n.latex("L"), tex["lagrangian"], f"{n.latex('T')} - {n.latex('V')}"),
                    f"{symbol} = {r['lagrangian']}")
        if name == "mass_matrix":
            block = ctx["mass_matrix"]
            return [block["matrix"]] if block["matrix"] else block["rows"], _matrix_text(symbol, r[name])
        if name == "generalized_forces":
            return ctx["force_rows"], _vector_text(symbol, [r[name][q] for q in coordinates])
        if name == "forcing":
            forcing = r["explicit_form"]["forcing"]
            return ([row for row in ctx["explicit_rows"] if row.startswith(n.latex("F"))],
                    _vector_text(symbol, [forcing[q] for q in coordinates]))
        if name == "constraint_matrix":
            block = matrix_block(n.latex("A"), [c["a"] for c in tex["constraints"]], "general")
            return ([block["matrix"]] if block["matrix"] else block["rows"],
                    _matrix_text(symbol, [c["a"] for c in r["constraints"]]))
        if name == "jacobi_integral":
            T, V = n.latex("T"), n.latex("V")
            return (rows(n.latex("h"), tex["jacobi_integral"], f"{T}_2 - {T}_0 + {V}"),
                    f"{symbol} = {r['jacobi_integral']}")
        if name == "equations":
            return ctx["equations"], "\n".join(f"{e['lhs']} = {e['rhs']}" for e in r["equations"])
        if name == "constraints":
            return ([c["rows"][0] for c in ctx["constraints"]],
                    "\n".join(f"{c['expr']} = 0" for c in r["constraints"]))
        return None, None

    def _printed(self, name: str, value):
        """A part the report has no section for (E, the constraint bias): its value with
        the report's tidying (`lagcli.report.display.Display`), E in the report's term order."""
        from lagcli.report.display import Display, signed_sum
        from lagcli.report.latex import latex_printer
        from lagcli.render.spec_printer import spec_str

        n, letter = self._notation, PARTS[name][0]
        shown, printer = Display(self._d), latex_printer(self._d)
        if name == "energy":
            terms = shown.energy
            return ([f"{n.latex('E')} &= {n.latex('T')} + {n.latex('V')} = {printer.tex_terms(terms)}"],
                    f"{n.text('E')} = {signed_sum(terms, spec_str)}")
        entries = [[shown.tidy(x) for x in row] for row in value.tolist()]
        tex = r" \\ ".join(" & ".join(printer.doprint(x) for x in row) for row in entries)
        return ([rf"{n.latex(letter)} = \begin{{pmatrix}} {tex} \end{{pmatrix}}"],
                _matrix_text(n.text(letter), [[spec_str(x) for x in row] for row in entries]))

    def _with_named(self, latex_rows: list[str]) -> str:
        """The rows in an aligned block, followed by the named quantities they use."""
        from lagcli.report.latex import named_rows_used

        _, ctx, _ = self._report
        named = named_rows_used(ctx["named"], " ".join(latex_rows))
        if named:
            latex_rows = [*latex_rows, r"&\text{where}", *named]
        return aligned_rows(latex_rows)


def aligned_rows(latex_rows: list[str]) -> str:
    """Rows of the LaTeX report (`label &= content`) in an aligned block (one row without
    an alignment point, such as a matrix, as it is)."""
    if len(latex_rows) == 1 and " &" not in str(latex_rows[0]).split(r"\begin{pmatrix}")[0]:
        return str(latex_rows[0])
    return r"\begin{aligned}" + r" \\ ".join(str(row) for row in latex_rows) + r"\end{aligned}"


def _matrix_text(symbol: str, entries: list[list[str]]) -> str:
    return f"{symbol} = [{', '.join('[' + ', '.join(row) + ']' for row in entries)}]"


def _vector_text(symbol: str, entries: list[str]) -> str:
    return f"{symbol} = [{', '.join(entries)}]"
