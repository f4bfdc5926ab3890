"""The JSON Schema (draft 2020-12) of spec files, made from the tables the checker uses.

`lagcli schema` prints it; editors use it for completion and validation of YAML and
TOML specs (docs/spec.md, "Editor support"). Each `Table` of lagcli/spec/format.py
becomes an object in `$defs` with exactly its keys (`additionalProperties: false`)
and its required ones; the shapes (`expression`, `vector`, ...) are `$defs` too.
Only json is needed: no sympy, no yaml.
"""
from __future__ import annotations

import json
from typing import Any

from lagcli.spec.format import SHAPES, TOP, Table, ref

DRAFT = "https://json-schema.org/draft/2020-12/schema"


def json_schema() -> dict:
    """The schema of a whole spec, as plain data."""
    defs: dict[str, Any] = dict(SHAPES)
    root = _object(TOP, defs)
    return {"$schema": DRAFT, "title": "lagcli spec", **root,
            "$defs": {name: defs[name] for name in sorted(defs)}}


def json_schema_text() -> str:
    return json.dumps(json_schema(), indent=2) + "\n"


def _object(table: Table, defs: dict) -> dict:
    out: dict[str, Any] = {"type": "object", "description": table.description,
                           "properties": {key: _shape(shape, defs) for key, shape in table.keys.items()},
                           "additionalProperties": False}
    if table.required:
        out["required"] = list(table.required)
    return out


def _shape(shape: Any, defs: dict) -> Any:
    """A shape with every `Table` in it replaced by a reference to its $defs entry."""
    if isinstance(shape, Table):
        if shape.name not in defs:
            defs[shape.name] = {}                      # taken before recursing: names are unique
            defs[shape.name] = _object(shape, defs)
        return ref(shape.name)
    if isinstance(shape, dict):
        return {key: _shape(value, defs) for key, value in shape.items()}
    if isinstance(shape, list):
        return [_shape(item, defs) for item in shape]
    return shape
