"""The spec's input laws (`simulate: inputs:`) as code of a target: u(t, q, q') per input.

`printed_laws` gives, per input in the layout's order, its law printed by the target's
printer with the model's state slots (y[i], p[j] as the target writes them; a law uses
no input and no temporary), or None for an input without a law, and the law in the
spec's own expression language for comments. Used by the Python, MATLAB/Octave, CasADi and
JAX targets (`<name>_inputs.m`, `inputs`, `rhs_closed_loop`).
"""
from __future__ import annotations

from lagcli.render.spec_printer import spec_str
from lagcli.targets.slots import check_slots


def state_printer(d, printer_class):
    """`code(expr)`: an expression of t, q, q' and the parameters printed by `printer_class`
    (`code.printer`: the printer, for what its code imports)."""
    model = d.model
    base, subscript = printer_class.index_base, printer_class.subscript
    table = {model.t: "t"}
    table.update({s: subscript.format(array="y", index=k + base) for k, s in enumerate((*model.q, *model.qd))})
    table.update({s: subscript.format(array="p", index=k + base) for k, s in enumerate(model.parameter_symbols)})
    printer = printer_class(table)

    def code(expr) -> str:
        check_slots([expr], table)
        return printer.code(expr)
    code.printer = printer
    return code


def printed_laws(d, printer_class, code=None) -> tuple[tuple[str, str | None, str | None], ...]:
    """((input name, printed law or None, the law as spec text or None), ...) in input
    order; () when the spec has no laws. `code`: the `state_printer` to print with (its
    printer then knows what the laws import)."""
    given = {law.symbol.name: law.expr for law in d.model.laws}
    if not given:
        return ()
    code = code or state_printer(d, printer_class)
    return tuple((u.name, code(given[u.name]), spec_str(given[u.name])) if u.name in given else (u.name, None, None)
                 for u in d.model.input_symbols)
