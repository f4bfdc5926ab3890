"""`lagcli generate --lang octave`: MATLAB/Octave function files and a script (`-o DIR`).

    <name>_rhs.m          [dydt, lambda] = <name>_rhs(t, y, p, u, alpha, beta)
    <name>_mass_matrix.m, <name>_forcing.m, <name>_constraint_matrix.m,
    <name>_constraint_bias.m, <name>_invariants.m      (t, y, p, u)
    <name>_info.m         names, defaults, initial state, settings, index structs
    <name>_simulate.m     [header, rows] = <name>_simulate(options...): ode45
    <name>_run.m          a script: <name>_simulate, then the CSV of `lagcli simulate`
    <name>_inputs.m, <name>_events.m, <name>_event_action.m, lagcli_event_loop.m ...
                          the spec's input laws and events (lagcli/targets/octave_hybrid.py)

The same text is valid MATLAB and Octave: `%` comments, `~=`, functions closed by
`end`, no Octave-only syntax. The right-hand side assembles the augmented system
[[M, -A^T], [A, 0]] [q''; lambda] = [F; b - 2 alpha (A q' + d) - beta^2 phi] and solves
it with `\\`, as the C and Python code does; everything but the printer and the
templates is shared (`codegen.generated_context`). Interface: docs/codegen.md.
"""
from __future__ import annotations

import math

from sympy.printing.octave import OctaveCodePrinter

from lagcli.derive.result import Derivation
from lagcli.targets import codegen
from lagcli.render.escape import octave_string
from lagcli.targets.identifiers import identifiers
from lagcli.targets.slots import SlotPrinter
from lagcli.render.templates import render
from lagcli.errors import Loc, Problem, SpecError
from lagcli.interface import STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT, Layout
from lagcli.runtime import octave_event_files
from lagcli.targets.octave_hybrid import EVENT_FILES, hybrid_context
from lagcli.runtime.run_rules import END_TOLERANCE, OUTPUT_SLACK

# Keywords (Octave's iskeyword(), MATLAB's) and the constants/builtins a field called
# so would shadow in a reader's mind (`pi`, `i`, `e`...): mangled in `<name>_info`.
RESERVED = frozenset("""
    __FILE__ __LINE__ break case catch classdef continue do else elseif end end_try_catch
    end_unwind_protect endarguments endclassdef endenumeration endevents endfor endfunction
    endif endmethods endparfor endproperties endspmd endswitch endwhile for function global
    if otherwise parfor persistent return spmd switch try until unwind_protect
    unwind_protect_cleanup while arguments enumeration events methods properties
    pi i j e Inf inf NaN nan eps ans true false
""".split())

FUNCTIONS = ("rhs", "mass_matrix", "forcing", "constraint_matrix", "constraint_bias",
             "invariants", "info", "simulate")


class OctavePrinter(SlotPrinter, OctaveCodePrinter):
    """MATLAB/Octave scalars: y(1), p(1) (arrays start at 1), builtin functions."""

    index_base = 1
    subscript = "{array}({index})"
    power_format = "{base}^{exp}"

    @staticmethod
    def literal(value) -> str:
        """A MATLAB literal for a number or string of the interface."""
        if isinstance(value, str):
            return octave_string(value)
        value = float(value)
        if math.isnan(value):
            return "NaN"
        if math.isinf(value):
            return "Inf" if value > 0 else "-Inf"
        return repr(value)


def octave_files(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict[str, str]:
    """{file name: text} of the function files and the script (see the top)."""
    context = octave_context(d, layout, initial, initial_notes)
    name = d.model.name
    if not name[:1].isalpha():
        raise SpecError(Problem(Loc(d.model.source, path="name"),
                                f"MATLAB/Octave function names start with a letter: {name!r}",
                                "set a `name:` that starts with a letter"))
    functions = FUNCTIONS + (("inputs",) if context["laws"] else ()) + (EVENT_FILES if context["events"] else ())
    files = {f"{name}_{function}.m": render(f"octave/{function}.m.jinja", **context)
             for function in functions}
    files[f"{name}_run.m"] = render("octave/run.m.jinja", **context)
    if context["events"]:
        files.update(octave_event_files())
    return files


def octave_context(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict:
    """Everything the MATLAB/Octave templates need, pre-printed."""
    context = codegen.generated_context(d, OctavePrinter, layout, initial, initial_notes)
    i = context["i"]
    return dict(context, **hybrid_context(d, OctavePrinter), prefix=layout.name, settings=layout.settings,
                # the output-time rule of lagcli/runtime/run_rules.py, restated in simulate.m
                output_slack=_short_literal(OUTPUT_SLACK), end_tolerance=_short_literal(END_TOLERANCE),
                step_budget={"base": STEP_BUDGET_BASE, "per_output": STEP_BUDGET_PER_OUTPUT},
                inputs=layout.input_names,
                input_defaults=tuple(OctavePrinter.literal(x.default) for x in layout.inputs),
                header=i.header, fields=identifiers(i.fields, RESERVED, "MATLAB field"))


def _short_literal(value: float) -> str:
    """A power of ten as the shortest literal MATLAB reads: 1e-9, 1e-12."""
    mantissa, _, exponent = format(value, ".0e").partition("e")
    return f"{mantissa}e{int(exponent)}"
