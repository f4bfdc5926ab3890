"""The closed loop: the derivation with the spec's input laws substituted for the inputs.

    F(t, q, q', u)  ->  F(t, q, q', u(t, q, q'))

so that `lagcli linearize --closed-loop` (lagcli.analysis.linearize, unchanged) gives the
closed-loop A and its eigenvalues: for u = -K x about an equilibrium, A - B K.
"""
from __future__ import annotations

import dataclasses

import sympy as sp

from lagcli.errors import UsageError


def closed_loop(d, laws: dict | None = None):
    """`d` with each input that has a law replaced by it in the forcing F: the spec's laws,
    or `laws` (input name -> sympy expression) when given (then exactly those)."""
    model = d.model
    given = {law.symbol.name: law.expr for law in model.laws} if laws is None else dict(laws)
    if not given:
        raise UsageError(f"{model.source}: --closed-loop needs input laws (simulate: inputs: in the spec); "
                         "this spec has none")
    symbols = {u.name: u for u in model.input_symbols}
    laws = tuple((symbols[name], sp.sympify(expr)) for name, expr in given.items())
    return dataclasses.replace(d, input_laws=laws)     # F is computed with them (Derivation.forcing)
