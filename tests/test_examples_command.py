"""`lagcli examples`: the bundled specs are reachable from an installed lagcli."""
from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from lagcli.cli import cli

SPECS = Path(__file__).resolve().parent.parent / "specs"
BUNDLED = sorted([*SPECS.glob("*.yaml"), *SPECS.glob("hybrid/*.yaml")], key=lambda p: p.name)  # events: hybrid/


def test_lists_every_bundled_spec_with_its_description():
    result = CliRunner().invoke(cli, ["examples"])
    assert result.exit_code == 0
    names = [p.stem for p in BUNDLED]
    listed = [line.split()[0] for line in result.output.splitlines()]
    assert listed == names
    assert "Planar double pendulum" in result.output


def test_prints_one_spec_byte_for_byte(tmp_path):
    out = tmp_path / "dp.yaml"
    result = CliRunner().invoke(cli, ["examples", "double_pendulum", "-o", str(out)])
    assert result.exit_code == 0
    assert out.read_bytes() == (SPECS / "double_pendulum.yaml").read_bytes()


def test_copies_all_and_keeps_existing_files(tmp_path):
    target = tmp_path / "mine"
    target.mkdir()
    (target / "atwood.yaml").write_text("# mine\n")
    result = CliRunner().invoke(cli, ["examples", "--copy", str(target)])
    assert result.exit_code == 0
    assert (target / "atwood.yaml").read_text() == "# mine\n"
    assert sorted(p.name for p in target.iterdir()) == sorted(p.name for p in BUNDLED)


def test_unknown_name_is_exit_2_with_the_list():
    result = CliRunner().invoke(cli, ["examples", "double_pendulm"])
    assert result.exit_code == 2
    assert "no bundled example called 'double_pendulm'" in result.output
    assert "double_pendulum" in result.output
