"""Every bad spec is refused by `lagcli check` with exit status 2 and a located message.

The corpus is `tests/data/bad/`: one small spec per error class, `<case>.yaml` or
`<case>.toml`, and beside it `<case>.expected`, whose every non-empty line must
appear in stderr (the first line usually starts with `file:line:column: key.path:`).
The check runs from inside that directory, so messages name the bare file.
"""
from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

BAD = Path(__file__).parent / "data" / "bad"
CASES = sorted(p for p in BAD.iterdir() if p.suffix in (".yaml", ".yml", ".toml"))
# hostile input must be refused quickly, never hang: a hang is caught by pytest-timeout
# (a guard on the test run, not a timing assertion: see pytestmark)
pytestmark = pytest.mark.timeout(120)


def run_check(path: str):
    """Run `lagcli check PATH`; return click's result."""
    from lagcli.cli import cli

    try:
        runner = CliRunner(mix_stderr=False)  # click < 8.2 keeps stderr apart only on request
    except TypeError:
        runner = CliRunner()
    return runner.invoke(cli, ["check", path])


def assert_refused(result, expected: list[str]) -> None:
    shown = f"exit {result.exit_code}\nstdout:\n{result.stdout}\nstderr:\n{result.stderr}"
    assert result.exit_code == 2, shown
    assert isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in result.output, shown
    assert result.stdout == "", "diagnostics belong on stderr"
    for line in expected:
        assert line in result.stderr, f"missing {line!r}\n{shown}"


def test_corpus_is_complete():
    stems = [p.stem for p in CASES]
    assert len(stems) == len(set(stems)), "case names must be unique across .yaml and .toml"
    for case in CASES:
        assert case.with_suffix(".expected").is_file(), f"{case.name} has no .expected file"


@pytest.mark.parametrize("case", CASES, ids=lambda p: p.name)
def test_bad_spec_is_refused(case: Path, monkeypatch):
    monkeypatch.chdir(BAD)
    expected = [line.strip() for line in case.with_suffix(".expected").read_text().splitlines()]
    result = run_check(case.name)
    assert_refused(result, [line for line in expected if line])


def test_oversize_spec_is_refused(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    padding = "# " + "x" * (1 << 20) + "\n"  # a valid spec, just too big
    Path("big.yaml").write_text("coordinates: [x]\nkinetic: x_dot**2/2\n" + padding)
    result = run_check("big.yaml")
    assert_refused(result, ["big.yaml: spec file is too large (the limit is 1 MiB)"])


def test_missing_file_is_refused(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = run_check("nowhere.yaml")
    assert_refused(result, ["nowhere.yaml: cannot read the spec"])


def test_unknown_extension_is_refused(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("spec.json").write_text("{}")
    result = run_check("spec.json")
    assert_refused(result, ["spec.json: unknown spec format '.json'"])


@pytest.mark.parametrize("text, expected", [
    ("a: " + "[" * 5000 + "]" * 5000 + "\n", "nested too deeply"),
    ("a: [" + ", ".join(["0"] * 150_000) + "]\n", "has too many items"),
], ids=["deep", "wide"])
def test_hostile_yaml_is_refused_quickly(tmp_path, monkeypatch, text, expected):
    monkeypatch.chdir(tmp_path)
    Path("hostile.yaml").write_text(text)
    result = run_check("hostile.yaml")
    assert_refused(result, ["hostile.yaml:1:", expected])


def test_problems_are_listed_in_the_order_of_the_file(tmp_path, monkeypatch):
    # the unknown key (line 7) is found before the expressions are read (lines 5, 6):
    # a reader meets them top to bottom, and so does the message
    monkeypatch.chdir(tmp_path)
    Path("multi.yaml").write_text(
        "coordinates: [x, y]\nparameters: {m: 1.0, k: 2.0}\nparticles:\n  P: {mass: m, position: [x, y]}\n"
        "potential: k*z**2\ngeneralized_forces: {x: foo*2}\ndamping: {q: 1}\n")
    result = run_check("multi.yaml")
    assert_refused(result, ["unknown name 'z'", "unknown name 'foo'", "unknown key 'damping'"])
    lines = [int(line.split(":")[1]) for line in result.stderr.splitlines() if line.startswith("multi.yaml:")]
    assert lines == [5, 6, 7]
