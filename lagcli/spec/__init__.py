"""Spec reading and validation: `load_spec(path)` turns a YAML/TOML file into a `Spec`."""
from __future__ import annotations

from pathlib import Path

from lagcli.spec.reader import RawDoc, read_document
from lagcli.spec.schema import validate
from lagcli.spec.types import Spec

__all__ = ["RawDoc", "Spec", "load_spec", "read_document", "validate"]


def load_spec(path: str | Path) -> Spec:
    """Read and validate the spec at `path`; raise `SpecError` (exit status 2) on any problem."""
    return validate(read_document(path))
