"""The variational integrator's functions of a big system are generated on request only
(docs/codegen.md, "Big systems"): `lagcli generate` leaves them out of a system whose
equations pass `discrete_code.VARIATIONAL_MAX_NODES` tree nodes unless `--variational`
asks, the programs lagcli runs itself always have them, and code without them refuses
`--method variational` with the hint. The rule is tried on the double pendulum with the
budget lowered to 0 (a real big system takes tens of seconds to generate)."""
from __future__ import annotations

import types

import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.derive import derive
from lagcli.derive.pipeline import load_model
from lagcli.targets import discrete_code, generate, program_sources

from conftest import SPECS, nlink_spec

HINT = "lagcli generate --variational"


@pytest.fixture(scope="module")
def pendulum():
    return derive(load_model(SPECS / "double_pendulum.yaml"))


@pytest.fixture
def everything_big(monkeypatch):
    monkeypatch.setattr(discrete_code, "VARIATIONAL_MAX_NODES", 0)


def test_small_systems_have_them_and_the_20_link_chain_does_not(tmp_path):
    assert discrete_code.included(derive(load_model(SPECS / "double_pendulum.yaml")))
    assert not discrete_code.included(derive(load_model(nlink_spec(tmp_path, 20))))


def test_c_without_them_refuses_with_the_hint(pendulum, everything_big):
    source = generate(pendulum, "c")["double_pendulum.c"]
    assert "_discrete_momenta" not in source and HINT in source
    asked = generate(pendulum, "c", variational=True)["double_pendulum.c"]
    assert "_discrete_momenta" in asked and HINT not in asked


def test_the_programs_lagcli_runs_have_them(pendulum, everything_big):
    assert "_discrete_momenta" in program_sources(pendulum, "c")["double_pendulum.c"]
    assert "def _discrete_momenta" in program_sources(pendulum, "python")["double_pendulum.py"]


def test_python_module_without_them_refuses(pendulum, everything_big):
    module = types.ModuleType("generated")
    exec(compile(generate(pendulum, "python")["double_pendulum.py"], "generated", "exec"), module.__dict__)
    with pytest.raises(ValueError, match="--variational"):
        module.simulate(t_end=0.1, method="variational")


def test_cli_option(tmp_path, everything_big):
    runner = CliRunner()
    done = runner.invoke(cli, ["generate", str(SPECS / "double_pendulum.yaml"), "--lang", "c",
                               "--variational", "-o", str(tmp_path / "c")])
    assert done.exit_code == 0, done.output
    assert "_discrete_momenta" in (tmp_path / "c" / "double_pendulum.c").read_text()
    refused = runner.invoke(cli, ["generate", str(SPECS / "double_pendulum.yaml"), "--lang", "rust",
                                  "--variational", "-o", str(tmp_path / "r")])
    assert refused.exit_code == 2 and "--lang python and c only" in refused.output
