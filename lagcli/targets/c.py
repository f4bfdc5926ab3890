"""`lagcli generate --lang c`: `<name>.h`, `<name>.c` (C99 + libm), the driver `<name>_main.c`
and lagcli's C runtime beside them (`lagcli/runtime/c/`: the integrator `lagcli_ode.{h,c}`,
the model table `lagcli_model.h` and the driver `lagcli_driver.{h,c}`, copied as they are).

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
from lagcli.targets import codegen
from lagcli.targets.slots import SlotPrinter
from lagcli.render.templates import render
from lagcli.errors import Loc, Problem, SpecError
from lagcli.interface import C_METHODS, Layout
from lagcli.runtime.run_rules import EXPLICIT_METHODS
from lagcli.runtime import c_runtime_files


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



def c_files(d: Derivation, layout: Layout, initial=None, initial_notes=(),
            variational: bool | None = None, spec_laws: bool = False) -> dict[str, str]:
    """{file name: text} of `<name>.h`, `<name>.c`, `<name>_main.c` and the C runtime;
    `layout`: the system's run interface; `initial` (the default state, made consistent
    by the caller) and `initial_notes`: see `lagcli.targets.about.interface`;
    `variational`: see `discrete_code.variational_context` (None: for a small system only);
    `spec_laws` (`lagcli generate`): the driver's model table runs the spec's input laws."""
    laws = open_loop_laws(d) if spec_laws else ()
    if laws:
        said = "; ".join(f"{u} = {text}" for u, code, text in laws if code is not None)
        initial_notes = (*initial_notes, f"The input laws (simulate: inputs:) run in the driver's model table "
                         f"({d.model.name}_spec_inputs): {said}; the _u functions take u as given.")
    context = c_context(d, layout, initial, initial_notes, variational, laws)
    name = d.model.name
    runtime = c_runtime_files()
    if {f"{name}.h", f"{name}.c", f"{name}_main.c"} & set(runtime):
        raise SpecError(Problem(Loc(d.model.source, path="name"),
                                f"the name {name!r} gives a file name of lagcli's C runtime "
                                f"({', '.join(runtime)})", "set another `name:` in the spec"))
    return {**model_sources(context), f"{name}_main.c": render("c/main.c.jinja", **context), **runtime}


def model_sources(context: dict) -> dict[str, str]:
    """`<name>.h` and `<name>.c` from a `c_context` (also the model inside an FMU)."""
    name = context["prefix"]
    return {f"{name}.h": render("c/model.h.jinja", **context), f"{name}.c": render("c/model.c.jinja", **context)}


LAWS_NOT_VARIATIONAL = ("--method variational does not run the input laws (simulate: inputs:) yet: it holds "
                        "the inputs constant; use --method DOP853 or RK45")


def open_loop_laws(d: Derivation) -> tuple:
    """The spec's input laws as C (`lagcli.targets.laws.printed_laws`) when `d`'s forcing
    still takes those inputs (`generate --lang c`: the model stays open loop, its `_u`
    functions take u as given, and the model table runs the laws); () when there are none
    or they are already substituted (the closed loop `lagcli simulate --backend c` builds)."""
    from lagcli.targets.laws import printed_laws

    with_law = {law.symbol for law in d.model.laws}
    if not with_law:         # no law: no walk of the forcing (0.4 s of CPU at 40 links)
        return ()
    return printed_laws(d, CPrinter) if with_law & d.forcing.free_symbols else ()


def c_context(d: Derivation, layout: Layout, initial=None, initial_notes=(),
              variational: bool | None = None, laws: tuple = ()) -> dict:
    """Everything the C templates need, pre-printed; `laws`: `open_loop_laws` (the model
    table then runs them, and refuses --method variational, which holds inputs constant)."""
    from lagcli.targets.discrete_code import variational_context
    from lagcli.targets.event_code import event_context

    context = codegen.generated_context(d, CPrinter, layout, initial, initial_notes)
    if laws:             # the variational integrator holds the inputs constant: the table refuses it
        context.update(variational=None, variational_refusal=LAWS_NOT_VARIATIONAL)
    else:
        context.update(variational_context(d, CPrinter, variational))    # the variational integrator's functions
    context.update(event_context(d, CPrinter))           # the spec's events (none: empty)
    name = layout.name
    settings = layout.settings
    residual = context["i"].residual_index
    return dict(context, prefix=name, PREFIX=name.upper(), nsys=context["n"] + context["m"], laws=laws,
                parts=body_parts(context),
                law_inputs=tuple(u for u, code, _ in laws if code is not None),
                settings=settings,
                driver_method=settings.method if settings.method in EXPLICIT_METHODS else EXPLICIT_METHODS[-1],
                table_method=settings.method if settings.method in C_METHODS else EXPLICIT_METHODS[-1],
                residual_column=-1 if residual is None else residual)


def body_parts(context: dict) -> dict:
    """{function: `c_parts.Parts` or None} of the model functions whose body is big enough
    to be split (lagcli/targets/c_parts.py): the right-hand side ("rhs", with the
    stabilisation after it), the invariants and the four output functions."""
    from lagcli.targets.c_parts import split_body

    nsys = context["n"] + context["m"]
    system, stabilization, invariants = context["system"], context["stabilization"], context["invariants"]
    rhs = [f"K[{r * nsys + k}] = {code};" for r, row in enumerate(context["system_rows"]) for k, code in enumerate(row)]
    rhs += [f"r[{k}] = {code};" for k, code in enumerate(context["system_rhs"])]
    after = [code for _, code in stabilization.temporaries]
    after += [code for _, velocity, position in context["stabilization_terms"] for code in (velocity, position or "")]
    outputs = [f"out[{k}] = {code};" for k, code in enumerate(invariants.values["invariants"])]
    outputs += [f"values[{k}] = {code};" for k, code in enumerate(context["residual"])]
    parts = dict(rhs=split_body(system.temporaries, rhs, after),
                 invariants=split_body(invariants.temporaries, outputs))
    for function, array, group in (("mass_matrix", "M", "mass"), ("forcing", "F", "forcing"),
                                   ("constraint_matrix", "A", "constraint_matrix"),
                                   ("constraint_bias", "b", "constraint_bias")):
        block = context[group]
        values = block.values[function]
        parts[function] = split_body(block.temporaries, [f"{array}[{k}] = {code};" for k, code in enumerate(values)])
    return parts
