"""The library entry points behind the CLI: path -> Model -> Derivation."""
from __future__ import annotations

from pathlib import Path

from lagcli.derive import derive
from lagcli.derive.result import Derivation
from lagcli.model import build_model
from lagcli.model_types import Model
from lagcli.spec import load_spec


def load_model(path: str | Path) -> Model:
    """Read, validate and build the model of a spec file (raises SpecError)."""
    return build_model(load_spec(str(path)))


def derive_file(path: str | Path) -> Derivation:
    return derive(load_model(path))
