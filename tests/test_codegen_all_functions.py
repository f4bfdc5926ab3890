"""Code generation and `simulate` on a spec that calls every function of the language.

tests/data/all_functions.yaml uses sin cos tan asin acos atan atan2 sinh cosh tanh exp
log sqrt abs sign min max diff; its equations contain sign, Max, Min, Abs, atan2, tanh
and the a.e. derivative (1 + sign(x - y))/2 of max. sympy's trigsimp used to grind
forever on such expressions in the tidy step of code generation, so:

- `generate --lang python` and `--lang c` finish (run in a subprocess with a generous
  timeout, so a regression fails instead of hanging the suite; no timing is asserted);
- the generated module (without sympy) and the C library (strict flags, ctypes) agree
  with the engine's Derivation evaluated with mpmath (test_codegen_python.reference)
  at states on both sides of every kink: x < 0 and x > 0, x < y and x > y, x = y,
  x_dot < 0, = 0 and > 0;
- a cold `lagcli simulate` on both backends finishes and follows an independent
  integration: scipy's DOP853 on M q'' = F lambdified from the Derivation.
"""
from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner

from test_codegen_python import ROOT, compare, run_module

SPEC = Path(__file__).resolve().parent / "data" / "all_functions.yaml"
HANG_GUARD_SECONDS = 600       # it takes seconds; before the fix it never finished
CC = shutil.which("cc")

GENERATE = r"""
import sys, time
from lagcli import commands
start = time.perf_counter()
commands.generate(sys.argv[1], "python", sys.argv[2])
commands.generate(sys.argv[1], "c", sys.argv[3])
print(time.perf_counter() - start)
"""

# (x, y, x_dot, y_dot, t): every branch of abs, sign, min and max, and the kinks themselves
STATES = [
    (0.5, -0.2, 0.1, 0.0, 0.0),
    (-0.7, 0.4, -0.3, 0.8, 0.7),
    (0.3, 0.9, 0.0, -0.5, 1.3),
    (-0.2, -0.6, 1.2, -1.1, 2.1),
    (0.4, 0.4, -0.9, 0.2, 0.4),           # x = y: max's a.e. derivative (1 + sign 0)/2
    (0.0, 0.3, 0.5, 0.1, 0.9),            # x = 0: abs, min(x, 0) and sign(x)
]


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    folder = tmp_path_factory.mktemp("all_functions")
    done = subprocess.run([sys.executable, "-c", GENERATE, str(SPEC), str(folder / "module.py"),
                           str(folder / "c")], capture_output=True, text=True, timeout=HANG_GUARD_SECONDS,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 0, done.stderr
    return folder, float(done.stdout.split()[-1])


@pytest.fixture(scope="module")
def derivation():
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive

    return derive(load_model(str(SPEC)))


def cases(d) -> list[dict]:
    p = [v.value for v in d.model.parameters]
    return [{"t": t, "y": [x, y, xd, yd], "p": p, "alpha": 0.0, "beta": 0.0}
            for x, y, xd, yd, t in STATES]


def test_generation_finishes(generated):
    folder, _ = generated
    assert (folder / "module.py").is_file() and (folder / "c" / "all_functions.c").is_file()


def test_every_function_is_called_in_the_generated_code(generated):
    folder, _ = generated
    python = (folder / "module.py").read_text()
    c = (folder / "c" / "all_functions.c").read_text()
    for name in ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
                 "exp", "log", "sqrt"):
        assert f"{name}(" in python and f"{name}(" in c, name
    assert "fabs(" in c and "fmax(" in c and "fmin(" in c
    assert "max(" in python and "min(" in python and "abs(" in python
    for text in (python, c):
        assert "Heaviside" not in text and "DiracDelta" not in text and "copysign" not in text


def test_python_module_agrees_with_engine(generated, derivation):
    folder, _ = generated
    states = cases(derivation)
    result = run_module(folder / "module.py", states)
    for i, (case, got) in enumerate(zip(states, result["cases"])):
        compare(derivation, case, got, f"all_functions state {i}")


@pytest.mark.skipif(CC is None, reason="no C compiler (cc)")
def test_c_library_agrees_with_engine(generated, derivation):
    from test_codegen_c import CFLAGS, RUNTIME_SOURCES, call

    folder, _ = generated
    c_dir = folder / "c"
    done = subprocess.run([CC, *CFLAGS, "all_functions.c", "all_functions_main.c", *RUNTIME_SOURCES,
                           "-o", "drv", "-lm"],
                          cwd=c_dir, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    done = subprocess.run([CC, *CFLAGS, "-shared", "-fPIC", "all_functions.c", "-o", "lib.so", "-lm"],
                          cwd=c_dir, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr

    library = _Library(ctypes.CDLL(str(c_dir / "lib.so")))
    for i, case in enumerate(cases(derivation)):
        compare(derivation, case, call(library, derivation, case), f"all_functions (C) state {i}")


class _Library:
    """The part of test_codegen_c.Built that its `call` uses."""

    def __init__(self, lib):
        self.lib = lib

    def function(self, suffix: str):
        return getattr(self.lib, f"all_functions_{suffix}")

    def strings(self, suffix: str) -> list[str]:
        assert suffix == "invariant_names"
        return ["energy"]


def independent_trajectory(d, times, rtol, atol) -> np.ndarray:
    """scipy DOP853 on M q'' = F, both lambdified from the Derivation (no lagcli emitter)."""
    from scipy.integrate import solve_ivp

    model = d.model
    subs = {p.symbol: p.value for p in model.parameters}
    args = [model.t, *model.q, *model.qd]
    M = sp.lambdify(args, sp.Matrix(d.mass_matrix).xreplace(subs), "numpy")
    F = sp.lambdify(args, sp.Matrix(d.forcing).xreplace(subs), "numpy")
    n = len(model.q)

    def rhs(t, y):
        qdd = np.linalg.solve(np.asarray(M(t, *y), float), np.asarray(F(t, *y), float).ravel())
        return np.concatenate([y[n:], qdd])

    y0 = [model.initial.get(s.name, 0.0) for s in model.q + model.qd]
    sol = solve_ivp(rhs, (0.0, times[-1]), y0, method="DOP853", t_eval=times, rtol=rtol, atol=atol)
    assert sol.success
    return sol.y.T


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=pytest.mark.skipif(
    CC is None, reason="no C compiler (cc)"))])
def test_cold_simulate_finishes_and_follows_the_equations(backend, derivation, tmp_path, monkeypatch):
    from lagcli.cli import cli
    from lagcli.run.rows import parse_csv

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))       # cold: nothing cached
    result = CliRunner().invoke(cli, ["simulate", str(SPEC), "--backend", backend,
                                      "--rtol", "1e-11", "--atol", "1e-13"])
    assert result.exit_code == 0, result.stderr
    header, rows = parse_csv(result.stdout)
    rows = np.array(rows)
    assert header == ["t", "x", "y", "x_dot", "y_dot", "energy"] and rows.shape == (21, 6)
    expected = independent_trajectory(derivation, rows[:, 0], 1e-11, 1e-13)
    assert np.max(np.abs(rows[:, 1:5] - expected)) < 1e-7
