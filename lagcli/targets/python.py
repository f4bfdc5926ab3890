"""`lagcli generate --lang python`: one self-contained module needing only numpy.

The module's interface is docs/design.md ("Generated Python module"). Scalar code
uses `math` on Python floats (fast for small systems); numpy is used for the
arrays it returns and `numpy.linalg.solve`; scipy only inside `simulate`. The
module never imports sympy. Its output times and step cap are the code of
`lagcli/runtime/run_rules.py`, inserted verbatim (the rules lagcli itself runs); a spec
with events gets lagcli's event loop the same way (lagcli/targets/python_events.py).
Everything but the printer is shared with the C output (`codegen.generated_context`).
"""
from __future__ import annotations

from sympy.printing.pycode import PythonCodePrinter

from lagcli.derive.result import Derivation
from lagcli.interface import Layout
from lagcli.targets import codegen
from lagcli.render.escape import python_string
from lagcli.targets.slots import SlotPrinter
from lagcli.render.templates import render
from lagcli.runtime import python_run_rules, python_variational


class PythonPrinter(SlotPrinter, PythonCodePrinter):
    """Python 3 on floats: `math` functions imported by name (`from math import sin`)."""

    power_format = "{base}**{exp}"

    def __init__(self, table: dict):
        super().__init__(table, {"fully_qualified_modules": False, "standard": "python3"})

    @staticmethod
    def literal(value) -> str:
        """A Python literal for a number or string of the interface."""
        if isinstance(value, str):
            return python_string(value)
        value = float(value)
        return repr(value) if value == value and abs(value) != float("inf") else f"float({str(value)!r})"

    def imports(self) -> tuple[tuple[str, tuple[str, ...]], ...]:
        """(module, sorted names) of every function the printed code calls."""
        return tuple((module, tuple(sorted(names))) for module, names in sorted(self.module_imports.items()))

    def _print_sign(self, expr):
        """1.0, -1.0 or 0.0 (0.0 for NaN too, as in the generated C)."""
        x = self._print(expr.args[0])
        return f"(1.0 if ({x}) > 0 else (-1.0 if ({x}) < 0 else 0.0))"

    def sqrt_name(self) -> str:
        return self._module_format("math.sqrt")



def python_module(d: Derivation, layout: Layout, initial=None, initial_notes=(),
                  variational: bool | None = None) -> str:
    """The text of the generated module for `d` with its run interface `layout`; `initial`
    (the default state, made consistent by the caller) and `initial_notes`: see
    `lagcli.targets.about.interface`; `variational`: see
    `discrete_code.variational_context` (None: for a small system only)."""
    from lagcli.targets.discrete_code import merged_imports, variational_context
    from lagcli.targets.laws import printed_laws, state_printer
    from lagcli.targets.python_events import events_context

    context = codegen.generated_context(d, PythonPrinter, layout, initial, initial_notes)
    discrete = variational_context(d, PythonPrinter, variational)    # the variational integrator's functions
    if discrete["variational"] is not None:
        context["imports"] = merged_imports(context["imports"], discrete["variational"].imports)
    code = state_printer(d, PythonPrinter)
    laws = printed_laws(d, PythonPrinter, code)       # the spec's input laws: simulate's default u
    events = events_context(d, code)                  # the spec's events and the event loop
    context["imports"] = merged_imports(context["imports"], code.printer.imports())
    return render("python/module.py.jinja", **context, **discrete, **events, laws=laws,
                  run_rules=python_run_rules(),               # lagcli's own run rules, pasted verbatim
                  variational_runtime=python_variational())   # and its variational integrator
