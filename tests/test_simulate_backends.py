"""The two backends of `lagcli simulate`, and the C backend's cache.

- Python (scipy) and C (the generated driver) agree column by column on every
  bundled spec: both run the same explicit Runge-Kutta pair with scipy's step
  control, so the agreement is far inside the 1e-7 checked here.
- A warm re-run of an unchanged spec imports neither sympy nor numpy, and gives
  the same bytes as the cold run.
- The cache is keyed by the spec's bytes; a changed spec gets a new driver.
- A failing or missing compiler is a run-time error (exit status 1).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.run.rows import parse_csv

from conftest import ROOT, SPECS

needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
SPEC_FILES = sorted(SPECS.glob("*.yaml"))


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def invoke(*args):
    return CliRunner().invoke(cli, ["simulate", *map(str, args)])


@pytest.mark.core_specs
@needs_cc
@pytest.mark.parametrize("spec", SPEC_FILES, ids=[p.stem for p in SPEC_FILES])
def test_python_and_c_backends_agree(spec):
    """Over the spec's own `simulate:` block (t_end, dt, method, tolerances): with the
    Baumgarte step cap (docs/simulate.md) even the constrained runs agree to ~1e-11;
    without it disc_on_incline differed by 3e-6 (residual 1.5e-6)."""
    from lagcli.derive.pipeline import load_model
    from lagcli.runtime.run_rules import output_times

    settings = load_model(str(spec)).settings
    results = {b: invoke(spec, "--backend", b) for b in ("python", "c")}
    for backend, result in results.items():
        assert result.exit_code == 0, f"{backend}: {result.stderr}"
    (hp, rp), (hc, rc) = (parse_csv(results[b].stdout) for b in ("python", "c"))
    assert hp == hc
    assert results["python"].stderr == results["c"].stderr          # the same notes, if any
    p, c = np.array(rp), np.array(rc)
    assert p.shape == c.shape and p.shape[0] == len(output_times(settings.t_end, settings.dt))
    assert p[-1, 0] == settings.t_end
    for k, name in enumerate(hp):
        worst = np.max(np.abs(p[:, k] - c[:, k]) / np.maximum(1.0, np.abs(p[:, k])))
        assert worst < 1e-7, f"{spec.name}: column {name} differs by {worst:.3g}"
    if "constraint_residual" in hp:
        assert np.max(p[:, hp.index("constraint_residual")]) < 1e-8, spec.name


WARM_PROBE = """
import atexit
import sys
from lagcli.cli import main


def heavy_modules():      # an exit handler: `main` ends the process itself (`cli._end`)
    heavy = sorted({m.split(".")[0] for m in sys.modules} & {"sympy", "numpy", "scipy"})
    print("heavy modules:", ",".join(heavy) or "none", file=sys.stderr)


atexit.register(heavy_modules)
sys.argv = ["lagcli", "simulate", *sys.argv[1:]]
main()
"""


def probe(tmp_path: Path, *args) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp_path / "cache")}
    return subprocess.run([sys.executable, "-c", WARM_PROBE, *map(str, args)], capture_output=True,
                          text=True, env=env, timeout=600)


@needs_cc
@pytest.mark.parametrize("spec, extra", [
    ("double_pendulum", ("--set", "m2=2", "--init", "theta1=0.3")),
    ("cartesian_pendulum", ("--init", "x=0.6", "--init", "y=-0.8", "--set", "g=1.5")),
])
def test_warm_rerun_imports_no_sympy(tmp_path, spec, extra):
    spec = SPECS / f"{spec}.yaml"
    args = (spec, "--t-end", "1", "--dt", "0.1")
    cold = probe(tmp_path, *args)
    assert cold.returncode == 0, cold.stderr
    assert "heavy modules: none" not in cold.stderr and "sympy" in cold.stderr
    warm = probe(tmp_path, *args)
    assert warm.returncode == 0, warm.stderr
    assert "heavy modules: none" in warm.stderr
    assert warm.stdout == cold.stdout
    overridden = probe(tmp_path, *args, *extra)        # run-time values: the same binary
    assert overridden.returncode == 0 and "heavy modules: none" in overridden.stderr
    assert overridden.stdout != cold.stdout
    assert len(list((tmp_path / "cache" / "lagcli").iterdir())) == 1


@needs_cc
def test_warm_rerun_with_an_inconsistent_state_still_repairs_it(tmp_path):
    spec = SPECS / "cartesian_pendulum.yaml"
    assert probe(tmp_path, spec, "--t-end", "0").returncode == 0
    warm = probe(tmp_path, spec, "--t-end", "0", "--init", "x=0.5")
    assert warm.returncode == 0, warm.stderr
    assert "solved for dependent coordinates: y = -0.866025403784" in warm.stderr
    assert "sympy" in warm.stderr                       # the repair needed the engine
    header, rows = parse_csv(warm.stdout)
    assert rows[0][header.index("constraint_residual")] < 1e-12


@needs_cc
def test_changed_spec_gets_a_new_driver(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    spec = tmp_path / "osc.yaml"
    spec.write_text("coordinates: [x]\nparameters: {k: 1.0}\nkinetic: x_dot**2/2\n"
                    "potential: k*x**2/2\ninitial: {x: 1.0}\n")
    first = invoke(spec, "--t-end", "3.141592653589793", "--dt", "3.141592653589793")
    assert first.exit_code == 0, first.stderr
    assert parse_csv(first.stdout)[1][-1][1] == pytest.approx(-1.0, abs=1e-8)
    spec.write_text(spec.read_text().replace("k*x**2/2", "4*k*x**2/2"))   # omega = 2
    second = invoke(spec, "--t-end", "3.141592653589793", "--dt", "3.141592653589793")
    assert parse_csv(second.stdout)[1][-1][1] == pytest.approx(1.0, abs=1e-8)
    assert len(list((tmp_path / "cache" / "lagcli").iterdir())) == 2


def _fake_compiler(folder: Path, script: str) -> None:
    folder.mkdir()
    cc = folder / "cc"
    cc.write_text("#!/bin/sh\n" + script)
    cc.chmod(0o755)


def test_failing_compiler_exits_1(tmp_path, monkeypatch):
    _fake_compiler(tmp_path / "bin", 'echo "fatal error: no luck" >&2\nexit 1\n')
    monkeypatch.setenv("PATH", str(tmp_path / "bin"))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    result = invoke(SPECS / "double_pendulum.yaml", "--t-end", "0.1", "--backend", "c")
    assert result.exit_code == 1
    assert "the C compiler failed" in result.stderr and "no luck" in result.stderr


def test_missing_compiler(tmp_path, monkeypatch):
    (tmp_path / "empty").mkdir()
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    result = invoke(SPECS / "double_pendulum.yaml", "--t-end", "0.1", "--backend", "c")
    assert result.exit_code == 1 and "'cc' was not found" in result.stderr
    fallback = invoke(SPECS / "double_pendulum.yaml", "--t-end", "0.1")     # default: python
    assert fallback.exit_code == 0, fallback.stderr
