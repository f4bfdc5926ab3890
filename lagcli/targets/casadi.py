"""`lagcli generate --lang casadi`: a Python module of CasADi `Function`s (one file).

The module builds, once at import, symbolic `SX` expressions of the derivation with its
common subexpressions (the one CSE of `codegen`: each temporary one SX node, shared by
every Function that uses it) and wraps them as `casadi.Function`s:

    rhs(t, x, p, u) -> ode                     x = [q; q'], the exact equations
    implicit(t, q, qd, qdd, lam, p, u) -> (residual, position, velocity, acceleration)
                                               M q'' - F - A^T lambda, phi, A q' + d, A q'' - b
    mass_matrix, forcing, constraint_matrix, constraint_bias, multipliers, energy,
    invariants (t, x, p, u)
    dae() -> {"t", "x", "p", "u", "ode"}       for casadi.integrator
    inputs(t, x, p) -> u, rhs_closed_loop(t, x, p) -> ode     the spec's input laws (if any)

casadi itself is imported by the generated module only (`pip install "lagcli[casadi]"`).
Everything but the printer and the template is shared with the other languages
(`codegen.generated_context`). Interface: docs/codegen.md, "CasADi".
"""
from __future__ import annotations

from sympy.printing.pycode import PythonCodePrinter

from lagcli.derive.result import Derivation
from lagcli.interface import Layout
from lagcli.targets import codegen
from lagcli.targets.laws import printed_laws
from lagcli.targets.python import PythonPrinter
from lagcli.targets.slots import SlotPrinter
from lagcli.render.templates import render

# The functions of the spec language (lagcli/expr.py) that casadi has by the same name.
SAME_NAME = ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "exp", "log")


class CasadiPrinter(SlotPrinter, PythonCodePrinter):
    """Python on casadi SX: its functions imported by name (`from casadi import sin`),
    |x| as `fabs`, min/max as nested `fmin`/`fmax`, sign as casadi's `sign`."""

    _kf = {name: f"casadi.{name}" for name in SAME_NAME}
    literal = staticmethod(PythonPrinter.literal)
    imports = PythonPrinter.imports

    def __init__(self, table: dict):
        super().__init__(table, {"fully_qualified_modules": False, "standard": "python3"})

    def sqrt_name(self) -> str:
        return self._module_format("casadi.sqrt")

    def _print_Abs(self, expr):
        return f"{self._module_format('casadi.fabs')}({self._print(expr.args[0])})"

    def _print_sign(self, expr):
        return f"{self._module_format('casadi.sign')}({self._print(expr.args[0])})"

    def _print_Min(self, expr):
        return self.nested_call("casadi.fmin", expr.args)

    def _print_Max(self, expr):
        return self.nested_call("casadi.fmax", expr.args)


def casadi_module(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> str:
    """The text of the generated CasADi module for `d` (`initial`, `initial_notes`: see
    `lagcli.targets.about.interface`)."""
    context = codegen.generated_context(d, CasadiPrinter, layout, initial, initial_notes)
    holonomic = tuple(name for name, row in zip(context["i"].multipliers, d.constraints)
                      if row.kind == "holonomic")
    laws = printed_laws(d, CasadiPrinter)
    defaults = [CasadiPrinter.literal(default) for _, default in context["i"].inputs]
    return render("casadi/module.py.jinja", **context, shared=_shared_temporaries(context),
                  holonomic=holonomic, laws=laws,
                  laws_code=[code if code is not None else default for (_, code, _), default in zip(laws, defaults)])


def _shared_temporaries(context: dict) -> tuple[tuple[str, str], ...]:
    """Every temporary once, in an order that defines each before its use: those of the
    augmented system, of the stabilisation terms, then the invariants' others."""
    seen, ordered = set(), []
    for block in (context["system"], context["stabilization"], context["invariants"]):
        for name, code in block.temporaries:
            if name not in seen:
                seen.add(name)
                ordered.append((name, code))
    return tuple(ordered)


def casadi_files(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict[str, str]:
    return {f"{layout.name}.py": casadi_module(d, layout, initial, initial_notes)}
