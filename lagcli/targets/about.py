"""What a generated file says about itself (`Interface`), as plain values: the one
computation, over the system's run interface (`lagcli.interface.Layout`), of what every
code target writes about a system — names, defaults, the CSV header, units, the fields
a target makes identifiers of, the settings and the default state.

Text from the spec (description, file name, notes) is kept as given here: each
template escapes it for its own grammar with the filters of `lagcli.render.escape`.
"""
from __future__ import annotations

from dataclasses import dataclass

from lagcli.interface import DEFAULT_BAUMGARTE, Layout
from lagcli.render.escape import shorten

DESCRIPTION_LIMIT = 300   # characters of the spec's description repeated in file headers


@dataclass(frozen=True)
class Interface:
    """What a generated file says about itself, as plain values (names in spec order),
    read from the system's `Layout` (kept as `layout`: its settings, inputs and units)
    plus what only generated files say."""

    layout: Layout
    name: str
    spec_file: str                       # file name only: the bytes do not depend on the cwd
    version: str
    description: str                     # one line, at most DESCRIPTION_LIMIT characters
    coordinates: tuple[str, ...]
    state: tuple[str, ...]
    parameters: tuple[tuple[str, float], ...]
    inputs: tuple[tuple[str, float], ...]  # (name, default) in spec order: u
    multipliers: tuple[str, ...]
    invariants: tuple[str, ...]          # CSV invariant columns, constraint_residual included
    evaluated: tuple[str, ...]           # those with an expression (all but the residual)
    residual: str | None                 # the residual column, when constrained
    residual_index: int | None           # its place among `invariants`
    header: tuple[str, ...]              # the CSV columns, in order (`Layout.header`)
    fields: tuple[str, ...]              # the names a target makes identifiers of (`Layout.fields`)
    initial: tuple[float, ...]           # full state, as given by the caller
    initial_notes: tuple[str, ...]
    settings: tuple[tuple[str, object], ...]
    baumgarte: tuple[float, float]


def interface(layout: Layout, initial=None, initial_notes=()) -> Interface:
    """The interface of a system's generated code. `initial` is the full default state
    [q..., q'...] to embed (the caller makes it consistent with the constraints,
    e.g. `lagcli.analysis.initial_state.spec_initial_state`; emit never solves for it), with
    `initial_notes` saying what was solved for; None: the spec's `initial:` as given
    (missing values 0)."""
    if initial is None:
        initial = tuple(float(layout.initial.get(name, 0.0)) for name in layout.state_names)
    residual = layout.residual_index
    return Interface(
        layout=layout,
        name=layout.name,
        spec_file=layout.source.file,
        version=layout.source.version,
        description=shorten(layout.source.description, DESCRIPTION_LIMIT),
        coordinates=layout.coordinates,
        state=layout.state_names,
        parameters=tuple((p.name, p.default) for p in layout.parameters),
        inputs=tuple((u.name, u.default) for u in layout.inputs),
        multipliers=layout.multiplier_names,
        invariants=layout.invariant_names,
        evaluated=tuple(c.name for c in layout.invariants if c.kind != "residual"),
        residual=None if residual is None else layout.invariant_names[residual],
        residual_index=residual,
        header=layout.header,
        fields=layout.fields,
        initial=tuple(float(v) for v in initial),
        initial_notes=tuple(initial_notes),
        settings=tuple((key, value if key == "method" else float(value))
                       for key, value in layout.settings.as_dict().items()),
        baumgarte=tuple(float(v) for v in DEFAULT_BAUMGARTE),
    )
