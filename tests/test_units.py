"""Units (docs/spec.md, "Units"): optional, and checked when given.

The errors (a force where a torque belongs, an inconsistent sum, an unknown unit) are
cases of the bad-spec corpus, tests/data/bad/units_*.yaml and unit_unknown.yaml.
"""
from __future__ import annotations

from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner

import lagcli
from lagcli.errors import Loc, SpecError
from lagcli.model.units import (ENERGY, FORCE, LENGTH, NONE, TIME, Mismatch, check_derivation_units, dimension_of,
                          unit_dimension)

CONSISTENT = Path(__file__).parent / "data" / "units_cart_pendulum.yaml"


def _runner() -> CliRunner:
    try:
        return CliRunner(mix_stderr=False)
    except TypeError:
        return CliRunner()


def test_a_consistent_spec_passes_check_and_shows_its_units():
    from lagcli.cli import cli

    result = _runner().invoke(cli, ["check", str(CONSISTENT)])
    assert result.exit_code == 0, result.stderr
    assert "m = 1 kg" in result.stdout and "tau = 0.1 N*m" in result.stdout


def test_every_term_of_the_derivation_is_consistent():
    system = lagcli.load(CONSISTENT)
    check_derivation_units(system.derivation)            # raises on any mismatch


def test_a_force_in_place_of_a_torque_is_rejected_naming_the_term():
    text = CONSISTENT.read_text().replace("torque: tau}", "torque: F}")
    with pytest.raises(SpecError) as caught:
        lagcli.load(text)
    message = str(caught.value)
    assert "forces[0].torque" in message and "'F' is a force" in message


@pytest.mark.parametrize("unit,dimension", [
    ("kg*m/s^2", FORCE), ("N", FORCE), ("N*m", ENERGY), ("J", ENERGY), ("m", LENGTH),
    ("ms", TIME), ("rad", NONE), ("deg", NONE), ("km/h*s", LENGTH),
])
def test_units_are_read_from_sympy_physics_units_names(unit, dimension):
    assert unit_dimension(unit, Loc("test")) == dimension


@pytest.mark.parametrize("unit", ["__import__('os')", "kg.m", "metre_per_banana", "'kg'"])
def test_a_unit_is_never_evaluated_as_python(unit):
    with pytest.raises(SpecError):
        unit_dimension(unit, Loc("test"))


def test_function_arguments_must_be_dimensionless():
    x, l = sp.symbols("x l", real=True)
    dims = {x: LENGTH, l: LENGTH}
    assert dimension_of(sp.sin(x / l), dims) == NONE
    with pytest.raises(Mismatch):
        dimension_of(sp.sin(x), dims)
    with pytest.raises(Mismatch):
        dimension_of(sp.exp(x) * l, dims)


def test_without_units_nothing_is_checked():
    lagcli.load("coordinates: [x]\nparameters: {m: 1.0, F: 2.0}\nparticles:\n  P: {mass: m, position: [x, 0]}\n"
                "generalized_forces: {x: F + m}\n")
