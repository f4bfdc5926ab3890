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
        "t": "s", "x": "m", "theta": None, "x_dot": "m/s", "theta_dot": None, "energy": "J"}
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
                          PlotOptions(None, (), layout.angles, layout.units, layout.kinds))
    labels = {ax.get_ylabel() for ax in figure.axes} | {figure.axes[-1].get_xlabel()}
    assert {"x [m]", "angle (rad)", "t [s]"} <= labels


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_a_warm_units_listing_reads_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    runner = CliRunner()
    assert runner.invoke(cli, ["simulate", UNITS_SPEC, "--t-end", "0.01", "-o", str(tmp_path / "a.csv")]).exit_code == 0
    listing = runner.invoke(cli, ["simulate", UNITS_SPEC, "--units"])
    assert "x_dot,velocity,m/s" in listing.stdout and "theta_dot,velocity,\n" in listing.stdout


@pytest.mark.skipif(shutil.which("cc") is None, reason="--lang fmu needs a C compiler")
def test_the_fmu_outputs_every_state_with_its_unit(tmp_path):
    """As a Simulink or OMEdit user sees it (FMPy standing in): every coordinate and velocity
    is an output with the spec's unit, <UnitDefinitions> lists the units, the energy stays
    an output, and FMPy's default simulate_fmu records all of them; the recorded x(t)
    agrees with `lagcli simulate` (a second integrator: FMPy's CVode on Model Exchange)."""
    fmpy = pytest.importorskip("fmpy")
    fmu = tmp_path / "cart.fmu"
    result = CliRunner().invoke(cli, ["generate", UNITS_SPEC, "--lang", "fmu", "-o", str(fmu)])
    assert result.exit_code == 0, result.output
    description = fmpy.read_model_description(str(fmu), validate=True)
    variables = {v.name: v for v in description.modelVariables}
    for name, unit in (("x", "m"), ("theta", None), ("x_dot", "m/s"), ("theta_dot", None), ("energy", "J")):
        assert variables[name].causality == "output" and variables[name].unit == unit, name
    assert variables["k"].unit == "N/m" and variables["k"].causality == "parameter"
    assert {u.name for u in description.unitDefinitions} == {"m", "m/s", "J", "kg", "m/s^2", "N/m", "N*s/m",
                                                              "N*m", "N"}
    recorded = fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.01)     # the defaults
    assert {"x", "theta", "x_dot", "theta_dot", "energy"} <= set(recorded.dtype.names)
    recorded = fmpy.simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.01, fmi_type="ModelExchange",
                                 relative_tolerance=1e-10)
    reference = lagcli.load(UNITS_SPEC).simulate(t_end=1.0, dt=0.01)
    assert abs(recorded["x"][-1] - reference["x"][-1]) < 1e-5
    assert abs(recorded["theta"][-1] - reference["theta"][-1]) < 1e-5


def test_report_parameter_tables_carry_the_units():
    """The text report gives each parameter its unit (M keeps its name: the report's
    mass matrix yields), and so does the LaTeX table."""
    system = lagcli.load(UNITS_SPEC)
    line = next(row for row in system.report("text").splitlines() if row.startswith("parameters"))
    assert "M = 2.0 kg" in line and "k = 10.0 N/m" in line
    latex = system.report("latex")
    assert r"$k$ & $10.0$~N/m" in latex and r"$m$ & $1.0$~kg" in latex
