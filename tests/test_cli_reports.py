"""`lagcli derive --text/--json` and `lagcli check` through the CLI, for every bundled spec.

JSON must carry the contract's keys, and every expression in it must parse back with
lagcli's own parser to the derivation's value (checked numerically at random points).
"""
import json
from pathlib import Path

import pytest
import sympy as sp
from click.testing import CliRunner

from lagcli import __version__
from lagcli.derive.pipeline import load_model
from lagcli.model.calculus import numerically_zero
from lagcli.cli import cli
from lagcli.derive import derive
from lagcli.render.spec_printer import parse_output

SPECS = sorted((Path(__file__).parent.parent / "specs").glob("*.yaml"))
ALL_FUNCTIONS = Path(__file__).parent / "data" / "all_functions.yaml"  # every function of the contract
DOCUMENTED_KEYS = {
    "name", "coordinates", "velocities", "parameters", "known", "dof", "scleronomic",
    "kinetic_energy", "mass_matrix", "potential_energy", "lagrangian", "generalized_forces",
    "equations", "constraints", "multipliers", "gyroscopic_matrix", "ignorable_coordinates",
    "conserved_quantities", "jacobi_integral", "energy_is_jacobi",
}


def run(*args):
    result = CliRunner().invoke(cli, list(args))
    return result


# Every spec's report parses back, the bicycles' too: their printed T and equations
# (65 000 to 270 000 characters, sums of hundreds of terms) are far over a spec's
# limits; parse_output reads lagcli's own output with lagcli.model.expr.OUTPUT_LIMITS.
ROUND_TRIP_SPECS = SPECS


@pytest.mark.parametrize("spec", ROUND_TRIP_SPECS + [ALL_FUNCTIONS], ids=lambda p: p.stem)
def test_json_round_trips(spec):
    result = run("derive", str(spec), "--json")
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert DOCUMENTED_KEYS <= set(report)
    d = derive(load_model(spec))
    back = lambda text: parse_output(text, d.model, d.multipliers)  # noqa: E731
    assert report["coordinates"] == [q.name for q in d.model.q]
    assert report["dof"] == d.dof
    pairs = [(back(report["kinetic_energy"][k]), getattr(d, k)) for k in ("T", "T2", "T1", "T0")]
    pairs += [(back(report["potential_energy"]), d.V), (back(report["lagrangian"]), d.L)]
    n = len(d.model.q)
    pairs += [(back(report["mass_matrix"][i][j]), d.mass_matrix[i, j]) for i in range(n) for j in range(n)]
    pairs += [(back(report["generalized_forces"][q.name]), d.generalized_forces[i])
              for i, q in enumerate(d.model.q)]
    pairs += [(back(eq["lhs"]) - back(eq["rhs"]), e.lhs - e.rhs)
              for eq, e in zip(report["equations"], d.equations)]
    pairs += [(back(c["d"]), row.d) for c, row in zip(report["constraints"], d.constraints)]
    pairs += [(back(c["expr"]), c_d.expr) for c, c_d in zip(report["conserved_quantities"], d.conserved)]
    if d.jacobi_integral is not None:
        pairs.append((back(report["jacobi_integral"]), d.jacobi_integral))
    assert numerically_zero([a - b for a, b in pairs])


@pytest.mark.parametrize("spec", SPECS, ids=lambda p: p.stem)
def test_text_report_has_every_section(spec):
    result = run("derive", str(spec))
    assert result.exit_code == 0, result.output
    for section in ("-- System --", "-- Energies --", "-- Generalized forces", "-- Equations of motion",
                    "-- Explicit form", "-- Conservation --"):
        assert section in result.stdout
    assert result.stderr == ""


def test_check_summarises(tmp_path):
    result = run("check", str(Path(__file__).parent.parent / "specs" / "ex6_9_two_wheels_axle.yaml"))
    assert result.exit_code == 0
    assert "0 holonomic, 1 nonholonomic" in result.stdout
    assert "DOF         : 2" in result.stdout
    assert "x, y, phi" in result.stdout


def test_output_file_is_written_and_stdout_is_empty(tmp_path):
    target = tmp_path / "out" / "eom.json"
    target.parent.mkdir()                # a missing directory is an error (tests/test_output_files.py)
    result = run("derive", str(SPECS[0]), "--json", "-o", str(target))
    assert result.exit_code == 0
    assert result.stdout == ""
    assert json.loads(target.read_text())["name"]


def test_failed_derivation_leaves_no_file(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("coordinates: [x]\nparticles:\n  P: {mass: 1, position: [x, y]}\n")
    target = tmp_path / "eom.json"
    result = run("derive", str(bad), "--json", "-o", str(target))
    assert result.exit_code == 2
    assert "unknown name 'y'" in result.stderr
    assert not target.exists() and list(tmp_path.iterdir()) == [bad]


def test_version_and_help():
    assert __version__ in run("--version").stdout
    assert {"derive", "check"} <= set(cli.commands)
    for command in cli.commands:
        result = run(command, "--help")
        assert result.exit_code == 0 and "Usage" in result.stdout, command


def test_simplify_switch_changes_display_only():
    spec = str(Path(__file__).parent.parent / "specs" / "double_pendulum.yaml")
    tidy = json.loads(run("derive", spec, "--json").stdout)
    raw = json.loads(run("derive", spec, "--json", "--no-simplify").stdout)
    d = derive(load_model(spec))
    a = parse_output(tidy["mass_matrix"][0][1], d.model)
    b = parse_output(raw["mass_matrix"][0][1], d.model)
    assert sp.count_ops(a) < sp.count_ops(b)
    assert numerically_zero([a - b])


def test_one_output_format_at_a_time():
    spec = str(SPECS[0])
    result = run("derive", spec, "--json", "--latex")
    assert result.exit_code == 2 and "choose one output format" in result.output
    assert run("derive", spec, "--standalone").exit_code == 2
    assert run("derive", spec, "--text").stdout == run("derive", spec).stdout


def test_a_report_expression_beyond_the_spec_limits_parses_back():
    """A bicycle-sized report prints expressions far over a spec's 20 000 characters;
    `parse_output` reads them back, a spec may not contain them."""
    from lagcli.errors import Loc, SpecError
    from lagcli.model.expr import Scope, parse

    model = load_model(Path(__file__).parent.parent / "specs" / "double_pendulum.yaml")
    text = " + ".join(f"{k}*sin(theta1)**2*theta2_dot" for k in range(1, 3001))   # ~80 000 characters
    theta1, theta2_dot = model.q[0], model.qd[1]
    assert sp.expand(parse_output(text, model) - 4501500 * sp.sin(theta1) ** 2 * theta2_dot) == 0
    with pytest.raises(SpecError, match="too large"):
        parse(text, Scope({}, model.t), Loc("spec.yaml"))
