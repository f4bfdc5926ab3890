"""Spec `inputs:` (docs/spec.md "inputs"): layout, generated code, simulate and reports.

Independent checks: the cart-pole's textbook accelerations (Ogata; the same closed form
as test_linearize.py) for the generated `rhs(t, y, p, u)`, and Newton's second law for
the whole system for `simulate --set F=...`: the horizontal momentum
p_x = (mc + m) x' + m l cos(theta) theta' grows as F t exactly (no other horizontal
force acts), whatever the pole does. Bad `inputs:` specs are in tests/data/bad/inputs_*.
"""
from __future__ import annotations

import csv
import importlib.util
import io
import shutil
import subprocess

import numpy as np
import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.interface import Input, Layout, layout_of

from conftest import spec_path

MC, M, L, G = 1.0, 0.1, 0.5, 9.81


def textbook_accelerations(theta, theta_dot, F):
    """x'', theta'' of the cart-pole (point-mass pole, angle from the upward vertical)."""
    s, c = np.sin(theta), np.cos(theta)
    den = MC + M * s * s
    x_ddot = (F + M * s * (L * theta_dot**2 - G * c)) / den
    theta_ddot = ((MC + M) * G * s - c * (F + M * L * theta_dot**2 * s)) / (L * den)
    return np.array([x_ddot, theta_ddot])


SPEC = """\
name: pushed
coordinates: [x]
parameters: {m: 2.0, c: 0.5}
inputs:
  F: {value: 1.5, latex: 'F_{\\mathrm{in}}', description: push}
  tau: 0.25
particles:
  P: {mass: m, position: [x, 0]}
forces:
  - {at: P, force: [F, 0]}
generalized_forces:
  x: tau - c*x_dot
"""


def test_layout_inputs_are_a_typed_tuple_in_spec_order():
    import lagcli

    layout = lagcli.load(SPEC).layout
    assert layout.inputs == (Input("F", 1.5, r"F_{\mathrm{in}}", "push"), Input("tau", 0.25, None, None))
    assert layout.input_names == ("F", "tau") and "F" not in layout.parameter_names
    assert Layout.from_json(layout.to_json()) == layout


def test_list_form_defaults_to_zero(derived):
    layout = layout_of(derived("cart_pole"))
    assert layout.inputs == (Input("F", 0.0, None, "horizontal force on the cart"),)


@pytest.fixture(scope="module")
def cart_pole_module(tmp_path_factory):
    from lagcli import commands

    path = tmp_path_factory.mktemp("inputs") / "cart_pole.py"
    commands.generate(str(spec_path("cart_pole")), "python", str(path))
    spec = importlib.util.spec_from_file_location("cart_pole_generated", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_generated_python_takes_u(cart_pole_module):
    module = cart_pole_module
    assert module.INPUTS == {"F": 0.0}
    y = [0.3, 0.4, -0.2, 0.7]
    for F in (0.0, 2.5, -1.0):
        expected = textbook_accelerations(y[1], y[3], F)
        np.testing.assert_allclose(module.rhs(0.0, y, None, [F])[2:], expected, rtol=1e-13)
        np.testing.assert_allclose(module.rhs(0.0, y, None, u={"F": F})[2:], expected, rtol=1e-13)
    # the contract's rhs(t, y, p): inputs at their defaults
    np.testing.assert_allclose(module.rhs(0.0, y, None), module.rhs(0.0, y, None, [0.0]), rtol=0)
    with pytest.raises(ValueError, match="u must have 1 values"):
        module.rhs(0.0, y, None, [1.0, 2.0])
    with pytest.raises(KeyError, match="unknown input"):
        module.rhs(0.0, y, None, {"G": 1.0})


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
def test_generated_c_rhs_u_and_defaults(tmp_path):
    from lagcli import commands

    commands.generate(str(spec_path("cart_pole")), "c", str(tmp_path))
    header = (tmp_path / "cart_pole.h").read_text()
    assert "#define CART_POLE_NINPUT 1" in header and "#define CART_POLE_U_F 0" in header
    assert "int cart_pole_rhs(double t, const double *y, const double *p, double *dydt);" in header
    (tmp_path / "probe.c").write_text(
        '#include <stdio.h>\n#include "cart_pole.h"\n'
        "int main(void) {\n"
        "    const double y[4] = {0.3, 0.4, -0.2, 0.7}, u[CART_POLE_NINPUT] = {2.5};\n"
        "    double a[4], b[4];\n"
        "    if (cart_pole_rhs_u(0.0, y, cart_pole_parameter_defaults, u, a)) return 1;\n"
        "    if (cart_pole_rhs(0.0, y, cart_pole_parameter_defaults, b)) return 1;\n"
        '    printf("%.17g %.17g %.17g %.17g\\n", a[2], a[3], b[2], b[3]);\n'
        "    return 0;\n}\n")
    flags = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]
    subprocess.run(["cc", *flags, "probe.c", "cart_pole.c", "-o", "probe", "-lm"], cwd=tmp_path, check=True)
    values = [float(v) for v in subprocess.run(["./probe"], cwd=tmp_path, capture_output=True, text=True,
                                               check=True, timeout=60).stdout.split()]
    np.testing.assert_allclose(values[:2], textbook_accelerations(0.4, 0.7, 2.5), rtol=1e-13)
    np.testing.assert_allclose(values[2:], textbook_accelerations(0.4, 0.7, 0.0), rtol=1e-13)


