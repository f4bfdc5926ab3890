"""What a generated file says about itself (`Interface`), as plain values.

Text from the spec (description, file name, notes) is kept as given here: each
template escapes it for its own grammar with the filters of `lagcli.render.escape`.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import PurePath

from lagcli.derive.result import Derivation
from lagcli.render.escape import shorten
from lagcli.targets.expressions import Outputs
from lagcli.interface import layout_of
from lagcli.interface import DEFAULT_BAUMGARTE

DESCRIPTION_LIMIT = 300   # characters of the spec's description repeated in file headers


@dataclass(frozen=True)
class Interface:
    """What a generated file says about itself, as plain values (names in spec order),
    read from the system's `lagcli.interface.Layout` plus what only generated files say."""

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
    initial: tuple[float, ...]           # full state, as given by the caller
    initial_notes: tuple[str, ...]
    settings: tuple[tuple[str, object], ...]
    baumgarte: tuple[float, float]


def interface(d: Derivation, outputs: Outputs, initial=None, initial_notes=()) -> Interface:
    """The interface of `d`'s generated code. `initial` is the full default state
    [q..., q'...] to embed (the caller makes it consistent with the constraints,
    e.g. `lagcli.analysis.initial_state.spec_initial_state`; emit never solves for it), with
    `initial_notes` saying what was solved for; None: the spec's `initial:` as given
    (missing values 0)."""
    from lagcli import __version__

    model, layout = d.model, layout_of(d)
    if initial is None:
        given = dict(model.initial)
        initial = tuple(float(given.get(name, 0.0)) for name in layout.state_names)
    return Interface(
        name=layout.name,
        spec_file=PurePath(model.source).name,
        version=__version__,
        description=shorten(model.description or "", DESCRIPTION_LIMIT),
        coordinates=layout.coordinates,
        state=layout.state_names,
        parameters=tuple((p.name, p.default) for p in layout.parameters),
        inputs=tuple((u.name, u.default) for u in layout.inputs),
        multipliers=layout.multiplier_names,
        invariants=tuple(c.name for c in layout.invariants),
        evaluated=tuple(c.name for c in layout.invariants if c.kind != "residual"),
        residual=next((c.name for c in layout.invariants if c.kind == "residual"), None),
        initial=tuple(float(v) for v in initial),
        initial_notes=tuple(initial_notes),
        settings=tuple((key, value if key == "method" else float(value))
                       for key, value in layout.settings.as_dict().items()),
        baumgarte=tuple(float(v) for v in DEFAULT_BAUMGARTE),
    )

