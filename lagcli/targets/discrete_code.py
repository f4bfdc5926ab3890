"""The generated functions of the variational integrator (lagcli/derive/discrete.py),
printed for a language: its own tidy + ONE cse over `DiscreteGroups` (kept apart from
the model's functions, whose code stays as it was), in the slots y = [q, q'], p, u.

    variational_context(d, printer_class, wanted) -> {"variational": VariationalCode | None,
                                                       "variational_refusal": str | None}

None and the refusal (naming the constraint) for a system with nonholonomic rows:
then no function is generated and the integrator refuses to run. The same for a big
system (`included`) unless asked for (`wanted=True`: `lagcli generate --variational`, and
every program lagcli runs itself): its second derivatives and their CSE cost several
times the rest of the code (the 40-link chain: ~45 s of CPU against ~15 s,
bench/README.md, "Scaling").
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from lagcli.derive.discrete import HOLONOMIC, JACOBIAN, MOMENTA, METHOD, discrete_groups, refusal
from lagcli.targets import codegen
from lagcli.targets.cse import eliminate
from lagcli.render.tidy import small, tidy_expression


@dataclass(frozen=True)
class VariationalCode:
    momenta: codegen.Block       # g, f
    jacobian: codegen.Block      # dg/dq, dg/dq', df/dq, df/dq'
    holonomic: codegen.Block     # phi, A, phi_t of the holonomic rows
    d: int                       # number of holonomic rows
    imports: tuple               # what the printed code calls (Python: names from math)


VARIATIONAL_MAX_NODES = codegen.TIDY_MAX_TOTAL_NODES   # tree nodes of the model's outputs, together
# Tidy the variational functions only when together this small: tidying costs ~0.3 ms of
# CPU per tree node and saves a few percent of their code (the 10-link chain: 26 366 nodes,
# ~5 s of a 7 s `generate --lang c`, for 7% less C); every bundled spec has at most 3 001.
VARIATIONAL_TIDY_MAX_NODES = 5_000


def included(d) -> bool:
    """Whether the variational functions are generated when nobody asked: when M and F
    as derived have at most VARIATIONAL_MAX_NODES tree nodes together (every bundled
    spec; the planar chain up to 13 links)."""
    return small([*d.mass_matrix, *d.forcing], VARIATIONAL_MAX_NODES)


def variational_context(d, printer_class, wanted: bool | None = None) -> dict:
    """`wanted`: True always generates the functions (when the system allows), False never,
    None when the system is small (`included`)."""
    reason = refusal(d)
    if reason is None and not (wanted if wanted is not None else included(d)):
        reason = (f"--method {METHOD}: the variational integrator's functions were not generated "
                  f"for this system (its equations have more than {VARIATIONAL_MAX_NODES} tree nodes, "
                  "where they cost several times the rest of the code)\n"
                  "  hint: generate with `lagcli generate --variational`")
    if reason is not None:
        return {"variational": None, "variational_refusal": reason}
    groups = discrete_groups(d)
    everything = [e for exprs in groups.groups().values() for e in exprs]
    if small(everything, VARIATIONAL_TIDY_MAX_NODES):
        cache: dict = {}
        groups = replace(groups, **{name: tuple(tidy_expression(e, d.model.qd, cache) for e in exprs)
                                    for name, exprs in groups.groups().items()})
    reduced = eliminate(groups)
    printer = codegen.printer_for(d, reduced, printer_class)
    code = VariationalCode(
        momenta=codegen.print_block(reduced, printer, MOMENTA),
        jacobian=codegen.print_block(reduced, printer, JACOBIAN),
        holonomic=codegen.print_block(reduced, printer, HOLONOMIC),
        d=len(groups.position),
        imports=printer.imports(),
    )
    return {"variational": code, "variational_refusal": None}


def merged_imports(*imports) -> tuple:
    """(module, sorted names) pairs of several printers, merged."""
    names: dict = {}
    for pairs in imports:
        for module, functions in pairs:
            names.setdefault(module, set()).update(functions)
    return tuple((module, tuple(sorted(names[module]))) for module in sorted(names))
