"""The library entry points behind the CLI: path (or spec text) -> Model -> Derivation."""
from __future__ import annotations

from pathlib import Path

import sympy as sp

import lagcli.derive
from lagcli.model.collector import collector_paused
from lagcli.derive.representable import refuse_unrepresentable
from lagcli.derive.result import Derivation
from lagcli.model.build import build_model
from lagcli.model.model_types import Model
from lagcli.errors import Problem, SpecError
from lagcli.spec.reader import parse_text, read_document
from lagcli.spec.schema import check
from lagcli.model.units import check_model_units
from lagcli.model.validation import check_mass_matrix, check_model


TEXT_SOURCE = "<string>"      # where problems of a spec given as text are located


def load_model(path: str | Path, data: bytes | None = None) -> Model:
    """Read, validate and build the model of a spec file (raises SpecError); `data`: its
    bytes when the caller has read them already (read once per command).

    When the spec has format problems, its expressions are still parsed where
    possible so that one run reports every problem (all together, as the docs say)."""
    return _build(read_document(str(path), data))


def load_model_text(text: str, toml: bool = False) -> Model:
    """`load_model` for a spec given as YAML (or TOML) text; problems are located in
    `<string>` (line and column as in a file)."""
    return _build(parse_text(TEXT_SOURCE, text, toml))


def _build(raw) -> Model:
    spec, problems = check(raw)
    if not problems:
        with collector_paused():
            model = build_model(spec)
            check_model(model)
            check_model_units(model)
        return model
    raise SpecError(problems + [p for p in _expression_problems(spec) if p not in problems])


def _expression_problems(spec) -> list:
    """Problems the model stage finds in a spec that already failed validation."""
    try:
        build_model(spec)
    except SpecError as exc:
        return exc.problems
    except Exception:  # noqa: BLE001 - a malformed spec may trip the builder; the first problems stand
        return []
    return []


def derive_model(model: Model) -> Derivation:
    """`derive(model)`, refusing a mass matrix that is singular everywhere (lagcli.model.validation)."""
    with collector_paused():
        derivation = lagcli.derive.derive(model)     # looked up at call time (tests patch it)
        refuse_unrepresentable(derivation)
        check_mass_matrix(derivation)
    return derivation


def derive_file(path: str | Path) -> Derivation:
    return derive_model(load_model(path))
