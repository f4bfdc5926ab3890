"""The conventions of command-line tools that `lagcli` keeps (issue 25, "First hour").

SPEC `-` is standard input; `check` takes several files and has `--json`; `-q` silences
notes and warnings; generators say what they wrote; `--lang` is case-insensitive with
`matlab` for Octave; `sweep --method` offers what it accepts; an unknown `--set` name
gets a did-you-mean; a bundled spec missing outside the checkout points at
`lagcli examples --copy`; every command's --help has an example; and the docs list
every option of `simulate --help`, every target of `generate` and run the
`parse_output` example of docs/derive.md as written.
"""
from __future__ import annotations

import doctest
import json
import re
import textwrap
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.targets import LANGUAGES
from lagcli.spec.files import MAX_BYTES

ROOT = Path(__file__).resolve().parent.parent
SPECS = ROOT / "specs"
CART_POLE = str(SPECS / "cart_pole.yaml")


def invoke(args, input=None):
    try:
        runner = CliRunner(mix_stderr=False)      # click < 8.2 keeps stderr apart only on request
    except TypeError:
        runner = CliRunner()
    return runner.invoke(cli, [str(a) for a in args], input=input)


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


# --- SPEC - : standard input ---------------------------------------------------------

def test_spec_from_stdin_gives_the_same_report_as_the_file():
    text = Path(CART_POLE).read_text()
    from_file = invoke(["derive", CART_POLE, "--json"])
    from_stdin = invoke(["derive", "-", "--json"], input=text)
    assert from_stdin.exit_code == 0, from_stdin.stderr
    assert json.loads(from_stdin.stdout) == json.loads(from_file.stdout)


STDIN_RUNS = {       # a command that takes a SPEC -> (spec, options, what it writes)
    "check": (CART_POLE, [], None),
    "derive": (CART_POLE, ["--json"], None),
    "generate": (CART_POLE, ["--lang", "python"], None),
    "simulate": (CART_POLE, ["--backend", "python", "--t-end", "0.05"], None),
    "sweep": (CART_POLE, ["--grid", "m=0.1:0.2:2", "--t-end", "0.05", "-o", "sweep.csv"], "sweep.csv"),
    "animate": (CART_POLE, ["--t-end", "0.1", "--frame", "0.05", "-o", "frame.png"], "frame.png"),
    "linearize": (CART_POLE, [], None),
    "equilibria": (CART_POLE, [], None),
    "routh": (str(SPECS / "spherical_pendulum.yaml"), [], None),
    "hamiltonian": (CART_POLE, [], None),
    "report": (CART_POLE, ["--no-pictures", "-o", "page.html"], "page.html"),
}


def test_the_stdin_runs_cover_every_command_taking_a_spec():
    taking = {name for path, command in leaf_commands() for name in [" ".join(path)]
              if any(p.name in ("spec", "specs") for p in command.params)}
    assert taking == set(STDIN_RUNS)


@pytest.mark.parametrize("command", sorted(STDIN_RUNS))
def test_every_command_taking_a_spec_reads_stdin(command, tmp_path, monkeypatch):
    import shutil

    if command == "sweep" and not shutil.which("cc"):
        pytest.skip("no cc: sweeps run the compiled driver")
    monkeypatch.chdir(tmp_path)
    spec, options, written = STDIN_RUNS[command]
    done = invoke([command, "-", *options], input=Path(spec).read_text())
    assert done.exit_code == 0, f"{command}: {done.stderr}"
    assert (tmp_path / written).stat().st_size > 0 if written else done.stdout


def test_stdin_errors_name_stdin_with_line_and_column():
    done = invoke(["check", "-"], input="coordinates: [x]\nkinetic: x_dot**2/2 +\n")
    assert done.exit_code == 2
    assert done.stderr.startswith("<stdin>:2:10: kinetic: invalid expression"), done.stderr


def test_stdin_is_toml_when_its_first_line_is_a_table_or_key_value():
    toml = 'name = "osc"\ncoordinates = ["x"]\nkinetic = "x_dot**2/2"\npotential = "x**2/2"\n'
    done = invoke(["check", "-"], input="# an oscillator\n" + toml)
    assert done.exit_code == 0, done.stderr
    assert done.stdout.startswith("<stdin>: OK: osc")


def test_stdin_has_the_size_limit_of_a_file():
    done = invoke(["check", "-"], input="coordinates: [x]\n" + "#" * MAX_BYTES)
    assert done.exit_code == 2
    assert "<stdin>: spec text is too large (the limit is 1 MiB)" in done.stderr


def test_a_spec_from_stdin_without_name_is_called_stdin():
    done = invoke(["check", "-"], input="coordinates: [x]\nkinetic: x_dot**2/2\n")
    assert done.stdout.startswith("<stdin>: OK: stdin"), done.stdout


# --- check: several files, --json -------------------------------------------------------

BAD = "coordinates: [x]\nparticles:\n  P: {mass: 1, position: [x, 0], colour: red}\n"


