"""`--set` of a parameter and of an input, and `--init` of an initial value, are accepted
alike by every command that runs or analyses a system (simulate, sweep, animate,
linearize, equilibria), with the same messages for the same mistakes: one parser
(`lagcli.run.options.parse_overrides`) reads them all."""
from __future__ import annotations

import shutil

import pytest
from click.testing import CliRunner

from lagcli.cli import cli

from conftest import SPECS

SPEC = str(SPECS / "cart_pole.yaml")
OVERRIDES = ["--set", "m=0.2", "--set", "F=0.5", "--init", "theta=0.1"]


def command(name: str, tmp_path) -> list[str]:
    """The shortest run of each command on the cart-pole (it has a parameter m, an input F)."""
    return {
        "simulate": ["simulate", SPEC, "--t-end", "0.05", "--backend", "python", "-o", str(tmp_path / "s.csv")],
        "sweep": ["sweep", SPEC, "--grid", "l=0.4:0.6:2", "--t-end", "0.05", "-o", str(tmp_path / "w.csv")],
        "animate": ["animate", SPEC, "--t-end", "0.05", "--frame", "0", "-o", str(tmp_path / "a.png")],
        "linearize": ["linearize", SPEC],
        "equilibria": ["equilibria", SPEC],
    }[name]


COMMANDS = ["simulate", "sweep", "animate", "linearize", "equilibria"]


def invoke(args, tmp_path):
    done = CliRunner().invoke(cli, args, env={"XDG_CACHE_HOME": str(tmp_path / "cache")})
    assert "Traceback" not in done.output
    return done


@pytest.mark.parametrize("name", COMMANDS)
def test_every_command_accepts_a_parameter_an_input_and_an_initial_value(name, tmp_path):
    if name == "sweep" and shutil.which("cc") is None:
        pytest.skip("no C compiler: sweep runs the compiled driver")
    if name == "animate":
        pytest.importorskip("matplotlib")
    done = invoke(command(name, tmp_path) + OVERRIDES, tmp_path)
    assert done.exit_code == 0, done.output


def test_linearize_uses_the_overrides():
    """--set m and F change the parameters and the input held; --init theta the point."""
    done = CliRunner().invoke(cli, ["linearize", SPEC, *OVERRIDES])
    assert done.exit_code == 0, done.output
    assert done.stdout.startswith("linearization of cart_pole about x = 0, theta = 0.1, x_dot = 0")
    assert "parameters: mc = 1, m = 0.2, l = 0.5, g = 9.81\ninputs: F = 0.5\n" in done.stdout


def test_equilibria_uses_the_parameter_and_starts_from_the_initial_value():
    """The cart-pole at rest: theta = 0 and pi for any m (F = 0); --init is a starting point."""
    done = CliRunner().invoke(cli, ["equilibria", SPEC, "--set", "m=0.2", "--init", "theta=3", "--json"])
    assert done.exit_code == 0, done.output
    assert '"theta": 3.14159265358979' in done.stdout


MISTAKES = [
    (["--set", "zz=1"], "--set 'zz=1': unknown parameter or input 'zz'"),
    (["--init", "zz=1"], "--init 'zz=1': unknown coordinate or velocity 'zz'"),
    (["--set", "theta=1"], "--set 'theta=1': 'theta' is not a parameter or input"),
    (["--init", "m=1"], "--init 'm=1': 'm' is not a coordinate or velocity"),
]


@pytest.mark.parametrize("name", COMMANDS)
@pytest.mark.parametrize("wrong,message", MISTAKES)
def test_the_same_mistake_reads_the_same_everywhere(name, wrong, message, tmp_path):
    done = invoke(command(name, tmp_path) + wrong, tmp_path)
    assert done.exit_code == 2 and message in done.output, done.output
