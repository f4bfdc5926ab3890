"""A warm `lagcli simulate` (the cache holds the spec's compiled driver) reads the
Layout from meta.json and runs the driver without importing sympy or numpy."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, SPECS

SCRIPT = """
import sys
from lagcli.cli import cli
try:
    cli(["simulate", sys.argv[1], "--t-end", "0.05", "--set", "m1=2", "-o", sys.argv[2]])
except SystemExit as exc:
    assert not exc.code, exc.code
print("sympy" in sys.modules, "numpy" in sys.modules)
"""


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_a_warm_run_imports_neither_sympy_nor_numpy(tmp_path):
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    spec, out = str(SPECS / "double_pendulum.yaml"), str(tmp_path / "run.csv")
    runs = [subprocess.run([sys.executable, "-c", SCRIPT, spec, out], env=env, capture_output=True,
                           text=True, timeout=600) for _ in range(2)]      # cold, then warm
    assert all(run.returncode == 0 for run in runs), runs[-1].stderr
    assert runs[0].stdout.split()[0] == "True"          # the cold run derives (sympy)
    assert runs[1].stdout.split() == ["False", "False"]
    with open(out) as csv:
        assert csv.readline().startswith("t,theta1,theta2,theta1_dot")


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
@pytest.mark.parametrize("plot", [False, True], ids=["csv", "csv and --plot"])
def test_python_lists_no_sympy_module_imported_by_a_warm_simulate(tmp_path, plot):
    """As a user would check it: `PYTHONPROFILEIMPORTTIME=1 lagcli simulate ...` on a warm
    cache lists every module imported; none is sympy's, with or without --plot (the
    angles and units of the plot come from the cached run interface, not the model)."""
    pytest.importorskip("matplotlib") if plot else None
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    command = [sys.executable, "-m", "lagcli", "simulate", str(SPECS / "double_pendulum.yaml"),
               "-o", str(tmp_path / "x.csv"), *(["--plot", str(tmp_path / "x.png")] if plot else [])]
    subprocess.run(command, env=env, check=True, capture_output=True, timeout=600)    # fills the cache
    warm = subprocess.run(command, env={**env, "PYTHONPROFILEIMPORTTIME": "1"}, capture_output=True,
                          text=True, timeout=600)
    assert warm.returncode == 0, warm.stderr
    imported = [line.rsplit("|", 1)[-1].strip() for line in warm.stderr.splitlines() if "import time:" in line]
    assert "lagcli.run.c_backend" in imported                  # the listing is there
    assert not [m for m in imported if m.split(".")[0] == "sympy"]


def test_generate_of_an_unconstrained_system_imports_neither_numpy_nor_scipy():
    """The consistent initial state's numeric solve (lagcli/analysis/constraint_solve.py)
    is imported only for a system with constraint rows: ~0.15 s of every `generate`."""
    code = ("import sys, lagcli; lagcli.load(sys.argv[1]).generate('c'); "
            "print('numpy' in sys.modules, 'scipy' in sys.modules)")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "-c", code, str(SPECS / "double_pendulum.yaml")], env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["False", "False"]
