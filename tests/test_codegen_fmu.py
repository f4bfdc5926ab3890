"""`lagcli generate --lang fmu`: the FMI 2.0 FMU, checked by FMPy (an independent FMI
importer) against `lagcli simulate`.

- Every bundled spec: the FMU passes FMPy's validation, and FMPy's Model Exchange
  simulation with its own CVode solver agrees with lagcli's Python backend (scipy) to
  1e-6 over the first SHORT_SPAN seconds of the spec's span (the whole span: `-m slow`).
  Outputs (multipliers, energy, jacobi, momenta, constraint residual) are compared too.
- Co-Simulation (lagcli's C integrator inside the FMU) for one unconstrained and one
  constrained spec.
- Golden files of the generated text (modelDescription.xml, lagcli_fmu_model.h,
  buildDescription.xml) for double_pendulum and ex6_9_two_wheels_axle, with the
  LAGCLI_UPDATE_GOLDEN switch of tests/test_golden_codegen.py.
- Same bytes: two generations give the same zip (same compiler), and every entry but
  the binary is the same in another process with another hash seed.
- No C compiler: exit status 1, a clear message, no file.
"""
from __future__ import annotations

import io
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

fmpy = pytest.importorskip("fmpy")
from fmpy.validation import validate_fmu  # noqa: E402

from conftest import HEAVY_SPECS  # noqa: E402
from lagcli.cli import cli  # noqa: E402
from test_golden_codegen import GOLDEN, compare_or_update  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
HEAVY_TIMEOUT = 600       # s: the benchmark bicycle's FMU is generated and checked in ~5 s (slow tests only)
SPEC_NAMES = [pytest.param(p.stem, marks=pytest.mark.timeout(HEAVY_TIMEOUT)) if p.stem in HEAVY_SPECS
              else p.stem for p in sorted((ROOT / "specs").glob("*.yaml"))]
SHORT_SPAN = 0.5          # seconds of each spec simulated in the default run
TOLERANCE = 1e-6
GOLDEN_SPECS = ["double_pendulum", "ex6_9_two_wheels_axle"]
pytestmark = pytest.mark.skipif(
    __import__("shutil").which("cc") is None, reason="--lang fmu needs a C compiler")


def system_of(derived, name: str):
    from lagcli.system import System

    d = derived(name)
    return System(d, Path(d.model.source).read_bytes())


_GENERATED: dict[str, bytes] = {}      # spec name -> FMU bytes, made once per session


def write_fmu(system, folder: Path, fresh: bool = False) -> Path:
    if fresh or system.name not in _GENERATED:
        (_GENERATED[system.name],) = system.generate("fmu").values()
    path = folder / f"{system.name}.fmu"
    path.write_bytes(_GENERATED[system.name])
    return path


def compare(system, fmu: Path, t_end: float, fmi_type: str) -> None:
    """FMPy's simulation of `fmu` agrees with `System.simulate` at every output time."""
    settings = system.layout.settings
    expected = system.simulate(t_end=t_end)
    names = [c.name for c in system.layout.columns if c.kind != "time"]
    options = dict(solver="CVode", relative_tolerance=1e-12) if fmi_type == "ModelExchange" else {}
    result = fmpy.simulate_fmu(str(fmu), fmi_type=fmi_type, stop_time=expected["t"][-1],
                               output_interval=settings.dt, output=names, **options)
    times = result["time"]
    assert np.allclose(times, expected["t"][: len(times)], atol=1e-12, rtol=0) and len(times) == len(expected["t"])
    for name in names:
        got, want = result[name], expected[name]
        scale = max(1.0, float(np.max(np.abs(want))))
        worst = float(np.max(np.abs(got - want)))
        if system.layout.column(name).kind == "residual":   # two different ~1e-10 noises
            assert float(np.max(got)) < TOLERANCE, name
            continue
        assert worst <= TOLERANCE * scale, f"{name}: FMU and lagcli simulate differ by {worst:.3g}"


