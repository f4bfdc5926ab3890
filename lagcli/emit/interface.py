"""What a generated file says about itself (`Interface`), as plain values.

Text from the spec (description, file name, notes) is kept as given here: each
template escapes it for its own grammar with the filters of `lagcli.emit.escape`.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import PurePath

from lagcli.derive.result import Derivation
from lagcli.emit.escape import shorten
from lagcli.emit.outputs import Outputs
from lagcli.numerics import DEFAULT_BAUMGARTE

DESCRIPTION_LIMIT = 300   # characters of the spec's description repeated in file headers


@dataclass(frozen=True)
class Interface:
    """What a generated file says about itself, as plain values (names in spec order)."""

    name: str
    spec_file: str                       # file name only: the bytes do not depend on the cwd
    version: str
    description: str                     # one line, at most DESCRIPTION_LIMIT characters
    coordinates: tuple[str, ...]
    state: tuple[str, ...]
    parameters: tuple[tuple[str, float], ...]
    multipliers: tuple[str, ...]
    invariants: tuple[str, ...]          # CSV invariant columns, constraint_residual included
    initial: tuple[float, ...]           # full state, as given by the caller
    initial_notes: tuple[str, ...]
    settings: tuple[tuple[str, object], ...]
    baumgarte: tuple[float, float]


def interface(d: Derivation, outputs: Outputs, initial=None, initial_notes=()) -> Interface:
    """The interface of `d`'s generated code. `initial` is the full default state
    [q..., q'...] to embed (the caller makes it consistent with the constraints,
    e.g. `lagcli.simulate.initial.spec_initial_state`; emit never solves for it), with
    `initial_notes` saying what was solved for; None: the spec's `initial:` as given
    (missing values 0)."""
    from lagcli import __version__

    model = d.model
    s = model.settings
    if initial is None:
        given = dict(model.initial)
        initial = tuple(float(given.get(x.name, 0.0)) for x in model.q + model.qd)
    columns = outputs.invariant_names + (("constraint_residual",) if d.constraints else ())
    return Interface(
        name=model.name,
        spec_file=PurePath(model.source).name,
        version=__version__,
        description=shorten(model.description or "", DESCRIPTION_LIMIT),
        coordinates=tuple(s.name for s in model.q),
        state=tuple(s.name for s in model.q + model.qd),
        parameters=tuple((p.symbol.name, float(p.value)) for p in model.parameters),
        multipliers=tuple(m.name for m in d.multipliers),
        invariants=columns,
        initial=tuple(float(v) for v in initial),
        initial_notes=tuple(initial_notes),
        settings=(("t_end", float(s.t_end)), ("dt", float(s.dt)), ("method", s.method),
                  ("rtol", float(s.rtol)), ("atol", float(s.atol))),
        baumgarte=tuple(float(v) for v in DEFAULT_BAUMGARTE),
    )

