"""`lagcli generate --lang c`: `<name>.h`, `<name>.c` (C99 + libm) and the driver `<name>_main.c`.

The interface is docs/design.md ("Generated C"). The right-hand side assembles the
augmented system [[M, -A^T], [A, 0]] [q''; lambda] = [F; b - 2 alpha (A q' + d) -
beta^2 phi] in fixed-size arrays on the stack and solves it by LU with partial
pivoting in place: no allocation. Everything compiles with
`cc -std=c99 -O2 -Wall -Wextra -Werror -pedantic ... -lm`.

The printer never emits the non-C99 `M_PI`-style macros: constants print as
21-digit literals, small integer powers as products. Everything but the printer
is shared with the Python output (`codegen.generated_context`).
"""
from __future__ import annotations

import math

from sympy.printing.c import C99CodePrinter

from lagcli.derive.result import Derivation
from lagcli.emit import codegen
from lagcli.emit.slots import SlotPrinter
from lagcli.emit.templates import render

INTEGRATOR_PREFIX = "lagcli_ode"     # names of the integrator fragment: lagcli_ode_integrate, ...


class CPrinter(SlotPrinter, C99CodePrinter):
    """C99 doubles: math.h functions, no math macros (M_PI is not C99)."""

    power_format = "pow({base}, {exp})"

    def __init__(self, table: dict):
        super().__init__(table, {"math_macros": {}})

    @staticmethod
    def literal(value) -> str:
        """A C double literal (C99 has no literal for inf or nan: HUGE_VAL and NAN from math.h)."""
        value = float(value)
        if math.isnan(value):
            return "NAN"
        if math.isinf(value):
            return "HUGE_VAL" if value > 0 else "(-HUGE_VAL)"
        text = repr(value)
        return text if any(c in text for c in ".e") else text + ".0"

    def _print_sign(self, expr):
        """A double (sympy's `(x > 0) - (x < 0)` is an int: sign(x)/sign(y) would divide
        integers); 0 for 0 and NaN, like copysign-free C99 code should."""
        x = self._print(expr.args[0])
        return f"(({x}) > 0 ? 1.0 : (({x}) < 0 ? -1.0 : 0.0))"



def c_files(d: Derivation, initial=None, initial_notes=()) -> dict[str, str]:
    """{file name: text} of `<name>.h`, `<name>.c` and `<name>_main.c`; `initial` (the
    default state, made consistent by the caller) and `initial_notes`: see
    `lagcli.emit.interface.interface`."""
    context = c_context(d, initial, initial_notes)
    name = d.model.name
    return {
        f"{name}.h": render("c/model.h.jinja", **context),
        f"{name}.c": render("c/model.c.jinja", **context),
        f"{name}_main.c": render("c/main.c.jinja", **context),
    }


def c_context(d: Derivation, initial=None, initial_notes=()) -> dict:
    """Everything the C templates need, pre-printed."""
    context = codegen.generated_context(d, CPrinter, initial, initial_notes)
    name = d.model.name
    return dict(context, prefix=name, PREFIX=name.upper(), nsys=context["n"] + context["m"],
                integrator_prefix=INTEGRATOR_PREFIX)
