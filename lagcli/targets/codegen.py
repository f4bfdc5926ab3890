"""The language-independent half of code generation: a Derivation in, the
strings-only context of every generated function body out (`generated_context`).

    outputs.collect    every expression generated code evaluates
    reduced_outputs    ONE sympy.cse over all of them (cse.eliminate), of the tidied
                       expressions (tidy.py) or of those as derived, whichever needs
                       fewer operations: temporaries are shared
    slots.slots        symbol -> array slot; the language's `SlotPrinter` prints
    print_block        one function body: the temporaries it needs, then its values
    function_bodies    every body, plus the matrix rows, stabilisation terms and
                       residual terms the templates lay out
    interface          what generated files say of the system, read from its run
                       interface (about.py over lagcli.interface.Layout)

A language module (python.py, c.py) only picks its printer class and templates:
everything here is shared, and what differs between languages is an attribute of
the printer class (`literal`, `power_format`, `sqrt_function`, `imports`). The
templates receive strings, tuples of strings and numbers, never sympy objects.
"""
from __future__ import annotations

from dataclasses import dataclass

from lagcli.derive.result import Derivation
from lagcli.targets.cse import CSE_OPTIMIZATIONS, Reduced, basic_optimizations, eliminate  # noqa: F401
from lagcli.targets.about import Interface, interface  # noqa: F401
from lagcli.targets.expressions import GROUPS, Outputs, collect, invariant_columns, tidied  # noqa: F401
from lagcli.targets.slots import SlotPrinter, check_slots, slots
from lagcli.render.tidy import small, tidy_expression, trigsimp_safe  # noqa: F401
from lagcli.interface import CONSTRAINT_TOLERANCE, Layout

TIDY_MAX_TOTAL_NODES = 30_000   # tidy generated code's expressions only when together this small

SYSTEM = ("mass_matrix", "forcing", "constraint_matrix", "constraint_bias")
POSITION = ("constraint_velocity", "constraint_position")


@dataclass(frozen=True)
class Block:
    """One function body, printed: temporaries (name, code) in order, then the printed
    expressions of each group; `negated[name]` holds the printed negatives."""

    temporaries: tuple[tuple[str, str], ...]
    values: dict
    negated: dict

    @property
    def names(self) -> frozenset[str]:
        """The temporaries computed here, by name."""
        return frozenset(name for name, _ in self.temporaries)


def print_block(reduced: Reduced, printer: SlotPrinter, names, exclude: Block | None = None,
                negated=()) -> Block:
    """Print the groups `names` and the temporaries they need (minus those of `exclude`)."""
    skip = exclude.names if exclude is not None else frozenset()
    temps = reduced.block(names, frozenset(s for s, _ in reduced.temporaries if printer.slots[s] in skip))
    check_slots([v for _, v in temps] + [e for name in names for e in reduced.groups[name]],
                printer.slots, reduced.free_symbols)
    return Block(
        temporaries=tuple((printer.slots[s], printer.code(v)) for s, v in temps),
        values={name: tuple(printer.code(e) for e in reduced.groups[name]) for name in names},
        negated={name: tuple(printer.code(-e) for e in reduced.groups[name]) for name in negated},
    )


def function_bodies(reduced: Reduced, printer: SlotPrinter, outputs: Outputs, n: int, m: int) -> dict:
    """Every generated function body, printed (groups of an unconstrained system are empty):

    mass, forcing, constraint_matrix, constraint_bias   one Block each
    system               M, F, A, b (and -A) for the augmented solve
    stabilization        the Baumgarte groups, minus the temporaries of `system`
    invariants           the invariants and the constraint values of the residual
    mass_rows, constraint_rows, system_rows    rows of printed entries; system_rows
                         are those of K = [[M, -A^T], [A, 0]]
    system_rhs           r = [F; b]
    stabilization_terms  (row of r, (A q' + d)_j, phi_j or None): r -= 2 alpha (A q' + d)
                         + beta^2 phi, phi for holonomic rows only
    residual             the values whose largest magnitude is constraint_residual
    """
    system = print_block(reduced, printer, SYSTEM, negated=("constraint_matrix",))
    stabilization = print_block(reduced, printer, POSITION, exclude=system)
    invariants = print_block(reduced, printer, ("invariants",) + POSITION)
    mass = print_block(reduced, printer, ("mass_matrix",))
    constraint_matrix = print_block(reduced, printer, ("constraint_matrix",))
    return dict(
        mass=mass,
        forcing=print_block(reduced, printer, ("forcing",)),
        constraint_matrix=constraint_matrix,
        constraint_bias=print_block(reduced, printer, ("constraint_bias",)),
        system=system,
        stabilization=stabilization,
        invariants=invariants,
        mass_rows=_rows(mass.values["mass_matrix"], n),
        constraint_rows=_rows(constraint_matrix.values["constraint_matrix"], n),
        system_rows=_augmented_rows(system, n, m),
        system_rhs=system.values["forcing"] + system.values["constraint_bias"],
        stabilization_terms=_stabilization_terms(stabilization, outputs, n),
        residual=invariants.values["constraint_position"] + invariants.values["constraint_velocity"],
    )


