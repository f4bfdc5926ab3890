"""`lagcli generate SPEC --lang python --form hamiltonian`: a module whose state is (q, p).

Hamilton's equations as lagcli/derive/hamilton_form.py states them (unconstrained
systems):

    p  = M q' + a                                  (momenta)
    q' = M^-1 (p - a)                              (solved numerically, never inverted)
    p' = dL/dq (t, q, q') + Q'(t, q, q', u)        (= -dH/dq + Q' at q' = q'(q, p))
    H  = T2 - T0 + V                               (at q' = q'(q, p); the Jacobi integral)

The expressions M, a, dL/dq + Q' and H go through the same pipeline as the Lagrangian
module (tidy, ONE cse, the slot printer of lagcli/targets/python.py): they are printed in
the Lagrangian slots y = [q, q'], and the module builds y from (q, p) once per call.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagcli.derive.hamilton_form import hamilton_form
from lagcli.derive.result import Derivation
from lagcli.interface import Layout
from lagcli.targets import codegen
from lagcli.targets.cse import eliminate
from lagcli.targets.python import PythonPrinter
from lagcli.render.templates import render
from lagcli.render.tidy import tidy_expression


@dataclass(frozen=True)
class HamiltonGroups:
    """The expressions of the Hamiltonian module, in the Lagrangian variables (q, q')."""

    mass_matrix: tuple      # n*n, M (upper triangle mirrored)
    offset: tuple           # n, a (T1 = a . q')
    momentum_rate: tuple    # n, dL/dq + Q'
    hamiltonian: tuple      # 1, T2 - T0 + V

    def groups(self) -> dict[str, tuple]:
        return {"mass_matrix": self.mass_matrix, "offset": self.offset,
                "momentum_rate": self.momentum_rate, "hamiltonian": self.hamiltonian}


def hamilton_groups(d: Derivation) -> HamiltonGroups:
    model, n = d.model, d.n
    cache: dict = {}

    def tidy(exprs) -> tuple:
        return tuple(tidy_expression(sp.sympify(e), model.qd, cache) for e in exprs)

    M = d.mass_matrix
    rate = [d.L.diff(q) + d.nonconservative_forces[k] for k, q in enumerate(model.q)]
    return HamiltonGroups(
        mass_matrix=tidy(M[min(i, j), max(i, j)] for i in range(n) for j in range(n)),
        offset=tidy(d.t1_coefficients),
        momentum_rate=tidy(rate),
        hamiltonian=tidy([d.T2 - d.T0 + d.V]),
    )


def hamilton_module(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> str:
    """The text of the (q, p) module of `d` with its run interface `layout` (refused for a
    constrained system, as `lagcli hamiltonian` does); `initial`: the Lagrangian default
    state [q, q']."""
    form = hamilton_form(d)
    reduced = eliminate(hamilton_groups(d))
    printer = codegen.printer_for(d, reduced, PythonPrinter)
    names = ("mass_matrix", "offset", "momentum_rate", "hamiltonian")
    blocks = {name: codegen.print_block(reduced, printer, (name,)) for name in names}
    system = codegen.print_block(reduced, printer, ("mass_matrix", "offset"))
    interface = codegen.interface(layout, initial, initial_notes)
    return render("python/hamiltonian.py.jinja", i=interface, n=d.n, literal=PythonPrinter.literal,
                  imports=printer.imports(), momenta=tuple(p.name for p in form.momenta),
                  mass_rows=codegen._rows(system.values["mass_matrix"], d.n), system=system,
                  offset=system.values["offset"], blocks=blocks)

