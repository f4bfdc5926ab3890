"""The rules of a run are written once per language: in Python, lagcli/runtime/run_rules.py
is what lagcli runs (lagcli.interface) and what the generated module carries, verbatim."""
from __future__ import annotations

import ast
import json
import math
import subprocess
import sys

import pytest

import lagcli
from lagcli.runtime import run_rules as numerics
from lagcli.runtime import python_run_rules

from conftest import SPECS


@pytest.fixture(scope="module")
def module_text():
    return lagcli.load(SPECS / "cartesian_pendulum.yaml").generate("python")["cartesian_pendulum.py"]


def test_the_generated_module_carries_the_rules_verbatim(module_text):
    assert python_run_rules() in module_text
    assert "def output_times" in python_run_rules() and "def max_step" in python_run_rules()
    assert module_text.count("def output_times") == 1 and module_text.count("def max_step") == 1


def test_the_rules_need_only_the_standard_library():
    tree = ast.parse(python_run_rules())
    imported = {alias.name for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))
                for alias in node.names}
    assert imported == {"math"}


def test_the_module_runs_the_same_rules_as_lagcli(module_text, tmp_path):
    """Edge cases of the output times (t_end a float multiple of dt, just short of one,
    not one) and of the step cap, in a fresh interpreter that cannot import lagcli."""
    path = tmp_path / "model.py"
    path.write_text(module_text)
    cases = [(1.0, 0.1), (0.3, 0.1), (1.0, 0.3), (2.5e-9, 1e-9), (0.0, 0.5)]
    caps = [("DOP853", 10.0, 10.0), ("RK45", 10.0, 1.0), ("Radau", 10.0, 10.0), ("RK45", 0.0, 0.0)]
    script = ("import json, sys\n"
              "sys.modules['lagcli'] = None          # the module must not need lagcli\n"
              f"sys.path.insert(0, {str(tmp_path)!r})\n"
              "import model\n"
              f"print(json.dumps([model.output_times(*c) for c in {cases!r}]))\n"
              f"print(json.dumps([model.max_step(*c, True) for c in {caps!r}]))\n")
    done = subprocess.run([sys.executable, "-I", "-c", script], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    times, steps = (json.loads(line) for line in done.stdout.splitlines())
    assert times == [numerics.output_times(*c) for c in cases]
    assert steps == [numerics.max_step(*c, True) for c in caps]
    assert times[0][-1] == 1.0 and len(times[0]) == 11                 # 0, 0.1, ..., 1.0
    assert times[2] == [0.0, 0.3, 0.6, 0.8999999999999999, 1.0]        # t_end appended
    assert steps[0] == pytest.approx(0.1) and steps[2] == math.inf      # 1/alpha; implicit: no cap
