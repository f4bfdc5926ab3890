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


PROJECTILE = """coordinates: [{name: x, unit: m}, {name: y, unit: m}]
parameters: {m: {value: 1.0, unit: kg}, g: {value: 9.81, unit: m/s^2}}
gravity: [0, -g]
particles: {P: {mass: m, position: [x, y]}}
"""


def test_a_zero_generalized_force_fits_every_dimension():
    # Q_x = 0 for the simplest projectile: zero is a force per metre as much as anything
    system = lagcli.load(PROJECTILE)
    assert system.derivation.generalized_forces[0] == 0
    check_derivation_units(system.derivation)


def test_inputs_take_a_unit_and_are_checked_with_it():
    spec = PROJECTILE + "inputs: {F: {value: 0.5, unit: N}}\nforces: [{at: P, force: [F, 0]}]\n"
    check_derivation_units(lagcli.load(spec).derivation)
    with pytest.raises(SpecError, match=r"the force should be a force, N \(kg\*m/s\*\*2\) but 'F' is a mass"):
        lagcli.load(spec.replace("unit: N}", "unit: kg}"))


@pytest.mark.parametrize("unit", ["exp(kg)", "sin(m)", "atan2(m, s)", "m + s"])
def test_a_function_of_a_unit_is_refused_as_a_unit(unit):
    with pytest.raises(SpecError, match="is not a product of powers of units"):
        unit_dimension(unit, Loc("spec.yaml"))


def test_unit_messages_speak_the_derived_units_of_the_docs():
    # a stiffness is N/m in docs/spec.md: the message says so, with its base units beside it
    text = CONSISTENT.read_text().replace("k: {value: 10.0, unit: N/m}", "k: {value: 10.0, unit: N}")
    with pytest.raises(SpecError, match=r"stiffness should be N/m \(kg/s\*\*2\) but 'k' is a force, N"):
        lagcli.load(text)