def generated_context(d: Derivation, printer_class, layout: Layout, initial=None, initial_notes=()) -> dict:
    """Everything a language's templates need, pre-printed by `printer_class`:
    `function_bodies`, the `Interface` of `layout` (the system's run interface; `initial`:
    see `about.interface`), the sizes n and m, the printer's `literal` and `imports`, and
    the constraint tolerance (lagcli.interface). The run rules are runtime code, not
    context (lagcli/runtime/)."""
    outputs, reduced = reduced_outputs(d, layout)
    printer = printer_for(d, reduced, printer_class)
    n, m = d.n, len(d.constraints)
    bodies = function_bodies(reduced, printer, outputs, n, m)
    return dict(
        bodies,
        i=interface(layout, initial, initial_notes), n=n, m=m,
        literal=printer_class.literal, imports=printer.imports(),
        constraint_tolerance=printer_class.literal(CONSTRAINT_TOLERANCE),
    )


def printer_for(d: Derivation, reduced: Reduced, printer_class) -> SlotPrinter:
    """A `printer_class` printing the symbols of `reduced` as slots, in the order of its terms
    when the CSE gave them an order (`Reduced.ordered`)."""
    printer = printer_class(slots(d, reduced, printer_class))
    return printer if reduced.ordered else printer.in_given_order()


def reduced_outputs(d: Derivation, layout: Layout) -> tuple[Outputs, Reduced]:
    """The expressions generated code evaluates and their one CSE: of the tidied
    expressions or of those as derived, whichever needs fewer operations (the tidied
    on a tie). Tidying lowers each small expression's operation count, which is what
    small systems gain from (the 8-link pendulum: 638 operations after CSE against
    746); on bigger systems the expansions share fewer parts than the derived
    expressions do (the 12-link pendulum: 1540 against 1534; specs/benchmark_bicycle.yaml:
    2618 against 2316), so outputs of more than TIDY_MAX_TOTAL_NODES tree nodes
    together are not tidied at all (tidying was a third of `generate` of the 20-link
    pendulum, bench/README.md)."""
    derived = collect(d, layout, tidy=False)
    optimizations = basic_optimizations()      # one memo of `tidy.factored` for both
    everything = [e for exprs in derived.groups().values() for e in exprs]
    tried = [tidied(derived, d.model.qd), derived] if small(everything, TIDY_MAX_TOTAL_NODES) else [derived]
    candidates = [(outputs, eliminate(outputs, optimizations)) for outputs in tried]
    if len(candidates) == 1:           # nothing to choose: no operation count (0.4 s at 40 links)
        return candidates[0]
    return min(candidates, key=lambda pair: pair[1].operation_count(GROUPS))


def _rows(values: tuple[str, ...], cols: int) -> tuple[tuple[str, ...], ...]:
    """Row-major printed entries -> one tuple per row."""
    return tuple(values[r * cols:(r + 1) * cols] for r in range(len(values) // cols)) if cols else ()


def _augmented_rows(system: Block, n: int, m: int) -> tuple[tuple[str, ...], ...]:
    """Rows of K = [[M, -A^T], [A, 0]] as printed entries."""
    M = system.values["mass_matrix"]
    A, negA = system.values["constraint_matrix"], system.negated["constraint_matrix"]
    top = [M[i * n:(i + 1) * n] + tuple(negA[j * n + i] for j in range(m)) for i in range(n)]
    bottom = [A[j * n:(j + 1) * n] + ("0",) * m for j in range(m)]
    return tuple(top + bottom)


def _stabilization_terms(block: Block, outputs: Outputs, n: int) -> tuple:
    """(row n + j of r, printed (A q' + d)_j, printed phi_j or None) for every constraint row."""
    phi = dict(zip(outputs.holonomic_rows, block.values["constraint_position"]))
    return tuple((n + j, w, phi.get(j)) for j, w in enumerate(block.values["constraint_velocity"]))