def test_check_goes_on_after_a_broken_file_and_exits_2(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(BAD)
    done = invoke(["check", CART_POLE, bad, SPECS / "atwood.yaml"])
    assert done.exit_code == 2
    assert "OK: cart_pole" in done.stdout and "OK: atwood" in done.stdout
    assert f"{bad}:3:34: particles.P.colour: unknown key 'colour'" in done.stderr


def test_check_json_records_locate_every_problem(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(BAD)
    done = invoke(["check", "--json", CART_POLE, bad])
    assert done.exit_code == 2
    assert done.stderr == ""
    good, broken = json.loads(done.stdout)
    assert good == {"file": CART_POLE, "valid": True, "problems": []}
    assert broken["valid"] is False
    (problem,) = broken["problems"]
    assert problem == {"file": str(bad), "line": 3, "column": 34, "path": "particles.P.colour",
                       "severity": "error", "message": "unknown key 'colour'",
                       "hint": "allowed keys are: mass, position"}


def test_check_json_names_stdin_like_its_messages():
    done = invoke(["check", "--json", "-"], input="coordinates: [x]\nkinetic: x_dot**2/2 +\n")
    (record,) = json.loads(done.stdout)
    assert record["file"] == record["problems"][0]["file"] == "<stdin>"


def test_check_json_of_valid_files_exits_0():
    done = invoke(["check", "--json", CART_POLE, SPECS / "atwood.yaml"])
    assert done.exit_code == 0
    assert [r["valid"] for r in json.loads(done.stdout)] == [True, True]


def test_check_json_carries_warnings(tmp_path):
    spec = tmp_path / "zero.yaml"
    spec.write_text("coordinates: [x]\nparameters: {m: 0.0}\nparticles:\n"
                    "  P: {mass: m, position: [x, 0]}\nkinetic: x_dot**2/2\n")
    done = invoke(["check", "--json", spec])
    severities = {p["severity"] for r in json.loads(done.stdout) for p in r["problems"]}
    assert "warning" in severities, done.stdout


# --- --quiet, notes of generators -------------------------------------------------------

def test_generators_say_what_they_wrote(tmp_path):
    target = tmp_path / "dp_c"
    done = invoke(["generate", SPECS / "double_pendulum.yaml", "--lang", "c", "-o", target])
    assert done.exit_code == 0, done.stderr
    files = [p for p in target.rglob("*") if p.is_file()]
    assert done.stderr == f"wrote {target}: {len(files)} files\n"
    module = tmp_path / "dp.py"
    done = invoke(["generate", SPECS / "double_pendulum.yaml", "--lang", "python", "-o", module])
    assert done.stderr == f"wrote {module}\n"


def test_nothing_is_said_when_writing_to_stdout_or_with_quiet(tmp_path):
    spec = SPECS / "double_pendulum.yaml"
    assert invoke(["generate", spec, "--lang", "python"]).stderr == ""
    assert invoke(["generate", spec, "--lang", "python", "-o", tmp_path / "a.py", "-q"]).stderr == ""
    assert invoke(["-q", "generate", spec, "--lang", "python", "-o", tmp_path / "b.py"]).stderr == ""


def test_quiet_silences_warnings_and_notes_but_not_errors(tmp_path):
    spec = tmp_path / "zero.yaml"
    spec.write_text("coordinates: [x]\nparameters: {m: 0.0}\nparticles:\n"
                    "  P: {mass: m, position: [x, 0]}\nkinetic: x_dot**2/2\n")
    loud = invoke(["check", spec])
    assert "warning:" in loud.stderr
    quiet = invoke(["check", spec, "--quiet"])
    assert quiet.exit_code == 0 and quiet.stderr == "" and quiet.stdout == loud.stdout
    copied = invoke(["examples", "--copy", tmp_path / "copies", "-q"])
    assert copied.exit_code == 0 and copied.stderr == ""
    failed = invoke(["check", tmp_path / "nowhere.yaml", "-q"])
    assert failed.exit_code == 2 and "cannot read the spec" in failed.stderr


@pytest.mark.timeout(60)
def test_other_warnings_are_shown_once_and_the_command_ends(monkeypatch):
    """A warning that is not lagcli's (a library's DeprecationWarning) is passed on once:
    shown while warnings were still recorded, it was recorded again, without end."""
    import warnings

    from lagcli import commands

    def derive_text(*args):
        warnings.warn("a library's remark", DeprecationWarning)
        return "report\n"
    monkeypatch.setattr(commands, "derive_text", derive_text)
    with warnings.catch_warnings(record=True) as outer:
        warnings.simplefilter("always")
        done = invoke(["derive", CART_POLE])
    assert done.exit_code == 0 and done.stdout == "report\n"
    assert [str(w.message) for w in outer] == ["a library's remark"]


def leaf_commands(group: click.Group = cli, prefix=()):
    for name, command in sorted(group.commands.items()):
        if isinstance(command, click.Group):
            yield from leaf_commands(command, prefix + (name,))
        else:
            yield prefix + (name,), command


@pytest.mark.parametrize("path", [p for p, _ in leaf_commands()], ids=" ".join)
def test_every_command_has_quiet_and_an_example(path):
    done = invoke([*path, "--help"])
    assert done.exit_code == 0
    assert "-q, --quiet" in done.stdout, path
    assert re.search(r"^\s*Examples?:\n\s+(XDG_CACHE_HOME=\S+ )?lagcli ", done.stdout, re.M), \
        f"lagcli {' '.join(path)} --help shows no example:\n{done.stdout}"


# --- --lang, --method, --set ------------------------------------------------------------

def test_lang_is_case_insensitive_and_matlab_is_octave(tmp_path):
    spec = SPECS / "double_pendulum.yaml"
    upper = invoke(["generate", spec, "--lang", "PYTHON"])
    assert upper.exit_code == 0 and upper.stdout == invoke(["generate", spec, "--lang", "python"]).stdout
    for lang in ("matlab", "MATLAB", "octave"):
        assert invoke(["generate", spec, "--lang", lang, "-o", tmp_path / lang]).exit_code == 0
    names = {lang: sorted(p.name for p in (tmp_path / lang).iterdir()) for lang in ("matlab", "octave")}
    assert names["matlab"] == names["octave"]
    for name in names["octave"]:
        assert (tmp_path / "matlab" / name).read_bytes() == (tmp_path / "octave" / name).read_bytes()


def test_sweep_method_offers_only_the_compiled_drivers_methods():
    from lagcli.runtime.run_rules import EXPLICIT_METHODS

    shown = re.search(r"--method \[([^\]]+)\]", invoke(["sweep", "--help"]).stdout)
    assert tuple(shown[1].split("|")) == EXPLICIT_METHODS
    refused = invoke(["sweep", CART_POLE, "--grid", "m=1:2:2", "--method", "Radau", "-o", "x.csv"])
    assert refused.exit_code == 2 and "'Radau' is not one of" in refused.stderr


@pytest.mark.parametrize("args", [
    ["simulate", CART_POLE, "--backend", "python", "--set", "MC=3"],
    ["sweep", CART_POLE, "--grid", "m=1:2:2", "-o", "sweep.csv", "--set", "MC=3"],
    ["animate", CART_POLE, "-o", "motion.gif", "--set", "MC=3"],
    ["equilibria", CART_POLE, "--set", "MC=3"],
    ["linearize", CART_POLE, "--at", "MC=3"],
    ["routh", SPECS / "spherical_pendulum.yaml", "--momentum", "p_phi=0.5", "--set", "M=3"],
], ids=lambda args: args[0])
def test_unknown_set_name_gets_a_did_you_mean(args, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    done = invoke(args)
    assert done.exit_code == 2, done.stderr
    assert "hint: did you mean 'm" in done.stderr, done.stderr


def test_did_you_mean_ignores_letter_case():
    from lagcli.run.options import closest_name

    assert closest_name("K", ["k", "m"]) == "k"
    assert closest_name("MC", ["mc", "m", "l"]) == "mc"
    assert closest_name("Theta", ["x", "theta"]) == "theta"
    assert closest_name("zz", ["mc", "m", "l"]) is None


# --- a bundled spec missing outside the checkout ---------------------------------------

def test_missing_bundled_spec_hints_at_examples_copy(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    done = invoke(["check", "specs/cart_pole.yaml"])
    assert done.exit_code == 2
    assert "specs/cart_pole.yaml: cannot read the spec: No such file or directory" in done.stderr
    assert "hint: 'cart_pole' is a bundled example" in done.stderr
    assert "`lagcli examples --copy specs/`" in done.stderr
    other = invoke(["check", "specs/my_own.yaml"])
    assert "hint" not in other.stderr


# --- the docs list what the commands take -----------------------------------------------

def options_of(help_text: str) -> set[str]:
    """The long options an --help text lists (the lines that start with `-`, up to the help)."""
    return {name for line in help_text.splitlines() if line.lstrip().startswith("-")
            for name in re.findall(r"--[a-z][a-z-]*", re.split(r"\s{2,}", line.strip())[0])}


def test_docs_simulate_lists_every_option_of_simulate_help():
    shown = options_of(invoke(["simulate", "--help"]).stdout) - {"--help"}
    table = re.search(r"^\| option \|.*?\n\n", (ROOT / "docs" / "simulate.md").read_text(), re.M | re.S)[0]
    documented = set(re.findall(r"^\| (.*?) \|", table, re.M))
    listed = {m for row in documented for m in re.findall(r"--[a-z][a-z-]*", row)}
    assert shown and shown <= listed, f"docs/simulate.md's option table lacks {sorted(shown - listed)}"


def test_docs_api_lists_every_target_of_generate():
    text = (ROOT / "docs" / "api.md").read_text()
    missing = [lang for lang in LANGUAGES if f'"{lang}"' not in text]
    assert not missing, f"docs/api.md does not list the targets {missing}"


def test_docs_derive_parse_output_example_runs(monkeypatch):
    monkeypatch.chdir(ROOT)
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "derive.md").read_text(), flags=re.S)
    assert any("parse_output" in b for b in blocks), "docs/derive.md shows no parse_output example"
    test = doctest.DocTestParser().get_doctest("\n".join(blocks), {}, "docs/derive.md",
                                               str(ROOT / "docs" / "derive.md"), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.failures == 0 and runner.tries >= 3
