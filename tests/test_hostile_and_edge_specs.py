"""Specs that once fooled or stalled the engine: each must give the right answer or a
located error (exit 2), never a traceback or a hang (a hang is caught by pytest-timeout:
a guard on the test run, not a timing assertion)."""
import json
import math
import os
import subprocess
import sys

import pytest
from click.testing import CliRunner

from lagcli.derive.pipeline import load_model
from lagcli.model.calculus import DependenceProbe, numerically_zero
from lagcli.cli import cli
from lagcli.derive import derive
from lagcli.errors import SpecError
from lagcli.spec.files import read_spec_bytes
from lagcli.render.spec_printer import parse_output

import sympy as sp

pytestmark = pytest.mark.timeout(300)

HEAD = "coordinates: [x, y]\nparameters: {k: 2.0, m: 1.0}\nparticles:\n  P: {mass: m, position: [x, y]}\n"


def write(tmp_path, body, name="s.yaml"):
    path = tmp_path / name
    path.write_text(HEAD + body)
    return path


def invoke(*args):
    result = CliRunner().invoke(cli, [str(a) for a in args])
    assert "Traceback" not in result.output
    return result


def test_dependence_is_assumed_when_no_point_evaluates(tmp_path):
    # sqrt(x - 5) and log(y - 10) are complex at every random point in [0.3, 1.3]
    d = derive(load_model(write(tmp_path, "potential: k*sqrt(x - 5) + k*log(y - 10)\n")))
    assert d.ignorable == ()


def test_probe_and_zero_test_can_say_no():
    x, t = sp.symbols("x t", real=True)
    assert not numerically_zero([sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1 + 1e-6 * x])
    assert numerically_zero([sp.sin(x + t) - sp.sin(x) * sp.cos(t) - sp.cos(x) * sp.sin(t)])
    assert DependenceProbe([sp.cos(x * t) ** 2 + sp.sin(x * t) ** 2]).depends_on(t) is False
    assert DependenceProbe([sp.cos(x * t)]).depends_on(t) is True


@pytest.mark.parametrize("constraint", ["sign(x_dot)*y_dot", "abs(x_dot) - 1", "x_dot**2 - y_dot",
                                        "max(x_dot, y_dot)"])
def test_non_linear_velocity_constraints_are_refused(tmp_path, constraint):
    result = invoke("check", write(tmp_path, f"constraints: ['{constraint}']\n"))
    assert result.exit_code == 2
    assert "not linear in the velocities" in result.stderr and "constraints[0]" in result.stderr


def test_exploding_definitions_are_refused_quickly(tmp_path):
    body = "definitions:\n  d1: x + y\n" + "".join(
        f"  d{i}: sin(d{i - 1})*cos(d{i - 1}) + d{i - 1}*d{i - 1}\n" for i in range(2, 14))
    result = invoke("check", write(tmp_path, body + "potential: d13\n"))
    assert result.exit_code == 2 and "too large" in result.stderr


@pytest.mark.parametrize("value", ["exp(exp(exp(100)))", "log(0)", "sqrt(-1)"])
def test_bad_constants_are_located_errors(tmp_path, value):
    path = tmp_path / "c.yaml"
    path.write_text(f"coordinates: [x]\nparameters:\n  m: '{value}'\nparticles:\n  P: {{mass: m, position: [x, 0]}}\n")
    result = invoke("check", path)
    assert result.exit_code == 2 and "c.yaml:3" in result.stderr and "parameters.m" in result.stderr


def test_complex_expression_is_a_located_error(tmp_path):
    result = invoke("derive", write(tmp_path, "potential: sqrt(-1)*x\n"))
    assert result.exit_code == 2 and "s.yaml:5" in result.stderr and "potential" in result.stderr


def test_cubic_kinetic_energy_is_a_located_error(tmp_path):
    result = invoke("check", write(tmp_path, "kinetic: x_dot**3\n"))
    assert result.exit_code == 2 and "s.yaml:5" in result.stderr and "degree at most 2" in result.stderr


