"""Golden files of the generated Python, C, MATLAB/Octave, Rust, CasADi and JAX, and their
determinism.

The generated text of one unconstrained (double_pendulum) and one constrained spec
(ex6_9_two_wheels_axle) is compared byte for byte with tests/golden/<lang>/ (a file
whose name does not start with the spec's, such as the crate's Cargo.toml, under
tests/golden/<lang>/<spec>/). On a
difference the test fails with a unified diff; after checking that the change is
intended, update the files with

    LAGCLI_UPDATE_GOLDEN=1 pytest tests/test_golden_codegen.py

Determinism: a second generation in another process, with another hash seed (sympy's
set iteration order depends on it), gives the same bytes.
"""
from __future__ import annotations

import difflib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = Path(__file__).resolve().parent / "golden"
SPECS = ["double_pendulum", "ex6_9_two_wheels_axle"]
LANGS = ["python", "c", "octave", "rust", "casadi", "jax"]
UPDATE = os.environ.get("LAGCLI_UPDATE_GOLDEN") == "1"


def generate(spec: str, lang: str) -> dict[str, str]:
    from lagcli.derive.pipeline import derive_file
    from lagcli.targets import generate as emit

    return emit(derive_file(ROOT / "specs" / f"{spec}.yaml"), lang)


def compare_or_update(path: Path, text: str) -> None:
    if UPDATE:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
        return
    assert path.exists(), f"missing golden file {path}; create it with LAGCLI_UPDATE_GOLDEN=1"
    expected = path.read_text()
    if text != expected:
        diff = "".join(difflib.unified_diff(expected.splitlines(True), text.splitlines(True),
                                            f"{path} (golden)", f"{path.name} (generated)"))
        pytest.fail(f"generated code differs from {path} (LAGCLI_UPDATE_GOLDEN=1 to accept):\n{diff}")


@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("spec", SPECS)
def test_golden(spec, lang):
    from lagcli.targets.octave import FUNCTIONS
    from lagcli.runtime import c_runtime_files, rust_runtime_files

    files = generate(spec, lang)
    expected = {"python": [f"{spec}.py"], "casadi": [f"{spec}.py"], "jax": [f"{spec}.py"], "c": [f"{spec}.h", f"{spec}.c", f"{spec}_main.c"],
                "octave": [f"{spec}_{f}.m" for f in FUNCTIONS + ("run",)],
                "rust": ["Cargo.toml", "src/lib.rs", "src/main.rs"]}[lang]
    runtime = {"c": c_runtime_files(),
               "rust": {f"src/{name}": text for name, text in rust_runtime_files().items()}}.get(lang, {})
    assert sorted(files) == sorted(expected + list(runtime))
    for name in runtime:       # the shipped sources, unchanged: not golden files of their own
        assert files.pop(name) == (ROOT / "lagcli" / "runtime" / lang / Path(name).name).read_text()
    for name, text in files.items():
        compare_or_update(GOLDEN / lang / (name if name.startswith(spec) else f"{spec}/{name}"), text)


@pytest.mark.parametrize("spec", SPECS)
def test_deterministic_across_processes(spec):
    here = {lang: generate(spec, lang) for lang in LANGS}
    script = ("import json, sys; sys.path.insert(0, sys.argv[1]); from tests.test_golden_codegen import generate; "
              f"print(json.dumps({{lang: generate(sys.argv[2], lang) for lang in {LANGS!r}}}))")
    env = {**os.environ, "PYTHONHASHSEED": "12345", "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-c", script, str(ROOT), spec], capture_output=True, text=True,
                          env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout) == here


def test_header_names_spec_and_version_without_dates():
    from lagcli import __version__

    text = generate("double_pendulum", "python")["double_pendulum.py"]
    head = "".join(text.splitlines(True)[:3])
    assert f"lagcli {__version__}" in head and "double_pendulum.yaml" in head
    c = generate("double_pendulum", "c")["double_pendulum.h"]
    assert f"lagcli {__version__}" in c.splitlines()[0] and "double_pendulum.yaml" in c.splitlines()[0]
