"""`lagcli generate --lang c`, compiled and run, for every bundled spec.

- `<name>.c` + `<name>_main.c` compile with the contract's strict flags and nothing else;
- `<name>.c` built as a shared library (the strict flags plus `-shared -fPIC`) is called
  through ctypes at seeded random states: q'', lambda, M, F and the invariants agree with
  the mpmath reference of test_codegen_python.py to 1e-12 relative;
- the driver run with no arguments prints the CSV header of `lagcli simulate` and one
  row per output time; with options it follows them, and it agrees with the generated
  Python module's `simulate` (the same integrator algorithm);
- names that are C keywords or math.h names (`double`, `register`, `y0`, `M_PI`) compile.

Skipped when there is no `cc`.
"""
from __future__ import annotations

import ctypes
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from test_codegen_python import SPEC_FILES, assert_close, compare, random_inputs, spec_id

ROOT = Path(__file__).resolve().parent.parent
CC = shutil.which("cc")
CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]

pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler (cc)")

KEYWORD_SPEC = """\
name: int
coordinates: [double]
parameters:
  register: 2.0
  y0: 1.5
  M_PI: 3.0
  x0: 2.0
potential: register*double**2/2 + M_PI*cos(double) + pi*double
kinetic: y0*double_dot**2/2 + x0*double_dot**2
initial: {double: 0.1}
simulate: {t_end: 0.05, dt: 0.01}
"""


class Built:
    """A generated C model: its directory, driver executable and ctypes library."""

    def __init__(self, spec: Path, directory: Path):
        from lagcli import commands

        self.name = spec.stem if spec.suffix else spec.name
        commands.generate(str(spec), "c", str(directory))
        self.name = next(p.stem for p in directory.glob("*.h") if not p.name.startswith("lagcli_"))
        self.directory = directory
        self.driver = directory / self.name
        compile_c([f"{self.name}.c", f"{self.name}_main.c", *RUNTIME_SOURCES, "-o", self.name], directory)
        library = directory / f"lib{self.name}.so"
        compile_c(["-shared", "-fPIC", f"{self.name}.c", "-o", library.name], directory)
        self.lib = ctypes.CDLL(str(library))

    def function(self, suffix: str):
        return getattr(self.lib, f"{self.name}_{suffix}")

    def strings(self, suffix: str) -> list[str]:
        table = (ctypes.c_char_p * 64).in_dll(self.lib, f"{self.name}_{suffix}")
        names = []
        for value in table:
            if value is None:
                return names
            names.append(value.decode())
        raise AssertionError(f"{suffix} is not NULL-terminated")

    def doubles(self, suffix: str, count: int) -> list[float]:
        return list((ctypes.c_double * count).in_dll(self.lib, f"{self.name}_{suffix}"))

    def run(self, *args: str) -> subprocess.CompletedProcess:
        return subprocess.run([str(self.driver), *args], capture_output=True, text=True, timeout=300)


RUNTIME_SOURCES = ("lagcli_ode.c", "lagcli_driver.c", "lagcli_variational.c", "lagcli_events.c")    # lagcli/runtime/c/, copied by generate


def compile_c(arguments: list[str], directory: Path) -> None:
    done = subprocess.run([CC, *CFLAGS, *arguments, "-lm"], cwd=directory, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(arguments)}:\n{done.stderr}"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    made = {}

    def get(spec: Path) -> Built:
        if spec not in made:
            made[spec] = Built(spec, tmp_path_factory.mktemp(f"c_{spec.stem}"))
        return made[spec]

    return get


def doubles(values) -> ctypes.Array:
    values = list(values)
    return (ctypes.c_double * max(1, len(values)))(*values)


def call(c: Built, d, case: dict) -> dict:
    n, m = d.n, len(d.constraints)
    y, p = doubles(case["y"]), doubles(case["p"])
    dydt, lam = doubles([0.0] * 2 * n), doubles([0.0] * m)
    M, F = doubles([0.0] * n * n), doubles([0.0] * n)
    ninv = len(c.strings("invariant_names"))
    inv = doubles([0.0] * ninv)
    t, alpha, beta = (ctypes.c_double(case[k]) for k in ("t", "alpha", "beta"))
    u = (doubles(case["u"]),) if d.model.inputs else ()     # a spec with inputs: the _u functions
    suffix = "_u" if u else ""
    assert c.function("rhs_stabilized" + suffix)(t, y, p, *u, alpha, beta, dydt, lam) == 0
    assert c.function("invariants")(t, y, p, inv) == 0
    assert c.function("mass_matrix")(t, y, p, M) == 0
    assert c.function("forcing" + suffix)(t, y, p, *u, F) == 0
    plain = doubles([0.0] * 2 * n)
    assert c.function("rhs" + suffix)(t, y, p, *u, plain) == 0
    names = c.strings("invariant_names")
    return {"qdd": list(dydt)[n:], "lam": list(lam)[:m], "M": list(M), "F": list(F),
            "inv": dict(zip(names, list(inv))), "rhs": list(plain), "dydt": list(dydt)}


