"""A big C function body in parts: gcc's optimizer is superlinear in the size of one function.

The body of the 100-link chain's right-hand side is ~20 000 statements in one function:
`gcc -O2` needed more than 7 minutes and 1.3 GB for it (bench/README.md, issue 24). Above
`MAX_STATEMENTS` statements, a body (its temporaries, then its stores into the output
arrays, as printed) is cut into runs of at most `PART_STATEMENTS` statements, each a static
function of its own, called in order. A temporary that a later part uses is stored into a
`double shared[]` array on the caller's stack by the part that computes it and read back
as a `const double` by each part that uses it, so the printed statements are the same as
in one body and gcc sees only a bounded function at a time.

    split_body    statements -> Parts (None when the body is small: printed in one piece)

A temporary is `x<k>` (lagcli/targets/slots.py): its uses are found in the printed code.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

MAX_STATEMENTS = 1000     # a body of more statements is split (the 20-link chain: 917 at most)
PART_STATEMENTS = 250     # statements per part

TEMPORARY = re.compile(r"\bx\d+\b")


@dataclass(frozen=True)
class Part:
    """One part function's body: reads `loads` ((temporary, slot of shared)), runs
    `statements` (printed C), then keeps `stores` ((slot, temporary)) for later parts."""

    loads: tuple[tuple[str, int], ...]
    statements: tuple[str, ...]
    stores: tuple[tuple[int, str], ...]


@dataclass(frozen=True)
class Parts:
    """A body in parts, in calling order; `shared`: the size of the shared array (>= 1);
    `after`: the loads ((temporary, slot)) of the code the caller runs after the parts."""

    parts: tuple[Part, ...]
    shared: int
    after: tuple[tuple[str, int], ...] = ()


def split_body(temporaries, stores, after=(), limit: int | None = None, size: int | None = None):
    """`temporaries` ((name, code), ...) and `stores` (C statements writing the outputs) in
    parts, or None when there are at most `limit` (MAX_STATEMENTS) statements of both.
    `after`: code the caller runs after the parts, as it prints it (the right-hand side's
    stabilisation, which may use the body's temporaries): a temporary it uses is kept too."""
    limit = MAX_STATEMENTS if limit is None else limit
    size = PART_STATEMENTS if size is None else size
    statements = [(name, f"const double {name} = {code};") for name, code in temporaries]
    statements += [(None, text) for text in stores]
    if len(statements) <= limit:
        return None
    runs = [statements[k:k + size] for k in range(0, len(statements), size)]
    runs.append([(None, text) for text in after])
    defined = {name: k for k, run in enumerate(runs) for name, _ in run if name is not None}
    used = [_uses(run, defined, k) for k, run in enumerate(runs)]
    slot = {name: k for k, name in enumerate(sorted(set().union(*used), key=_number))}
    parts = tuple(Part(loads=_loads(used[k], slot), statements=tuple(text for _, text in run),
                       stores=tuple((slot[name], name) for name, _ in run if name in slot))
                  for k, run in enumerate(runs[:-1]))
    return Parts(parts, max(len(slot), 1), _loads(used[-1], slot))


def _loads(names, slot: dict) -> tuple[tuple[str, int], ...]:
    return tuple((name, slot[name]) for name in sorted(names, key=_number))


def _uses(run, defined: dict, k: int) -> set:
    """The temporaries of earlier parts that the run `k` uses."""
    found = set()
    for _, text in run:
        found.update(name for name in TEMPORARY.findall(text) if defined.get(name, k) < k)
    return found


def _number(name: str) -> int:
    return int(name[1:])