def test_big_power_does_not_stall_the_report(tmp_path):
    result = invoke("derive", write(tmp_path, "potential: (sin(x) + cos(y) + x*y)**1000\n"))
    assert result.exit_code == 0


def test_non_smooth_functions_report_in_the_spec_language(tmp_path):
    path = write(tmp_path, "potential: k*max(x, 0)**2/2 + k*abs(y)\n")
    result = invoke("derive", path, "--json")
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    d = derive(load_model(path))
    forcing = [parse_output(report["explicit_form"]["forcing"][q], d.model) for q in ("x", "y")]
    x, y, k = (d.model.symbol(n) for n in ("x", "y", "k"))
    values = {x: 0.7, y: -0.4, k: 2.0}
    assert [float(f.subs(values)) for f in forcing] == pytest.approx([-2.0 * 0.7, 2.0])


def test_writing_onto_a_directory_is_a_clear_error(tmp_path):
    result = invoke("derive", write(tmp_path, ""), "-o", tmp_path)
    assert result.exit_code == 2 and "cannot write" in result.stderr


@pytest.mark.parametrize("setting", ["t_end: '-1'", "dt: -1", "rtol: 0"])
def test_non_positive_simulate_settings_are_located_once(tmp_path, setting):
    result = invoke("check", write(tmp_path, f"simulate: {{{setting}}}\n"))
    key = setting.split(":")[0]
    assert result.exit_code == 2 and f"s.yaml:5:" in result.stderr
    assert result.stderr.count(f"simulate.{key}: must be positive") == 1


def test_generalized_force_that_vanishes_identically_keeps_the_jacobi_integral(tmp_path):
    d = derive(load_model(write(tmp_path, "generalized_forces: {x: k*(sin(x)**2 + cos(x)**2 - 1)}\n")))
    assert d.jacobi_integral is not None
    assert [q.name for q in d.ignorable] == ["x", "y"]


def test_a_declared_known_function_makes_the_spec_rheonomic(tmp_path):
    d = derive(load_model(write(tmp_path, "known: {f: sin(t)}\n")))
    assert not d.scleronomic


def test_format_and_expression_problems_are_reported_together(tmp_path):
    path = tmp_path / "multi.yaml"
    path.write_text("coordinates: [x]\nparamters: {m: 1}\nparticles:\n  P: {mass: 1, position: [x, zz]}\n"
                    "potential: qq*x\n")
    result = invoke("check", path)
    assert result.exit_code == 2
    for expected in ("multi.yaml:2:1: paramters: unknown key", "did you mean 'parameters'",
                     "multi.yaml:4:30: particles.P.position[1]: in 'zz': unknown name 'zz'",
                     "multi.yaml:5:12: potential: in 'qq*x': unknown name 'qq'"):
        assert expected in result.stderr


# --- hostile files: refused before anything is read (lagcli.spec.files.read_spec_bytes) ---

@pytest.mark.parametrize("command", [["check"], ["derive"], ["simulate", "--t-end", "0.1"]])
def test_a_fifo_spec_is_refused_without_blocking(tmp_path, monkeypatch, command):
    # nobody ever writes to the pipe: opening it for reading would block forever
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    result = invoke(*command, fifo)
    assert result.exit_code == 2, result.output
    assert f"{fifo}: cannot read the spec: it is a named pipe (FIFO)" in result.stderr


@pytest.mark.parametrize("command", [["check"], ["simulate", "--t-end", "0.1"]])
def test_an_endless_device_is_refused_without_reading_it(tmp_path, monkeypatch, command):
    # /dev/zero never ends: simulate's warm path (the driver cache lookup) reads the spec
    # bytes before anything else, so it too must refuse the device before reading
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    link = tmp_path / "zero.yaml"
    link.symlink_to("/dev/zero")
    for path in (link, "/dev/zero"):
        result = invoke(*command, path)
        assert result.exit_code == 2, result.output
        assert "Traceback" not in result.output
    assert f"{link}: cannot read the spec: it is a device" in invoke(*command, link).stderr