@pytest.mark.core_specs
@pytest.mark.parametrize("spec", SPEC_FILES, ids=spec_id)
def test_c_agrees_with_engine(spec, built, derived, rng):
    d = derived(spec.name)
    c = built(spec)
    n = d.n
    model = d.model
    assert c.strings("state_names") == [s.name for s in model.q + model.qd]
    assert c.strings("parameter_names") == [p.symbol.name for p in model.parameters]
    assert c.strings("multiplier_names") == [s.name for s in d.multipliers]
    if model.parameters:
        assert c.doubles("parameter_defaults", len(model.parameters)) == [p.value for p in model.parameters]
    for i, case in enumerate(random_inputs(d, rng)):
        got = call(c, d, case)
        label = f"{spec.stem} state {i} (alpha={case['alpha']:.3g})"
        compare(d, case, got, label)
        assert_close(got["dydt"][:n], case["y"][n:], f"{label}: q'", rtol=0)
        if case["alpha"] == 0.0:
            assert_close(got["rhs"], got["dydt"], f"{label}: rhs", rtol=0)


@pytest.mark.parametrize("spec", SPEC_FILES, ids=spec_id)
def test_driver_without_arguments_prints_the_csv(spec, built, derived):
    from lagcli.runtime.run_rules import output_times

    d = derived(spec.name)
    c = built(spec)
    done = c.run()
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    model = d.model
    invariants = ["energy"] + (["jacobi"] if d.jacobi_integral is not None else [])
    invariants += [f"p_{q.name}" for q in d.ignorable] + (["constraint_residual"] if d.constraints else [])
    header = ["t", *(s.name for s in model.q + model.qd), *(s.name for s in d.multipliers), *invariants]
    assert lines[0].split(",") == header
    assert len(lines) - 1 == len(output_times(model.settings.t_end, model.settings.dt))
    first = [float(v) for v in lines[1].split(",")]
    assert first[0] == 0.0 and np.all(np.isfinite(first))


def test_driver_options_and_agreement_with_python(built, tmp_path):
    """Options override the spec; rows match the generated module's simulate()."""
    import importlib.util

    from lagcli import commands

    spec = ROOT / "specs" / "cartesian_pendulum.yaml"
    c = built(spec)
    args = ["--t-end", "0.5", "--dt=0.125", "--method", "RK45", "--rtol", "1e-10", "--atol", "1e-12",
            "--set", "l=1.0", "--init", "x_dot=0.4", "--baumgarte", "5", "5"]
    done = c.run(*args)
    assert done.returncode == 0, done.stderr
    rows = np.array([[float(v) for v in line.split(",")] for line in done.stdout.splitlines()[1:]])
    assert list(rows[:, 0]) == [0.0, 0.125, 0.25, 0.375, 0.5]

    commands.generate(str(spec), "python", str(tmp_path / "m.py"))
    loader = importlib.util.spec_from_file_location("cartesian", tmp_path / "m.py")
    module = importlib.util.module_from_spec(loader)
    loader.loader.exec_module(module)
    y0 = list(module.INITIAL)
    _, expected = module.simulate(t_end=0.5, dt=0.125, method="RK45", rtol=1e-10, atol=1e-12,
                                  p={"l": 1.0}, y0=y0, baumgarte=(5.0, 5.0))
    assert np.allclose(rows, expected, rtol=1e-9, atol=1e-12)


def test_driver_rejects_bad_options(built):
    c = built(ROOT / "specs" / "double_pendulum.yaml")
    for args in (["--method", "Radau"], ["--set", "nope=1"], ["--dt", "0"], ["--t-end"], ["--frobnicate"],
                 ["--init", "theta1=abc"]):
        done = c.run(*args)
        assert done.returncode == 2, args
        assert done.stderr.startswith("error: ") and done.stdout == ""
    assert c.run("--help").returncode == 0
    for args, message in ((["--set", "zz=1"], "error: --set zz=1: unknown parameter 'zz'"),
                          (["--set", "m1=abc"], "error: --set m1=abc: 'abc' is not a number"),
                          (["--init", "q=1"], "error: --init q=1: unknown coordinate or velocity 'q'"),
                          (["--init", "=1"], "error: --init =1: expected NAME=VALUE")):
        done = c.run(*args)
        assert done.returncode == 2 and done.stderr.splitlines()[0] == message, done.stderr


