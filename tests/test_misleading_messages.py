"""Messages that must not mislead: the true problem, at its line, with a true hint, and
no false second error after it (issue 25). The messages themselves are cases of the
bad-spec corpus (tests/data/bad/); these tests check what the corpus cannot: that a
wrong message is absent."""
from __future__ import annotations

from pathlib import Path

from test_bad_specs import run_check

BAD = Path(__file__).parent / "data" / "bad"


def _stderr(case: str, monkeypatch) -> str:
    monkeypatch.chdir(BAD)
    result, _ = run_check(case)
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
