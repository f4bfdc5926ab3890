"""The recipe for a new code target in lagcli/targets/__init__.py names real override
points: a printer whose arrays start at 1 and are subscripted with parentheses
prints every symbol of a system that way."""
from __future__ import annotations

from lagcli.interface import layout_of
from lagcli.targets.c import CPrinter
from lagcli.targets.cse import eliminate
from lagcli.targets.expressions import collect
from lagcli.targets.slots import slots


class OneBasedPrinter(CPrinter):
    index_base = 1
    subscript = "{array}({index})"


def test_index_base_and_subscript_reach_the_slots(derived):
    d = derived("double_pendulum")
    table = slots(d, eliminate(collect(d, layout_of(d))), OneBasedPrinter)
    model = d.model
    assert [table[s] for s in model.q + model.qd] == ["y(1)", "y(2)", "y(3)", "y(4)"]
    assert [table[s] for s in model.parameter_symbols] == [f"p({j})" for j in range(1, 6)]
    printer = OneBasedPrinter(table)
    assert printer.code(model.q[0] * model.parameter_symbols[0]) in ("y(1)*p(1)", "p(1)*y(1)")
