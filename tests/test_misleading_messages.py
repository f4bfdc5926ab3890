"""Messages that must not mislead: the true problem, at its line, with a true hint, and
no false second error after it (issue 25). The messages themselves are cases of the
bad-spec corpus (tests/data/bad/); these tests check what the corpus cannot: that a
wrong message is absent."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from test_bad_specs import run_check

BAD = Path(__file__).parent / "data" / "bad"


def _stderr(case: str, monkeypatch) -> str:
    monkeypatch.chdir(BAD)
    result = run_check(case)
    assert result.exit_code == 2, result.output
    return result.stderr


def test_a_parameter_in_a_parameter_value_is_not_called_unknown(monkeypatch):
    stderr = _stderr("parameter_uses_parameter.yaml", monkeypatch)
    assert "unknown name" not in stderr and "definitions:" in stderr


def test_a_toml_key_in_the_table_above_gives_no_false_unknown_name(monkeypatch):
    stderr = _stderr("toml_misplaced_keys_only.toml", monkeypatch)
    assert stderr.count("it looks like a top-level key") == 2
    assert "unknown name" not in stderr


def test_a_yaml_equals_sign_is_reported_on_its_own_line_with_a_hint(monkeypatch):
    stderr = _stderr("yaml_equals_sign.yaml", monkeypatch)
    assert stderr.startswith("yaml_equals_sign.yaml:4:") and "write 'g: 9.81'" in stderr


def test_an_unclosed_toml_array_points_where_it_opened(monkeypatch):
    assert _stderr("toml_unclosed_array.toml", monkeypatch).startswith("toml_unclosed_array.toml:2:1:")


def test_toml_unit_hints_are_written_in_toml(monkeypatch):
    for case in ("toml_unit_in_string.toml", "toml_unit_in_inline_table.toml", "toml_unit_after_number.toml"):
        stderr = _stderr(case, monkeypatch)
        assert '{value = 1.0, unit = "kg"}' in stderr or 'unit = "' in stderr, stderr
        assert "unit: kg}" not in stderr and "lhs - rhs" not in stderr, stderr


def test_the_repair_note_names_initial_when_no_init_was_given():
    # x_dot is solved for from the spec's own y_dot: the note used to say "(--init)"
    import lagcli

    system = lagcli.load("coordinates: [x, y]\nparameters: {m: 1.0, l: 1.0, g: 9.81}\ngravity: [0, -g]\n"
                         "particles: {P: {mass: m, position: [x, y]}}\nconstraints: [x**2 + y**2 - l**2]\n"
                         "initial: {x: 0.6, y: -0.8, y_dot: 0.5}\n")
    (note,) = system.spec_start()[0].notes
    assert note.endswith("x_dot = 0.666666666667 from y_dot (initial:)"), note     # 0.8 * 0.5 / 0.6
    assert "--init" not in note


AT_REST_SPEC = "coordinates: [x]\nparameters: {m: 1.0, k: 2.0}\nkinetic: m*x_dot**2/2\npotential: k*x**2/2\n"


def _simulate(tmp_path, *args):
    from click.testing import CliRunner

    from lagcli.cli import cli

    spec = tmp_path / "spring.yaml"
    spec.write_text(AT_REST_SPEC)
    try:
        runner = CliRunner(mix_stderr=False)
    except TypeError:
        runner = CliRunner()
    return runner.invoke(cli, ["simulate", str(spec), "--t-end", "0.02", *args])


BACKENDS = ["python", pytest.param("c", marks=pytest.mark.skipif(shutil.which("cc") is None,
                                                                 reason="no C compiler (cc)"))]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_spec_without_initial_says_it_starts_at_rest(tmp_path, backend, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    for _ in range(2):                                   # cold, then (C) warm
        result = _simulate(tmp_path, "--backend", backend)
        assert result.exit_code == 0, result.output
        assert "starts at rest with every coordinate 0" in result.stderr
    assert "at rest" not in _simulate(tmp_path, "--backend", backend, "--init", "x=0.1").stderr
    assert _simulate(tmp_path, "--backend", backend, "-q").stderr == ""


@pytest.mark.parametrize("backend", BACKENDS)
def test_set_mass_zero_is_refused_by_physical_validation(tmp_path, backend, monkeypatch):
    # not a run-time "singular mass matrix" at t = 0: on the cold path and, with C, the warm one
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    assert _simulate(tmp_path, "--backend", backend, "--init", "x=0.1").exit_code == 0
    result = _simulate(tmp_path, "--backend", backend, "--init", "x=0.1", "--set", "m=0")
    assert result.exit_code == 2, result.output
    assert "--set m=0: " in result.stderr and "the mass matrix is singular at the initial state" in result.stderr
    assert "integration failed" not in result.stderr


def test_set_values_whose_products_overflow_are_refused_by_physical_validation(tmp_path, monkeypatch):
    # each value is a double, m1 l1^2 = 1e897 in the mass matrix is not: refused before the run
    # (it was a run-time "accelerations are not finite" at t = 0)
    from click.testing import CliRunner

    from conftest import SPECS
    from lagcli.cli import cli

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    result = CliRunner().invoke(cli, ["simulate", str(SPECS / "double_pendulum.yaml"), "--set", "m1=1e299",
                                      "--set", "l1=1e299", "--t-end", "0.01", "--backend", "python"])
    assert result.exit_code == 2, result.output
    assert "the mass matrix's row of theta1 is not a finite number at the initial state" in result.output
    assert "integration failed" not in result.output
