"""Input laws (spec `simulate: inputs:`, `--input`, `System.simulate(inputs=...)`), checked
against closed forms and an LQR design made here with scipy."""
from __future__ import annotations

import json
import math
import shutil
import subprocess

import numpy as np
import pytest
import scipy.linalg

import lagcli
from lagcli.errors import LagcliError

from conftest import SPECS
from test_hybrid_events import run

OSCILLATOR = """
coordinates: [x]
parameters: {m: 2.0, k: 8.0}
inputs: [F]
particles:
  P: {mass: m, position: [x, 0]}
forces:
  - {at: P, force: [F, 0]}
initial: {x: 1.0}
simulate:
  t_end: 3.0
  dt: 0.1
  inputs: {F: -k*x}
"""


def cart_pole_lqr(mc=1.0, m=0.1, l=0.5, g=9.81):
    """A, B of the upright cart-pole (the closed form in specs/cart_pole.yaml) and the LQR
    gain for Q = diag(1, 10, 1, 1), R = 1, from scipy."""
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, -m * g / mc, 0, 0], [0, (mc + m) * g / (mc * l), 0, 0]])
    B = np.array([[0], [0], [1 / mc], [-1 / (mc * l)]])
    P = scipy.linalg.solve_continuous_are(A, B, np.diag([1.0, 10.0, 1.0, 1.0]), np.eye(1))
    return A, B, (B.T @ P).ravel()


def test_spec_law_is_a_spring():
    traj = lagcli.load(OSCILLATOR).simulate()
    assert np.allclose(traj["x"], np.cos(2 * traj.t), atol=1e-8)      # x'' = -k x / m, w = 2


def test_api_laws_numbers_strings_and_callables():
    system = lagcli.load(OSCILLATOR)
    t = system.simulate(inputs={"F": "-2*k*x"}).t
    assert np.allclose(system.simulate(inputs={"F": "-2*k*x"})["x"], np.cos(math.sqrt(8) * t), atol=1e-8)
    callable_run = system.simulate(inputs={"F": lambda t, y: -18.0 * y[0]})
    assert np.allclose(callable_run["x"], np.cos(3 * t), atol=1e-8)
    held = system.simulate(inputs={"F": 4.0})                         # a constant overrides the law
    assert np.allclose(held["x"], 1 + t ** 2, atol=1e-9)


def test_cli_input_and_set_override_the_spec_law(tmp_path):
    spec = tmp_path / "osc.yaml"
    spec.write_text(OSCILLATOR)
    result = run("simulate", spec, "--input", "F=-2*k*x - 0*x_dot + 0*t", "-o", tmp_path / "a.csv")
    assert result.exit_code == 0, result.stderr
    rows = np.loadtxt(tmp_path / "a.csv", delimiter=",", skiprows=1)
    assert np.allclose(rows[:, 1], np.cos(math.sqrt(8) * rows[:, 0]), atol=1e-8)
    result = run("simulate", spec, "--set", "F=4", "-o", tmp_path / "b.csv")
    rows = np.loadtxt(tmp_path / "b.csv", delimiter=",", skiprows=1)
    assert np.allclose(rows[:, 1], 1 + rows[:, 0] ** 2, atol=1e-9)


@pytest.mark.parametrize("law, message", [
    ("F=x_ddot", "an input law cannot use accelerations"),
    ("F=lambda_1", "unknown name 'lambda_1'"),
    ("G=x", "unknown input 'G'"),
    ("F=__import__('os')", "is not allowed"),
])
def test_bad_laws_on_the_command_line_are_exit_2(tmp_path, law, message):
    spec = tmp_path / "osc.yaml"
    spec.write_text(OSCILLATOR)
    result = run("simulate", spec, "--input", law, "-o", tmp_path / "a.csv")
    assert result.exit_code == 2 and message in result.stderr, result.stderr