@pytest.mark.core_specs
@pytest.mark.parametrize("name", SPEC_NAMES)
def test_fmu_validates_and_agrees_with_simulate(name, derived, tmp_path):
    system = system_of(derived, name)
    fmu = write_fmu(system, tmp_path)
    assert validate_fmu(str(fmu)) == []
    description = fmpy.read_model_description(str(fmu), validate=True)
    assert description.modelExchange is not None and description.coSimulation is not None
    names = [v.name for v in description.modelVariables]
    layout = system.layout
    assert names[: 2 * len(layout.coordinates)] == list(layout.state_names)
    assert set(layout.header) - {"t"} <= set(names)
    compare(system, fmu, min(SHORT_SPAN, layout.settings.t_end), "ModelExchange")


@pytest.mark.core_specs
@pytest.mark.parametrize("name", SPEC_NAMES)      # the bicycles: -m slow (conftest)
def test_fmu_agrees_over_the_whole_span(name, derived, tmp_path):
    system = system_of(derived, name)
    compare(system, write_fmu(system, tmp_path), system.layout.settings.t_end, "ModelExchange")


@pytest.mark.parametrize("name", GOLDEN_SPECS)
def test_co_simulation_agrees_with_simulate(name, derived, tmp_path):
    system = system_of(derived, name)
    compare(system, write_fmu(system, tmp_path), SHORT_SPAN, "CoSimulation")


def test_parameters_and_start_values_reach_the_model(derived, tmp_path):
    """A parameter set through FMI changes the motion as `simulate(parameters=...)` does."""
    system = system_of(derived, "double_pendulum")
    fmu = write_fmu(system, tmp_path)
    name = system.layout.parameter_names[-1]
    value = system.layout.parameter_defaults[name] * 1.5
    expected = system.simulate(t_end=0.3, parameters={name: value})
    result = fmpy.simulate_fmu(str(fmu), stop_time=0.3, output_interval=system.layout.settings.dt,
                               solver="CVode", relative_tolerance=1e-12, start_values={name: value},
                               output=list(system.layout.state_names))
    for state in system.layout.state_names:
        assert np.max(np.abs(result[state] - expected[state])) < TOLERANCE