def test_driver_warns_about_an_inconsistent_initial_state(built):
    """It integrates the state as given (lagcli simulate is the one that repairs it), but
    says so: the rod constraint x^2 + y^2 - l^2 is off by 0.5^2 + 0.8^2 - 1 = -0.11."""
    c = built(ROOT / "specs" / "cartesian_pendulum.yaml")
    done = c.run("--init", "x=0.5", "--t-end", "0.02")
    assert done.returncode == 0, done.stderr
    assert done.stderr.startswith("warning: the initial state violates the constraints: "
                                  "constraint_residual = 0.11 ")
    assert len(done.stdout.splitlines()) == 4
    consistent = c.run("--init", "x=0.6", "--init", "y=-0.8", "--t-end", "0.02")
    assert consistent.returncode == 0 and consistent.stderr == ""
    unconstrained = built(ROOT / "specs" / "double_pendulum.yaml").run("--init", "theta1=3", "--t-end", "0")
    assert unconstrained.returncode == 0 and unconstrained.stderr == ""


def test_driver_failure_reports_time_and_keeps_rows(built):
    """A singular mass matrix (l2 = 0) stops the run: rows so far, message, exit 1."""
    c = built(ROOT / "specs" / "double_pendulum.yaml")
    done = c.run("--set", "l2=0", "--t-end", "0.1")
    assert done.returncode == 1
    assert done.stderr.startswith("error: at t = 0: singular mass matrix")
    assert done.stdout.splitlines()[0].startswith("t,theta1")


def test_keyword_names_compile(tmp_path, built):
    spec = tmp_path / "int.yaml"
    spec.write_text(KEYWORD_SPEC)
    c = built(spec)
    assert c.strings("parameter_names") == ["register", "y0", "M_PI", "x0"]
    done = c.run()
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == "t,double,double_dot,energy,jacobi"
    code = re.sub(r'/\*.*?\*/|"[^"]*"', "", (c.directory / "int.c").read_text(), flags=re.S)
    assert not re.search(r"\bM_[A-Z0-9_]+", code)          # C99 has no M_PI: a literal instead
    assert "3.14159265358979323846" in code


def test_generate_c_cli_writes_the_model_and_the_runtime_and_needs_a_directory(tmp_path):
    from click.testing import CliRunner

    from lagcli.cli import cli

    spec = str(ROOT / "specs" / "double_pendulum.yaml")
    result = CliRunner().invoke(cli, ["generate", spec, "--lang", "c"])
    assert result.exit_code == 2
    assert "-o DIR" in result.output
    result = CliRunner().invoke(cli, ["generate", spec, "--lang", "c", "-o", str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "double_pendulum.c", "double_pendulum.h", "double_pendulum_main.c",
        "lagcli_driver.c", "lagcli_driver.h", "lagcli_events.c", "lagcli_events.h", "lagcli_linalg.h",
        "lagcli_model.h", "lagcli_ode.c", "lagcli_ode.h", "lagcli_variational.c", "lagcli_variational.h"]


def test_printed_functions_evaluate_in_c_like_math(tmp_path):
    """sign, Abs, Min, Max, atan2, tanh... printed by CPrinter, compiled, compared with
    Python's math at points on and off the kinks. sign is a double: sign(x)/sign(y) at
    y = 0 is inf, not an integer division by zero (SIGFPE)."""
    import math

    import sympy as sp

    from lagcli.targets.c import CPrinter

    x, y = sp.symbols("x y", real=True)
    printer = CPrinter({x: "y[0]", y: "y[1]"})
    cases = [
        (sp.sign(x) / sp.sign(y), lambda a, b: _sign(a) / _sign(b) if b else math.copysign(math.inf, _sign(a))),
        (sp.sign(x - y) * x + sp.Abs(y), lambda a, b: _sign(a - b) * a + abs(b)),
        ((1 + sp.sign(x - y)) / 2 * sp.Max(x, y, 0), lambda a, b: (1 + _sign(a - b)) / 2 * max(a, b, 0)),
        (sp.Min(x, 0) ** 2 + sp.atan2(y, x) + sp.tanh(x), lambda a, b: min(a, 0) ** 2 + math.atan2(b, a) + math.tanh(a)),
    ]
    body = "\n".join(f"double f{k}(const double *y) {{ return {printer.code(e)}; }}" for k, (e, _) in enumerate(cases))
    (tmp_path / "f.c").write_text("#include <math.h>\n" + body + "\n")
    compile_c(["-shared", "-fPIC", "f.c", "-o", "libf.so"], tmp_path)
    lib = ctypes.CDLL(str(tmp_path / "libf.so"))
    points = [(1.0, 0.0), (-0.5, 0.25), (0.3, 0.3), (0.0, -2.0), (2.0, 3.0)]
    for k, (_, expected) in enumerate(cases):
        function = getattr(lib, f"f{k}")
        function.restype = ctypes.c_double
        for a, b in points:
            if k == 0 and a == 0 and b == 0:
                continue
            got = function(doubles([a, b]))
            assert got == pytest.approx(expected(a, b), rel=1e-15, abs=1e-300), (k, a, b)


def _sign(v: float) -> float:
    return (v > 0) - (v < 0)
