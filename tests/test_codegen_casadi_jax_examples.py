"""The worked examples of docs/codegen.md for `--lang casadi` and `--lang jax`, run as
written (each Python block whose first line names it), then checked independently:

- cart-pole swing-up: IPOPT converges on the collocation problem built from the generated
  implicit residual, and the optimised force, replayed open loop by `lagcli simulate` as
  a piecewise-constant input law (`--input`), ends with the pole upright and at rest;
- double pendulum in batches: the vmapped JAX rhs at 10^5 states equals the generated C
  (ctypes) to 1e-10, and the jitted RK4 rollout of 10^4 initial conditions ends where the
  C driver, run from some of them, ends (1e-6).

Skipped, with the reason, when casadi, jax or cc is missing.
"""
from __future__ import annotations

import ctypes
import os
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "codegen.md"


def doc_block(first_line: str) -> str:
    """The Python block of docs/codegen.md that starts with `first_line`."""
    for block in re.findall(r"^```python\n(.*?)^```", DOC.read_text(encoding="utf-8"), re.M | re.S):
        if block.startswith(first_line):
            return block
    raise AssertionError(f"docs/codegen.md has no Python block starting with {first_line!r}")


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """A folder with the bundled specs, current and on sys.path (for the generated modules)."""
    shutil.copytree(ROOT / "specs", tmp_path / "specs")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")   # lagcli
    return tmp_path


def generate(spec: str, lang: str, output: str) -> None:
    from lagcli import commands

    commands.generate(f"specs/{spec}.yaml", lang, output)


def test_cart_pole_swing_up(workdir):
    pytest.importorskip("casadi", reason="casadi is not installed (pip install 'lagcli[casadi]')")
    generate("cart_pole", "casadi", "cart_pole_casadi.py")
    namespace: dict = {}
    exec(compile(doc_block("# cart-pole swing-up"), "docs/codegen.md (swing-up)", "exec"), namespace)
    assert namespace["solution"].stats()["return_status"] == "Solve_Succeeded"
    F = np.asarray(namespace["F"])
    assert F.shape == (50,) and np.abs(F).max() <= 15.0 + 1e-6
    exec(compile(doc_block("# replay of the swing-up"), "docs/codegen.md (replay)", "exec"), namespace)
    t, x, theta, x_dot, theta_dot = namespace["final"][:5]
    assert t == 2.0
    assert abs(theta) < 1e-3 and abs(theta_dot) < 1e-2, namespace["final"]     # upright, at rest
    assert abs(x) < 1e-3 and abs(x_dot) < 1e-2, namespace["final"]             # over the start


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc): no C reference")
def test_double_pendulum_batches_agree_with_c(workdir):
    jax = pytest.importorskip("jax", reason="jax is not installed (pip install 'lagcli[jax]')")
    sys.path.insert(0, str(ROOT / "tests"))
    from test_codegen_c import Built, doubles

    generate("double_pendulum", "jax", "double_pendulum_jax.py")
    namespace: dict = {}
    exec(compile(doc_block("# double pendulum in batches"), "docs/codegen.md (batches)", "exec"), namespace)
    c = Built(workdir / "specs" / "double_pendulum.yaml", workdir / "c")
    rhs, p, out = c.function("rhs"), doubles(np.asarray(namespace["p"])), doubles([0.0] * 4)
    states, derivatives = np.asarray(namespace["states"]), np.asarray(namespace["derivatives"])
    assert states.shape == derivatives.shape == (100_000, 4)
    expected = np.empty_like(states)
    for k, y in enumerate(states):
        assert rhs(ctypes.c_double(0.0), doubles(y), p, out) == 0
        expected[k] = list(out)
    scale = np.abs(expected).max(axis=1, keepdims=True)
    assert (np.abs(derivatives - expected) <= 1e-10 * scale).all()
    initial, final = np.asarray(namespace["initial"]), np.asarray(namespace["final"])
    assert initial.shape == final.shape == (10_000, 4)
    names = ("theta1", "theta2", "theta1_dot", "theta2_dot")
    for k in range(0, 10_000, 2_000):
        done = c.run("--t-end", "1", "--dt", "1", "--rtol", "1e-12", "--atol", "1e-14",
                     *(f"--init={name}={value!r}" for name, value in zip(names, initial[k].tolist())))
        assert done.returncode == 0, done.stderr
        end = [float(v) for v in done.stdout.splitlines()[-1].split(",")[1:5]]
        assert np.abs(final[k] - end).max() <= 1e-6, (k, final[k], end)
    assert jax.config.jax_enable_x64
