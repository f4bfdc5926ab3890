"""`lagcli generate --lang rust`: a dependency-free crate (`-o DIR`).

    Cargo.toml       the package: no dependencies
    src/lib.rs       the model: sizes, names, defaults, `Parameters`, index constants,
                     rhs, rhs_stabilized, mass_matrix, forcing, constraint_matrix,
                     constraint_bias, invariants, and the `MODEL` table for the driver
    src/main.rs      the example binary: `driver::main(&MODEL)`
    src/ode.rs       lagcli's RK45/DOP853 integrator     } lagcli/runtime/rust/,
    src/driver.rs    options, output times, the CSV      } copied as they are

The right-hand side assembles [[M, -A^T], [A, 0]] [q''; lambda] = [F; b - 2 alpha
(A q' + d) - beta^2 phi] in fixed-size arrays on the stack and solves it by LU with
partial pivoting in place: no allocation. Everything but the printer and the templates
is shared with the other languages (`codegen.generated_context`). Interface:
docs/codegen.md.
"""
from __future__ import annotations

import math

import sympy as sp
from sympy.printing.rust import RustCodePrinter, reserved_words

from lagcli.derive.result import Derivation
from lagcli.targets import codegen
from lagcli.targets.identifiers import identifier, identifiers
from lagcli.targets.slots import SlotPrinter
from lagcli.render.templates import render
from lagcli.interface import Layout
from lagcli.runtime import rust_runtime_files

# Rust's keywords (sympy's list) and the names Cargo refuses for a package.
RESERVED = frozenset(reserved_words) | {"_"}
CRATE_RESERVED = RESERVED | {"test", "core", "std", "alloc", "proc_macro", "build", "deps",
                             "examples", "incremental", "con", "prn", "aux", "nul"}


class RustPrinter(SlotPrinter, RustCodePrinter):
    """f64 expressions: every number a float literal, functions as methods (`x.sin()`)."""

    power_format = "{base}.powf({exp})"

    @staticmethod
    def literal(value) -> str:
        """An f64 literal (`f64::INFINITY`, `f64::NAN` for the non-finite)."""
        value = float(value)
        if math.isnan(value):
            return "f64::NAN"
        if math.isinf(value):
            return "f64::INFINITY" if value > 0 else "f64::NEG_INFINITY"
        text = repr(value)
        return text if any(c in text for c in ".e") else text + ".0"

    def _print_Integer(self, expr, _type=False):
        return self.literal(int(expr))

    def _print_Float(self, expr, _type=False):
        return self.literal(float(expr))

    def _print_Rational(self, expr):
        """p/q as the double nearest to it, which is what f64 division of p by q gives
        (both exact below 2**53; Python's int division rounds correctly too)."""
        return self.literal(int(expr.p) / int(expr.q))

    def _cast_to_float(self, expr):
        return expr      # every value is an f64 already

    def _print_caller_var(self, expr):
        """The receiver of a method call: parenthesised unless a slot or a call
        (`-x.sin()` would be -(x.sin())), a number typed (`(2.0_f64).sin()`)."""
        if expr.is_Symbol or isinstance(expr, sp.Function):
            return self._print(expr)
        if expr.is_Integer or expr.is_Float or expr.is_Rational:
            return f"({self._print(expr)}_f64)"
        return f"({self._print(expr)})"

    def _power_operand(self, expr) -> str:
        return self._print_caller_var(expr) if expr.is_number else super()._power_operand(expr)

    def _print_sqrt(self, base) -> str:
        return f"{self._print_caller_var(base)}.sqrt()"

    def _print_MinMax(self, expr, method):
        first, *rest = expr.args
        text = self._print_caller_var(first)
        for arg in rest:
            text = f"{text}.{method}({self._print(arg)})"
        return text

    def _print_Min(self, expr):
        return self._print_MinMax(expr, "min")

    def _print_Max(self, expr):
        return self._print_MinMax(expr, "max")

    def _print_sign(self, expr):
        """1.0, -1.0 or 0.0 (0.0 for NaN too, as in the generated C)."""
        x = self._print(expr.args[0])
        return f"(if {x} > 0.0 {{ 1.0 }} else if {x} < 0.0 {{ -1.0 }} else {{ 0.0 }})"


def crate_name(name: str) -> str:
    """The Cargo package (and crate) name: the spec's name in lower case, mangled."""
    return identifier(name.lower(), CRATE_RESERVED)


def rust_files(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict[str, str]:
    """{file name: text} of the crate (see the top)."""
    context = rust_context(d, layout, initial, initial_notes)
    runtime = {f"src/{name}": text for name, text in rust_runtime_files().items()}
    return {
        "Cargo.toml": render("rust/Cargo.toml.jinja", **context),
        "src/lib.rs": render("rust/lib.rs.jinja", **context),
        "src/main.rs": render("rust/main.rs.jinja", **context),
        **runtime,
    }


def rust_context(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict:
    """Everything the Rust templates need, pre-printed."""
    context = codegen.generated_context(d, RustPrinter, layout, initial, initial_notes)
    i = context["i"]
    return dict(context, crate=crate_name(layout.name), settings=layout.settings,
                inputs=layout.input_names,
                input_defaults=tuple(context["literal"](x.default) for x in layout.inputs),
                nsys=context["n"] + context["m"],
                header=i.header, fields=identifiers(i.fields, RESERVED, "Rust"),
                residual_column=i.residual_index)