@pytest.mark.parametrize("value, message", [
    (lambda t, y: "push", "the callable returned 'push', not a number"),
    (lambda t: 1.0, "the callable must take (t, y)"),        # not a bare TypeError from inside the run
    ([1.0, 2.0], "[1.0, 2.0] is not a number, an expression string or a callable u(t, y)"),
])
def test_an_input_that_is_no_law_is_a_clear_error(value, message):
    with pytest.raises(LagcliError) as caught:
        lagcli.load(OSCILLATOR).simulate(inputs={"F": value})
    assert str(caught.value).startswith("inputs={'F': ...}: ") and message in str(caught.value)


def test_closed_loop_eigenvalues_are_those_of_a_minus_b_k():
    A, B, K = cart_pole_lqr()
    gains = [f"k{i}={float(v)!r}" for i, v in enumerate(K, start=1)]
    result = run("linearize", SPECS / "hybrid" / "cart_pole_lqr.yaml", "--closed-loop", "--json",
                 *[a for g in gains for a in ("--at", g)])
    assert result.exit_code == 0, result.stderr
    content = json.loads(result.stdout)
    assert content["notes"] == ["closed loop: the input laws substituted "
                                "(F = -k1*x - k2*theta - k3*x_dot - k4*theta_dot)"]    # said so
    found = [complex(*e) for e in content["eigenvalues"]]        # [re, im] pairs
    expected = sorted(np.linalg.eigvals(A - B @ K[None, :]), key=lambda z: (z.real, z.imag))
    found = sorted(found, key=lambda z: (z.real, z.imag))
    assert np.allclose(found, expected, atol=1e-8)


def test_lqr_brings_the_cart_pole_back_upright():
    A, B, K = cart_pole_lqr()
    system = lagcli.load(SPECS / "hybrid" / "cart_pole_lqr.yaml")
    traj = system.simulate(parameters={f"k{i}": v for i, v in enumerate(K, start=1)}, initial={"theta": 0.2})
    assert traj["theta"][0] == 0.2
    assert np.max(np.abs(traj["theta"][-100:])) < 1e-3 and abs(traj["x"][-1]) < 1e-2
    assert np.max(np.abs(traj["theta"])) <= 0.2 + 1e-12


