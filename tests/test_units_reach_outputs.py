"""Units declared in a spec reach what a user sees: `simulate --units`, the plot's axes,
the run interface (checked against docs/spec.md's rules: velocities per second, t in s,
energies in J), and a spec without units shows none."""
from __future__ import annotations

import shutil

import pytest
from click.testing import CliRunner

import lagcli
from lagcli.cli import cli

from conftest import ROOT, SPECS

UNITS_SPEC = str(ROOT / "tests" / "data" / "units_cart_pendulum.yaml")


def test_the_run_interface_carries_the_spec_units():
    layout = lagcli.load(UNITS_SPEC).layout
    assert {c.name: c.unit for c in layout.columns} == {
        "t": "s", "x": "m", "theta": "rad", "x_dot": "m/s", "theta_dot": "rad/s", "energy": "J"}
    assert {p.name: p.unit for p in layout.parameters}["k"] == "N/m"
    assert lagcli.load(SPECS / "double_pendulum.yaml").layout.units == {}


def test_simulate_units_prints_each_column_with_its_unit():
    result = CliRunner().invoke(cli, ["simulate", UNITS_SPEC, "--units"])
    assert result.exit_code == 0, result.output
    rows = [line.split(",") for line in result.stdout.splitlines()]
    assert rows[0] == ["column", "kind", "unit"]
    assert ["x_dot", "velocity", "m/s"] in rows and ["t", "time", "s"] in rows


def test_the_plot_axes_carry_the_units():
    pytest.importorskip("matplotlib")
    from lagcli.run.rows import Trajectory as Rows
    from lagcli.viz.plot import PlotOptions, build_figure

    system = lagcli.load(UNITS_SPEC)
    trajectory = system.simulate(t_end=0.2)
    rows = Rows(list(trajectory.names), trajectory.to_csv().splitlines()[1:])
    layout = system.layout
    figure = build_figure(rows, layout.coordinates, layout.energy_conserved, "units",
                          PlotOptions(None, (), layout.angles, layout.units))
    labels = {ax.get_ylabel() for ax in figure.axes} | {figure.axes[-1].get_xlabel()}
    assert {"x [m]", "theta [rad]", "t [s]"} <= labels


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_a_warm_units_listing_reads_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    runner = CliRunner()
    assert runner.invoke(cli, ["simulate", UNITS_SPEC, "--t-end", "0.01", "-o", str(tmp_path / "a.csv")]).exit_code == 0
    listing = runner.invoke(cli, ["simulate", UNITS_SPEC, "--units"])
    assert "theta_dot,velocity,rad/s" in listing.stdout