def _rows(text: str) -> tuple[list[str], np.ndarray]:
    table = list(csv.reader(io.StringIO(text)))
    return table[0], np.array(table[1:], dtype=float)


@pytest.mark.parametrize("backend", ["python", "c"])
def test_simulate_holds_an_input_set_on_the_command_line(backend, monkeypatch, tmp_path):
    if backend == "c" and shutil.which("cc") is None:
        pytest.skip("no C compiler (cc)")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    F = 0.8
    result = CliRunner().invoke(cli, ["simulate", str(spec_path("cart_pole")), "--backend", backend,
                                      "--t-end", "1", "--dt", "0.25", "--set", f"F={F}"])
    assert result.exit_code == 0, result.output
    header, rows = _rows(result.output)
    col = {name: rows[:, header.index(name)] for name in header}
    p_x = (MC + M) * col["x_dot"] + M * L * np.cos(col["theta"]) * col["theta_dot"]
    np.testing.assert_allclose(p_x, F * col["t"], atol=1e-8)


def test_unknown_set_names_parameters_and_inputs():
    result = CliRunner().invoke(cli, ["simulate", str(spec_path("cart_pole")), "--set", "G=1"])
    assert result.exit_code == 2
    assert "unknown parameter or input 'G'" in result.output and "mc, m, l, g, F" in result.output


def test_api_simulate_inputs_argument():
    import lagcli

    system = lagcli.load(spec_path("cart_pole"))
    trajectory = system.simulate(t_end=0.5, dt=0.25, inputs={"F": 0.8})
    x_dot, theta, theta_dot = (trajectory[name] for name in ("x_dot", "theta", "theta_dot"))
    p_x = (MC + M) * x_dot + M * L * np.cos(theta) * theta_dot
    np.testing.assert_allclose(p_x, 0.8 * trajectory.t, atol=1e-8)
    with pytest.raises(Exception, match="unknown input 'G'"):
        system.simulate(t_end=0.1, inputs={"G": 1.0})


def test_reports_list_the_inputs():
    import json

    runner = CliRunner()
    content = json.loads(runner.invoke(cli, ["derive", str(spec_path("cart_pole")), "--json"]).output)
    assert content["inputs"] == {"F": 0.0} and "F" not in content["parameters"]
    # an input is a signal of time: its force has no potential, no Jacobi integral
    assert content["forces_conservative"] is False and content["jacobi_integral"] is None
    assert "inputs      : F (default 0)" in runner.invoke(cli, ["check", str(spec_path("cart_pole"))]).output
    assert "inputs u          : F (default 0.0)" in runner.invoke(cli, ["derive", str(spec_path("cart_pole"))]).output
