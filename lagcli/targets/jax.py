"""`lagcli generate --lang jax`: a module of pure `jax.numpy` functions (one file).

    mass_matrix, forcing, constraint_matrix, constraint_bias (t, y, p, u=None)
    accelerations(t, y, p, u=None, baumgarte=None) -> (q'', lambda)
    rhs, multipliers, invariants (t, y, p, u=None)
    inputs(t, y, p), rhs_closed_loop(t, y, p)            the spec's input laws (if any)

Each is a pure function of arrays (no Python branch on a value, no side effect), so
`jax.jit`, `jax.vmap`, `jax.grad` and `jax.jacfwd` take it; the augmented system
[[M, -A^T], [A, 0]] [q''; lambda] = [F; b] is solved with `jnp.linalg.solve`. Values
keep the dtype of the arguments (the literals are weakly typed). jax itself is imported
by the generated module only (`pip install "lagcli[jax]"`). Everything but the printer
and the template is shared with the other languages (`codegen.generated_context`).
Interface: docs/codegen.md, "JAX".
"""
from __future__ import annotations

from sympy.printing.numpy import JaxPrinter as SympyJaxPrinter

from lagcli.derive.result import Derivation
from lagcli.interface import Layout
from lagcli.targets import codegen
from lagcli.targets.laws import printed_laws
from lagcli.targets.python import PythonPrinter
from lagcli.targets.slots import SlotPrinter
from lagcli.render.templates import render


class JaxPrinter(SlotPrinter, SympyJaxPrinter):
    """jax.numpy on arrays: its functions imported by name (`from jax.numpy import sin`),
    min/max as nested `minimum`/`maximum`."""

    literal = staticmethod(PythonPrinter.literal)
    imports = PythonPrinter.imports

    def __init__(self, table: dict):
        super().__init__(table, {"fully_qualified_modules": False})

    def sqrt_name(self) -> str:
        return self._module_format("jax.numpy.sqrt")

    def _print_Min(self, expr):
        return self.nested_call("jax.numpy.minimum", expr.args)

    def _print_Max(self, expr):
        return self.nested_call("jax.numpy.maximum", expr.args)


def jax_files(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict[str, str]:
    """{<name>.py: the text of the generated JAX module} (`initial`, `initial_notes`: see
    `lagcli.targets.about.interface`)."""
    context = codegen.generated_context(d, JaxPrinter, layout, initial, initial_notes)
    return {f"{layout.name}.py": render("jax/module.py.jinja", **context, laws=printed_laws(d, JaxPrinter))}
