"""What a `derive` imports: sympy's `Add` imports sympy.tensor.tensor (and with it
sympy.combinatorics, ~0.04 s of a 2 s command) the first time it flattens a sum. The
derivation and its report build sums with `lagcli.model.sums.total` and products with
`lagcli.model.products.product`, which give sympy's very expressions (tests/test_sums_and_ordering.py,
tests/test_products.py) without it: a chain's or a bundled pendulum's `derive` never loads it."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest

from conftest import ROOT, SPECS, nlink_spec

SCRIPT = """
import sys
from lagcli.cli import cli
try:
    cli(["derive", "--json", sys.argv[1]])
except SystemExit as exc:
    assert not exc.code, exc.code
print("sympy.tensor.tensor" in sys.modules, file=sys.stderr)
"""


@pytest.mark.parametrize("spec", ["nlink", "double_pendulum", "cart_pole"])
def test_derive_never_imports_sympys_tensor_module(tmp_path, spec):
    path = nlink_spec(tmp_path, 10) if spec == "nlink" else SPECS / f"{spec}.yaml"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "-c", SCRIPT, str(path)], env=env, capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("{")
    assert run.stderr.split()[-1] == "False"


UNUSED_BY_A_YAML_DERIVE = ("tomllib", "html", "importlib.resources", "sympy.printing.c", "sympy.codegen.ast")

IMPORTS_SCRIPT = """
import sys
from lagcli.cli import cli
try:
    cli(["derive", "--json", sys.argv[1]])
except SystemExit as exc:
    assert not exc.code, exc.code
print(sorted(name for name in sys.argv[2:] if name in sys.modules), file=sys.stderr)
"""


def test_derive_of_a_yaml_spec_imports_only_what_it_uses(tmp_path):
    """The TOML reader (tomllib), the page's HTML escapes, the runtime's shipped files
    (importlib.resources) and sympy's C printers are imported where they are used, not by
    every command's start (bench/README.md, "Imports (session 16)")."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run([sys.executable, "-c", IMPORTS_SCRIPT, str(SPECS / "double_pendulum.yaml"),
                          *UNUSED_BY_A_YAML_DERIVE], env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stderr.splitlines()[-1] == "[]"
