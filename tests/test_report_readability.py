"""What a teacher would put on a slide: the reports' expressions are tidy, ordered as the
lecture notes write them, and nothing is printed twice.

- Tidy: sympy's trigsimp (an independent, thorough simplifier that lagcli does not use
  for display) cannot shrink a printed energy, mass-matrix entry or integral by more
  than a small tolerance (common factors aside: T is printed as a sum of terms, as in
  the notes): no sin**2 + cos**2 left in T of the heavy top, Ex 18, wedge, nor where
  one identity opens the way for another (bead on a spinning hoop, sphere on a turntable).
- Ordered: in every equation of motion the q'' terms come first.
- Once: no two lines of the text report state the same thing.
- Exact: printed expressions equal the derivation's (tests/test_cli_reports.py parses
  the JSON back and compares at random points; here the ordered equations are checked
  the same way).
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner

from lagcli.derive.pipeline import load_model
from lagcli.model.calculus import numerically_zero
from lagcli.cli import cli
from lagcli.derive import derive
from lagcli.render.spec_printer import parse_output

SPECS = Path(__file__).resolve().parent.parent / "specs"
ALL = sorted(SPECS.glob("*.yaml"))
TOLERANCE = 0.1          # trigsimp may find at most 10% fewer operations (+ 2)


def _report(spec: Path, *args) -> str:
    result = CliRunner().invoke(cli, ["derive", str(spec), *args])
    assert result.exit_code == 0, result.output
    return result.stdout


SMALL_SPECS = tuple(p.stem for p in ALL if "bicycle" not in p.stem)   # trigsimp takes minutes on a bicycle


@pytest.mark.core_specs
@pytest.mark.parametrize("name", SMALL_SPECS)
def test_printed_expressions_do_not_simplify_further(name):
    spec = SPECS / f"{name}.yaml"
    report = json.loads(_report(spec, "--json"))
    d = derive(load_model(spec))
    texts = {"T": report["kinetic_energy"]["T"], "T2": report["kinetic_energy"]["T2"],
             "V": report["potential_energy"], "L": report["lagrangian"]}
    texts.update({f"M[{i}][{j}]": e for i, row in enumerate(report["mass_matrix"]) for j, e in enumerate(row)})
    texts.update({c["name"]: c["expr"] for c in report["conserved_quantities"]})
    for label, text in texts.items():
        printed = parse_output(text, d.model)
        ops = sp.count_ops(sp.factor_terms(printed))   # a sum of terms as printed, common factors aside
        simplest = sp.count_ops(sp.trigsimp(printed))
        assert ops <= simplest * (1 + TOLERANCE) + 2, f"{name} {label}: {text} ({ops} ops, trigsimp {simplest})"


def test_heavy_top_energy_has_no_pythagorean_residue():
    report = json.loads(_report(SPECS / "heavy_symmetric_top.yaml", "--json"))
    for text in (report["kinetic_energy"]["T"], report["lagrangian"], report["jacobi_integral"]):
        assert "phi)**2" not in text and "psi)**2" not in text, text   # sin(phi)**2 + cos(phi)**2 was there


def _top_level_terms(text: str) -> list[str]:
    """The terms of a printed sum, split at + and - outside parentheses."""
    terms, depth, current = [], 0, ""
    for i, ch in enumerate(text):
        depth += ch == "("
        depth -= ch == ")"
        if depth == 0 and ch in "+-" and i > 0 and text[i - 1] == " " and text[i + 1:i + 2] == " ":
            terms.append(current.strip())
            current = ""
        else:
            current += ch
    return [*terms, current.strip()]


@pytest.mark.parametrize("spec", ALL, ids=lambda p: p.stem)
def test_equations_lead_with_the_accelerations(spec):
    report = json.loads(_report(spec, "--json"))
    d = derive(load_model(spec))
    for eq, derived in zip(report["equations"], d.equations):
        has_qdd = ["_ddot" in term for term in _top_level_terms(eq["lhs"])]
        first_other = has_qdd.index(False) if False in has_qdd else len(has_qdd)
        assert not any(has_qdd[first_other:]), f"{spec.stem}: q'' term after others in {eq['lhs']}"
        back = parse_output(eq["lhs"], d.model, d.multipliers) - parse_output(eq["rhs"], d.model, d.multipliers)
        assert numerically_zero([back - (derived.lhs - derived.rhs)])


@pytest.mark.parametrize("spec", ALL, ids=lambda p: p.stem)
def test_no_statement_is_printed_twice(spec):
    lines = [line.strip() for line in _report(spec).splitlines() if " = " in line]
    repeated = {line for line in lines if lines.count(line) > 1}
    assert not repeated, f"{spec.stem}: printed more than once: {sorted(repeated)}"


def test_equal_energies_are_said_once():
    text = _report(SPECS / "double_pendulum.yaml")
    assert "T  = T2 = " in text and "\nT2 = " not in text
    assert "h = T2 - T0 + V = T + V = E = " in text and "conserved energy" not in text
    assert "jacobi jacobi" not in text


def test_no_double_negative_in_ex20():
    text = _report(SPECS / "ex20_spinning_disk_double_pendulum.yaml")
    assert "-(-" not in text and "- m*Omega**2*l**2*(-" not in text


CLASHING_SPEC = """\
name: clash
coordinates: [th]
parameters: {L: 2.0, M: 1.0, h: 0.5, T: 3.0, g: 9.81}
gravity: [0, -g]
particles:
  P: {mass: M, position: ['L*sin(th)', '-L*cos(th) + h']}
potential: T*th**2/2
"""


def test_parameters_named_like_the_report_notation_keep_their_names(tmp_path):
    """The user's names win: the report's own T, L, M, h yield (Tkin, Lag, Mmat), the
    parameters keep theirs (tests/test_user_names_win.py checks every surface)."""
    import re

    spec = tmp_path / "clash.yaml"
    spec.write_text(CLASHING_SPEC)
    text = _report(spec)
    assert "L = 2.0, M = 1.0, h = 0.5, T = 3.0, g = 9.81" in text
    assert "notation          : Tkin = the kinetic energy, Lag = the Lagrangian, Mmat = the mass matrix, hJac = the Jacobi integral (T, L, M and h are the spec's own)" in text
    for line in text.splitlines():
        label, _, expression = line.partition(" = ")
        assert label.strip() not in {"T", "L", "M", "h"}, line
    assert not re.search(r"\b[TLMh]_\b", text)
    report = json.loads(_report(spec, "--json"))
    assert set(report["parameters"]) == {"L", "M", "h", "T", "g"}     # the JSON parses back
    assert report["renamed_parameters"] == {}


@pytest.mark.parametrize("spec, reason", [
    ("ex18_slider_compound_pendulum", "the non-conservative forces Q' are not zero"),   # F at the tip
    ("ex19_oscillating_support", "L depends explicitly on t"),                        # support a cos(w t)
    ("sphere_on_turntable", "constraint 1 has a term d free of velocities"),          # the table turns
    ("double_pendulum", None),
])
def test_the_report_says_why_there_is_no_jacobi_integral(spec, reason):
    """The physical obstacle, as the lecture notes state the conditions for h."""
    content = json.loads(_report(SPECS / f"{spec}.yaml", "--json"))
    assert content["no_jacobi_reason"] == reason
    assert (content["jacobi_integral"] is None) == (reason is not None)
    if reason:
        assert f"no Jacobi integral: {reason}" in _report(SPECS / f"{spec}.yaml")