@pytest.mark.slow             # cmake: half a minute
def test_sources_build_on_their_own(derived, tmp_path):
    """The FMU without its binary, built from sources/ by FMPy (cmake, all warnings as
    errors), simulates as the one lagcli built: the sources are complete."""
    system = system_of(derived, "cartesian_pendulum")
    fmu = write_fmu(system, tmp_path)
    stripped = tmp_path / "sources_only.fmu"
    with zipfile.ZipFile(fmu) as full, zipfile.ZipFile(stripped, "w") as out:
        for entry in full.infolist():
            if not entry.filename.startswith("binaries/"):
                out.writestr(entry, full.read(entry))
    done = subprocess.run([sys.executable, "-m", "fmpy", "compile", "--all-warnings", "--warning-as-error",
                           str(stripped)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    compare(system, stripped, 0.2, "ModelExchange")


def test_inputs_and_units_reach_the_model_description(derived, tmp_path):
    """Layout.inputs (each an input Real, start 0) and parameter units (a unit of
    UnitDefinitions), given to the layout by hand: FMPy validates the description."""
    from dataclasses import replace

    from lagcli.targets import c as c_target
    from lagcli.targets.fmu import fmu_context
    from lagcli.render.templates import render
    from lagcli.interface import Input

    system = system_of(derived, "cart_pole")
    layout = system.layout
    layout = replace(layout, inputs=(Input("F_in"), Input("tau_in")),
                     parameters=(replace(layout.parameters[0], unit="kg"),) + layout.parameters[1:])
    context = fmu_context(c_target.c_context(system.derivation, layout), {}, ["cart_pole.c"])
    xml = tmp_path / "modelDescription.xml"
    xml.write_text(render("fmu/modelDescription.xml.jinja", guid="{0}", **context), encoding="utf-8")
    description = fmpy.read_model_description(str(xml), validate=True)
    variables = {v.name: v for v in description.modelVariables}
    assert [variables[u].causality for u in ("F_in", "tau_in")] == ["input", "input"]
    assert variables["F_in"].start == "0.0"
    assert variables[layout.parameters[0].name].unit == "kg"
    assert [u.name for u in description.unitDefinitions] == ["kg"]
    header = render("fmu/lagcli_fmu_model.h.jinja", guid="{0}", **context)
    assert "#define LAGCLI_FMU_NINPUT 2u" in header


# -- golden files and bytes ------------------------------------------------------------

def fmu_text_files(name: str) -> dict[str, str]:
    from lagcli.targets.fmu import fmu_sources
    from lagcli.analysis.initial_state import spec_initial_state
    from lagcli.system import load

    system = load(ROOT / "specs" / f"{name}.yaml")
    start, _ = spec_initial_state(system.derivation)
    return fmu_sources(system.derivation, system.layout, start.values, start.notes)


@pytest.mark.parametrize("name", GOLDEN_SPECS)
def test_golden(name):
    from lagcli.runtime import c_runtime_files, fmi2_runtime_files

    files = fmu_text_files(name)
    shipped = {**c_runtime_files(), **fmi2_runtime_files()}
    for model in (f"{name}.h", f"{name}.c"):     # the C model of --lang c, as its golden files
        assert files.pop(f"sources/{model}") == (GOLDEN / "c" / model).read_text()
    for path in list(files):
        if path.removeprefix("sources/") in shipped or path.startswith("documentation/"):
            files.pop(path)      # the runtime and the licence as shipped
    assert sorted(files) == ["modelDescription.xml", "sources/buildDescription.xml",
                             "sources/lagcli_fmu_model.h"]
    for path, text in files.items():
        compare_or_update(GOLDEN / "fmu" / name / Path(path).name, text)


def test_same_bytes(derived, tmp_path):
    """Twice in this process: the same zip, binary included; in another process with
    another hash seed: the same text files (the binary is the compiler's)."""
    system = system_of(derived, "ex6_9_two_wheels_axle")
    first, second = tmp_path / "a", tmp_path / "b"
    for folder in (first, second):
        folder.mkdir()
    first, second = write_fmu(system, first, fresh=True), write_fmu(system, second, fresh=True)
    assert first.read_bytes() == second.read_bytes()
    with zipfile.ZipFile(first) as fmu:
        entries = fmu.infolist()
        assert [e.filename for e in entries] == sorted(e.filename for e in entries)
        assert {e.date_time for e in entries} == {(1980, 1, 1, 0, 0, 0)}
        assert {e.external_attr >> 16 for e in entries} == {0o644}
        texts = {e.filename: fmu.read(e).decode() for e in entries if not e.filename.startswith("binaries/")}
        assert any(e.filename.startswith("binaries/") for e in entries)
    script = ("import json, sys; sys.path.insert(0, sys.argv[1]); "
              "from test_codegen_fmu import fmu_text_files; "
              "print(json.dumps(fmu_text_files('ex6_9_two_wheels_axle')))")
    env = {**os.environ, "PYTHONHASHSEED": "4321", "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-c", script, str(ROOT / "tests")], capture_output=True, text=True,
                          env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    assert __import__("json").loads(done.stdout) == texts


# -- the command line ------------------------------------------------------------------

def test_cli_writes_the_fmu(tmp_path):
    out = tmp_path / "pendulum.fmu"
    result = CliRunner().invoke(cli, ["generate", str(ROOT / "specs" / "cartesian_pendulum.yaml"),
                                      "--lang", "fmu", "-o", str(out)])
    assert result.exit_code == 0, result.output
    with zipfile.ZipFile(io.BytesIO(out.read_bytes())) as fmu:
        assert "modelDescription.xml" in fmu.namelist()


def test_cli_needs_an_output_file():
    result = CliRunner().invoke(cli, ["generate", str(ROOT / "specs" / "cartesian_pendulum.yaml"),
                                      "--lang", "fmu"])
    assert result.exit_code == 2 and "-o NAME.fmu" in result.output


def test_no_compiler_exit_1_and_nothing_written(tmp_path, monkeypatch):
    from lagcli.runtime import toolchain

    monkeypatch.setattr(toolchain, "find_compiler", lambda: None)
    out = tmp_path / "x.fmu"
    result = CliRunner().invoke(cli, ["generate", str(ROOT / "specs" / "cartesian_pendulum.yaml"),
                                      "--lang", "fmu", "-o", str(out)])
    assert result.exit_code == 1 and "'cc' was not found" in result.output
    assert list(tmp_path.iterdir()) == []


def test_a_name_that_would_replace_an_fmu_source_is_refused(tmp_path):
    spec = tmp_path / "clash.yaml"
    spec.write_text("name: lagcli_fmi2\ncoordinates: [x]\nparameters: {k: 1.0}\n"
                    "kinetic: x_dot**2/2\npotential: k*x**2/2\n")
    out = tmp_path / "clash.fmu"
    result = CliRunner().invoke(cli, ["generate", str(spec), "--lang", "fmu", "-o", str(out)])
    assert result.exit_code == 2 and "name" in result.output and "lagcli_fmi2.c" in result.output
    assert not out.exists()


def test_c_keyword_names(tmp_path):
    """A model called `int` with a coordinate `double` and parameters `register`, `M_PI`:
    the names stay as they are in modelDescription.xml, the C uses slots."""
    from test_codegen_c import KEYWORD_SPEC

    from lagcli.system import load

    spec = tmp_path / "int.yaml"
    spec.write_text(KEYWORD_SPEC)
    system = load(spec)
    fmu = write_fmu(system, tmp_path, fresh=True)
    assert validate_fmu(str(fmu)) == []
    compare(system, fmu, 0.2, "ModelExchange")


def test_a_singular_model_is_an_fmi_error(derived, tmp_path):
    """l2 = 0 makes the double pendulum's mass matrix singular: the FMU says so (fmi2Error
    with the reason logged), as the C driver does."""
    system = system_of(derived, "double_pendulum")
    fmu = write_fmu(system, tmp_path)
    messages = []
    with pytest.raises(Exception, match="fmi2"):
        fmpy.simulate_fmu(str(fmu), stop_time=0.1, start_values={"l2": 0.0}, solver="CVode",
                          logger=lambda *args: messages.append(args))
    assert any(b"singular mass matrix" in arg for message in messages for arg in message
               if isinstance(arg, bytes))


def test_an_input_set_through_fmi_drives_the_model(derived, tmp_path):
    """cart_pole's force input F (spec `inputs:`), given to FMPy as a start value, moves the
    cart as `System.simulate(inputs=...)` does; the total horizontal momentum grows as F t
    (Newton, independent of both)."""
    system = system_of(derived, "cart_pole")
    fmu = write_fmu(system, tmp_path)
    F, t_end = 0.8, 0.5
    expected = system.simulate(t_end=t_end, inputs={"F": F})
    result = fmpy.simulate_fmu(str(fmu), stop_time=t_end, output_interval=system.layout.settings.dt,
                               solver="CVode", relative_tolerance=1e-12, start_values={"F": F},
                               output=["x_dot", "theta", "theta_dot"])
    for name in ("x_dot", "theta", "theta_dot"):
        np.testing.assert_allclose(result[name], expected[name][: len(result)], atol=1e-6)
    params = system.layout.parameter_defaults
    momentum = ((params["mc"] + params["m"]) * result["x_dot"]
                + params["m"] * params["l"] * np.cos(result["theta"]) * result["theta_dot"])
    np.testing.assert_allclose(momentum, F * result["time"], atol=1e-6)