def test_a_directory_spec_is_refused(tmp_path):
    folder = tmp_path / "folder.yaml"
    folder.mkdir()
    result = invoke("check", folder)  # click refuses it first
    assert result.exit_code == 2 and "is a directory" in result.stderr
    with pytest.raises(SpecError, match="cannot read the spec: it is a directory"):
        read_spec_bytes(folder)


def test_read_spec_bytes_does_not_import_sympy_or_numpy():
    # the warm C path of `simulate` reads the spec with it and must stay light
    code = ("import sys; from lagcli.spec.files import read_spec_bytes; "
            "print(sorted(m for m in ('sympy', 'numpy') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


# --- constants and long text ---

def test_long_user_text_is_clipped_in_messages(tmp_path):
    key = "k" * 50_000  # an explicit key (?): YAML limits plain keys to 1024 characters
    path = tmp_path / "long.yaml"
    path.write_text(f"coordinates: [x]\n? {key}\n: 1\npotential: x + {'y' * 15_000}\n")
    result = invoke("check", path)
    assert result.exit_code == 2
    assert "unknown key 'kkkk" in result.stderr and "(50000 characters)" in result.stderr
    assert "unknown name 'yyyy" in result.stderr and "(15000 characters)" in result.stderr
    assert len(result.stderr) < 3000


@pytest.mark.parametrize("value, expected", [
    ("1e-300", 1e-300), ("-1e300", -1e300), ("exp(690)", math.exp(690)), ("acos(1/2)*3", math.pi),
    ("atan2(0, -1)", math.pi), ("min(2, sqrt(3))", math.sqrt(3)), ("sign(-1e-300)", -1.0),
])
def test_constants_in_range_are_accepted(tmp_path, value, expected):
    path = tmp_path / "c.yaml"
    path.write_text(f"coordinates: [x]\nparameters:\n  m: '{value}'\nparticles:\n  P: {{mass: 1, position: [x, 0]}}\n")
    (parameter,) = load_model(path).parameters
    assert parameter.value == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("potential, problem", [
    ("x*1e300*1e300", "too large"),                 # sympy merges the numbers into 1e600*x
    ("x/(1e-200*1e-200)", "too small"),
    ("x**(sqrt(-2)**2)", "complex"),
    ("x**acos(2)", "the constant acos(2) is not a real number"),
    ("log(0)*x", "the constant log(0) is infinite"),
    ("x*exp(1e6)", "the constant exp(1e6) is too large"),
    ("x/(sin(pi))", "division by zero"),
])
def test_bad_constants_inside_expressions_are_located(tmp_path, potential, problem):
    result = invoke("check", write(tmp_path, f"potential: {potential}\n"))
    assert result.exit_code == 2, result.output
    assert "s.yaml:5:12: potential:" in result.stderr and problem in result.stderr


def test_sign_of_a_reciprocal_in_a_position_derives(tmp_path):
    # sympy leaves d/dx sign(1/x) unevaluated (it cannot prove 1/x real); it is 0
    path = tmp_path / "sign.yaml"
    path.write_text("coordinates: [x]\nparameters: {m: 1.0}\nparticles:\n"
                    "  P: {mass: m, position: [x, sign(1/x)]}\n")
    d = derive(load_model(path))
    x_dot, m = d.model.qd[0], d.model.symbol("m")
    assert sp.simplify(d.T - m * x_dot**2 / 2) == 0


def test_many_ignorable_coordinates(tmp_path):
    # 12 free particles on a line chain of springs in y: every x_i is ignorable, no y_i is;
    # deciding this is one pass per coordinate (no work repeated per ignorable coordinate)
    n = 12
    path = tmp_path / "free.yaml"
    path.write_text(
        f"coordinates: [{', '.join(f'x{i}' for i in range(n))}, {', '.join(f'y{i}' for i in range(n))}]\n"
        "parameters: {m: 1.0, k: 2.0}\nparticles:\n"
        + "".join(f"  P{i}: {{mass: m, position: [x{i}, y{i}]}}\n" for i in range(n))
        + "potential: '" + " + ".join(f"k*(y{i} - y{i + 1})**2/2" for i in range(n - 1)) + "'\n")
    d = derive(load_model(path))
    assert [q.name for q in d.ignorable] == [f"x{i}" for i in range(n)]
    momenta = {c.name: c.expr for c in d.conserved if c.kind == "momentum"}
    m = d.model.symbol("m")
    assert all(sp.simplify(momenta[f"p_x{i}"] - m * d.model.qd[i]) == 0 for i in range(n))


@pytest.mark.parametrize("tower", ["sin(exp(exp(exp(exp(x)))))", "exp(exp(exp(exp(exp(exp(x))))))"])
def test_towers_in_numeric_identity_tests_do_not_stall(tmp_path, tower):
    # "is Q'_y zero?", "is the row integrable?" are decided at random points: there the
    # towers overflow double precision, which makes a point unusable instead of making
    # mpmath compute pi to millions of digits (sin) or run out of memory (exp)
    result = invoke("check", write(tmp_path, f"generalized_forces: {{y: '{tower}'}}\n"
                                             f"constraints: ['x_dot - {tower}*y_dot']\n"))
    assert result.exit_code == 0, result.output
    assert "Jacobi      : does not exist" in result.stdout


def test_roots_of_big_numbers_are_taken_in_floating_point(tmp_path):
    # sympy would factor the 40-digit integer to pull perfect powers out of the exact root
    big = "1234567890123456789012345678901234567891"
    d = derive(load_model(write(tmp_path, f"potential: ({big})^(1/3)*x + sqrt(2)*y\n")))
    x, y = d.model.q
    assert float(d.V.coeff(x)) == pytest.approx(int(big) ** (1 / 3), rel=1e-14)
    assert d.V.coeff(y) == sp.sqrt(2)  # small numbers stay exact


def test_dependence_probe_moves_one_symbol_as_a_fresh_evaluation():
    """The probe evaluates a moved point from the base point's values, only what mentions
    the moved symbol anew: the very values sympy's own evaluation at that point gives
    (within rounding; here to 1e-12), for a chain's V-like nested sums, and its verdicts
    follow (sin^2 + cos^2 of the moved symbol cancels)."""
    import random

    from lagcli.model.calculus import _Moved

    q = sp.symbols("q1:13", real=True)
    g, W = sp.symbols("g W", real=True)
    sums = [sp.Add(*(sp.cos(q[i]) * (i + 1) for i in range(k + 1))) for k in range(len(q))]
    V = sp.Add(*(g * (k + 2) * s for k, s in enumerate(sums))) + sp.sin(W * q[3]) ** 2 + sp.cos(W * q[3]) ** 2
    probe = DependenceProbe([V, sp.exp(sums[-1] / 50) / (2 + sp.sin(q[0]))])
    base, first, memo = probe._point(0)
    rng = random.Random(3)
    for symbol in probe.symbols:
        at = base[symbol] + rng.uniform(0.5, 1.5)
        moved = _Moved(probe, memo, symbol, at)
        point = {**base, symbol: at}
        for expr in probe.exprs:
            assert abs(moved.value(expr) - float(expr.evalf(subs=point))) < 1e-12 * (1 + abs(moved.value(expr)))
    assert all(probe.depends_on(s) for s in (*q, g))
    assert DependenceProbe([V - g * sp.Add(*((k + 2) * s for k, s in enumerate(sums)))]).depends_on(q[3]) is False
