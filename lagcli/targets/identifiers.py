"""Spec names as identifiers of a target language (`identifiers`).

Generated code computes with array slots (lagcli/targets/slots.py), so spec names reach a
target's grammar only where a generated file offers them by name: the fields of the
Rust `Parameters` struct, the index constants of the Rust crate, the index structs of
the MATLAB/Octave `<name>_info`. There a name that is a keyword (or a builtin a reader
would not expect to see shadowed) of the target gets a trailing underscore: `type` ->
`type_`, `end` -> `end_`. The rule is injective: a name that would collide with a
mangled one (`type_` when `type` is reserved) gets its own underscore too (`type__`).
"""
from __future__ import annotations

from lagcli.errors import EmitError


def identifier(name: str, reserved: frozenset[str]) -> str:
    """`name` with a trailing `_` when it, less its trailing underscores, is reserved."""
    return name + "_" if name.rstrip("_") in reserved else name


def identifiers(names, reserved: frozenset[str], target: str) -> dict[str, str]:
    """{name: identifier} for `names`, all distinct (an `EmitError` otherwise: names
    the spec checker accepts never collide, since the rule is injective)."""
    table = {name: identifier(name, reserved) for name in names}
    if len(set(table.values())) != len(table):
        raise EmitError(f"two names give the same {target} identifier: {sorted(table)}")
    return table