def generated_module(spec_path, tmp_path):
    """The module `generate --lang python` writes for `spec_path`, imported."""
    import importlib.util

    (name, text), = lagcli.load(spec_path).generate("python").items()
    path = tmp_path / name
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(f"{path.stem}_generated", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_generated_module_takes_a_callable_law(tmp_path):
    module = generated_module(SPECS / "cart_pole.yaml", tmp_path)
    A, B, K = cart_pole_lqr()
    header, rows = module.simulate(t_end=10.0, y0=[0.0, 0.2, 0.0, 0.0], u=lambda t, y: [-K @ np.asarray(y)])
    system = lagcli.load(SPECS / "hybrid" / "cart_pole_lqr.yaml")
    traj = system.simulate(parameters={f"k{i}": v for i, v in enumerate(K, start=1)}, t_end=10.0)
    assert np.allclose(rows[:, 1:5], traj.states, atol=1e-7)


def test_the_compiled_driver_runs_laws_in_c_and_never_reuses_a_driver_for_another_law(tmp_path, monkeypatch):
    """The law is C code of the generated model (the closed loop), so C and Python agree,
    and a second law (or a constant that replaces it) gets its own cached driver."""
    import shutil

    if shutil.which("cc") is None:
        pytest.skip("no C compiler (cc)")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    system = lagcli.load(SPECS / "hybrid" / "cart_pole_lqr.yaml")
    for inputs in ({}, {"F": "-(k2*theta + k4*theta_dot)"}, {"F": 0.0}):
        c = system.simulate(t_end=2.0, backend="c", inputs=inputs)
        python = system.simulate(t_end=2.0, backend="python", inputs=inputs)
        assert np.allclose(c.states, python.states, rtol=1e-8, atol=1e-8), inputs
    entries = [p for p in (tmp_path / "cache" / "lagcli").iterdir() if (p / "meta.json").exists()]
    assert len(entries) == 3                       # one driver per law set
    with pytest.raises(LagcliError, match="callable"):
        system.simulate(t_end=1.0, backend="c", inputs={"F": lambda t, y: 0.0})


@pytest.mark.parametrize("lang", ["rust"])
def test_targets_without_laws_refuse_them_clearly(lang, tmp_path):
    """Rust does not carry the laws: a located refusal, exit 2, nothing written (the C,
    Python, Octave, FMU, CasADi and JAX targets do)."""
    result = run("generate", SPECS / "hybrid" / "cart_pole_lqr.yaml", "--lang", lang, "-o", tmp_path / "out")
    assert result.exit_code == 2
    assert "cart_pole_lqr.yaml: --lang" in result.stderr and "does not implement simulate: inputs: yet" in result.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
def test_generated_c_runs_the_spec_law_like_the_python_backend(tmp_path):
    """`generate --lang c` substitutes the spec's law into the model, so its own driver
    (<name>_main.c) balances the cart-pole: its CSV equals `lagcli simulate --backend
    python` (the law evaluated numerically in the run layer's loop) to ~1e-9."""
    from test_codegen_c import RUNTIME_SOURCES, compile_c

    spec = SPECS / "hybrid" / "cart_pole_lqr.yaml"
    out = tmp_path / "c"
    assert run("generate", spec, "--lang", "c", "-o", out).exit_code == 0
    assert "F = -k1*x - k2*theta - k3*x_dot - k4*theta_dot" in (out / "cart_pole_lqr.h").read_text()
    compile_c(["cart_pole_lqr.c", "cart_pole_lqr_main.c", *RUNTIME_SOURCES, "-o", "driver"], out)
    done = subprocess.run([str(out / "driver")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    (out / "c.csv").write_text(done.stdout)
    assert run("simulate", spec, "--backend", "python", "-o", tmp_path / "python.csv").exit_code == 0
    c, python = (np.genfromtxt(path, delimiter=",", names=True) for path in (out / "c.csv", tmp_path / "python.csv"))
    assert c.dtype.names == python.dtype.names and len(c) == len(python) == 1001
    for name in c.dtype.names:
        assert np.allclose(c[name], python[name], rtol=0, atol=1e-9), name
    assert abs(c["theta"][-1]) < 1e-3 < abs(c["theta"][0])     # balanced: the law acted
    held = subprocess.run([str(out / "driver"), "--set", "F=0.3", "--t-end", "1"], capture_output=True, text=True,
                          timeout=120)                     # --set replaces the law, as lagcli simulate's
    rows = np.loadtxt(held.stdout.splitlines()[1:], delimiter=",")
    expected = lagcli.load(spec).simulate(t_end=1.0, inputs={"F": 0.3}, backend="python")
    assert held.returncode == 0 and np.allclose(rows[:, 1:5], expected.states, rtol=0, atol=1e-9)
    assert rows[-1, 2] > 1.0                                   # no law: the pole falls


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
def test_generated_c_rhs_u_stays_open_loop_for_embedding_and_spec_inputs_is_the_law(tmp_path):
    """An embedding program's u acts: `_rhs_u` of a spec with a law is the open-loop
    cart-pole (the 2x2 Lagrange equations solved here with numpy), whatever the law, and
    `_spec_inputs` is the law u = -(k1 x + k2 theta + k3 x_dot + k4 theta_dot)."""
    from test_codegen_c import compile_c

    spec = SPECS / "hybrid" / "cart_pole_lqr.yaml"
    assert run("generate", spec, "--lang", "c", "-o", tmp_path).exit_code == 0
    (tmp_path / "cart_pole_lqr_main.c").unlink()
    (tmp_path / "use.c").write_text(r"""
#include <stdio.h>
#include "cart_pole_lqr.h"

int main(void)
{
    const double *p = cart_pole_lqr_parameter_defaults;
    const double y[4] = {0.3, -0.4, 0.5, 0.7}, u_given[1] = {0.8};
    double u[1], dydt[4];
    cart_pole_lqr_spec_inputs(0.0, y, p, u);
    if (cart_pole_lqr_rhs_u(0.0, y, p, u_given, dydt) != 0)
        return 1;
    printf("%.17g %.17g %.17g\n", u[0], dydt[2], dydt[3]);
    return 0;
}
""")
    compile_c(sorted(p.name for p in tmp_path.glob("*.c")) + ["-o", "use"], tmp_path)
    out = subprocess.run(["./use"], cwd=tmp_path, capture_output=True, text=True, check=True).stdout.split()
    u, x_ddot, theta_ddot = map(float, out)
    x, theta, x_dot, theta_dot = 0.3, -0.4, 0.5, 0.7
    mc, m, l, g, k1, k2, k3, k4 = 1.0, 0.1, 0.5, 9.81, -1.0, -30.61497677, -2.24534752, -6.7231181
    assert u == pytest.approx(-(k1 * x + k2 * theta + k3 * x_dot + k4 * theta_dot), rel=1e-14)
    M = np.array([[mc + m, m * l * math.cos(theta)], [m * l * math.cos(theta), m * l ** 2]])
    F = np.array([0.8 + m * l * math.sin(theta) * theta_dot ** 2, m * g * l * math.sin(theta)])
    assert np.allclose([x_ddot, theta_ddot], np.linalg.solve(M, F), rtol=1e-13, atol=0)


def test_generated_module_runs_the_spec_law_by_default_and_u_overrides_it(tmp_path):
    """The module's simulate() uses the spec's law (its `spec_inputs`) when u is not given:
    the rows equal `lagcli simulate` (the run layer's loop with the law lambdified from
    sympy); u= still overrides it: held at 0 the pole falls, the LQR gain made here with
    scipy balances it as the spec's does."""
    module = generated_module(SPECS / "hybrid" / "cart_pole_lqr.yaml", tmp_path)
    header, rows = module.simulate()
    traj = lagcli.load(SPECS / "hybrid" / "cart_pole_lqr.yaml").simulate(backend="python")
    assert header[:5] == ["t", "x", "theta", "x_dot", "theta_dot"]
    assert np.array_equal(rows[:, 0], traj.t)
    assert np.allclose(rows[:, 1:5], traj.states, rtol=0, atol=1e-9)
    assert abs(rows[-1, 2]) < 1e-3
    _, falling = module.simulate(u=[0.0])
    assert abs(falling[-1, 2]) > 0.3
    K = cart_pole_lqr()[2]
    _, balanced = module.simulate(u=lambda t, y: [-K @ np.asarray(y)])
    assert np.allclose(balanced[:, 1:5], rows[:, 1:5], atol=1e-6)      # the spec's gain is this K to 8 digits


FORCED = OSCILLATOR.replace("parameters: {m: 2.0, k: 8.0}", "parameters: {m: 2.0, k: 8.0, w: 3.0}\n"
                            "known: {f: sin(w*t)}\ndefinitions: {stiffness: k}").replace(
    "inputs: {F: -k*x}", "inputs: {F: -stiffness*x + f}")        # a known function and a definition


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_law_of_a_known_function_and_a_definition_against_the_forced_oscillator(backend):
    """m x'' = -k x + sin(w t) from x = 1 at rest: x = cos(2t) + (w/2) B sin(2t) - B sin(w t)
    with B = 1/(m (w^2 - 4)) = 0.1 (w0 = 2)."""
    if backend == "c" and shutil.which("cc") is None:
        pytest.skip("no C compiler (cc)")
    traj = lagcli.load(FORCED).simulate(backend=backend)
    t, B = traj.t, 1 / (2.0 * (9.0 - 4.0))
    assert np.allclose(traj["x"], np.cos(2 * t) + 1.5 * B * np.sin(2 * t) - B * np.sin(3 * t), rtol=0, atol=1e-8)
