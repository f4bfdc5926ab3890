"""Spec reading and validation: `load_spec(path)` turns a YAML/TOML file into a `Spec`.

The submodules are imported on first use: `lagcli.spec.files` (reading a spec's
bytes) must stay light for the warm C path of `simulate`, which imports it.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from lagcli.spec.types import Spec

__all__ = ["RawDoc", "Spec", "load_spec", "read_document", "validate"]
_HOMES = {"RawDoc": "reader", "read_document": "reader", "validate": "schema", "Spec": "types"}


def load_spec(path: str | Path) -> "Spec":
    """Read and validate the spec at `path`; raise `SpecError` (exit status 2) on any problem."""
    from lagcli.spec.reader import read_document
    from lagcli.spec.schema import validate

    return validate(read_document(path))


def __getattr__(name: str):
    if name not in _HOMES:
        raise AttributeError(f"module 'lagcli.spec' has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(f"lagcli.spec.{_HOMES[name]}"), name)
