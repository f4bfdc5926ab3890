"""`lagcli generate --lang rust`, built with cargo and run, for every bundled spec.

- the crates build with `cargo build --offline` and no warning (all of them in one
  throwaway workspace, so cargo builds them in one go into one target directory);
- the right-hand side (the example binary's `--rhs` mode: dy/dt at states read from
  stdin; tests/data/all_functions.yaml too) agrees with the Derivation, solved independently with mpmath, at seeded random
  states to 1e-12 relative (the reference of test_codegen_python.py);
- the example binary's CSV agrees with `lagcli simulate` to 1e-7, header included;
- the shipped integrator (lagcli/runtime/rust/ode.rs) takes scipy's steps: the same nfev
  as solve_ivp on a test problem; its driver's numbers are lagcli/interface.py's;
- names that are Rust keywords (`type`, `fn`, `self`, `mod`) build; spec text in comments
  and strings is escaped.

Skipped, with the reason, when there is no `cargo`.
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import HEAVY_SPECS, selected_specs
from test_codegen_python import SPEC_FILES, assert_close, random_inputs, reference

ROOT = Path(__file__).resolve().parent.parent
CARGO = shutil.which("cargo") or next((str(p) for p in [Path.home() / ".cargo" / "bin" / "cargo"]
                                       if p.exists()), None)
SIM_T_END = 0.2          # the CSV comparison: short, the example binary is a debug build
CSV_TOL = 1e-7

pytestmark = pytest.mark.skipif(CARGO is None, reason="no cargo (Rust toolchain): the Rust crate is not built")

DEFAULT_SPECS = [p for p in SPEC_FILES if p.stem not in HEAVY_SPECS]
ALL_FUNCTIONS = ROOT / "tests" / "data" / "all_functions.yaml"     # every function of the spec language

KEYWORD_SPEC = """\
name: type
description: 'a spec */ with // awkward ! text "quoted" \\ and a newline
  fn main() {}'
coordinates: [fn]
parameters:
  self: 2.0
  mod: 1.5
  type_: 3.0
  x0: 2.0
potential: self*fn**2/2 + mod*cos(fn) + type_*sign(fn)*fn**2 + max(fn, 0)**3
kinetic: x0*fn_dot**2
initial: {fn: 0.1}
simulate: {t_end: 0.05, dt: 0.01}
"""


# A pushed pendulum whose input has a default that is not 0 (cart_pole's F defaults to 0).
INPUT_SPEC = """\
name: pushed_pendulum
coordinates: [th]
parameters: {m: 1.0, l: 0.5, g: 9.81}
inputs:
  tau: {value: 0.3, description: torque at the pivot}
gravity: [0, -g]
particles:
  P: {mass: m, position: [l*sin(th), -l*cos(th)]}
forces:
  - {at: P, force: [tau*cos(th)/l, tau*sin(th)/l]}
initial: {th: 0.2}
simulate: {t_end: 0.2, dt: 0.05}
"""


def cargo(args, cwd: Path, target: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "CARGO_TARGET_DIR": str(target), "CARGO_TERM_COLOR": "never"}
    env["PATH"] = str(Path(CARGO).parent) + os.pathsep + env.get("PATH", "")
    return subprocess.run([CARGO, *args], cwd=cwd, capture_output=True, text=True, env=env, timeout=1200)


def build_workspace(specs: dict[str, Path], folder: Path) -> dict[str, Path]:
    """Generate a crate per spec under `folder`, build them all; {key: binary path}."""
    from lagcli import commands
    folder.mkdir(parents=True, exist_ok=True)
    members = {}
    for key, spec in specs.items():
        commands.generate(str(spec), "rust", str(folder / key))
        members[key] = re.search(r'^name = "(.*)"', (folder / key / "Cargo.toml").read_text(), re.M).group(1)
    (folder / "Cargo.toml").write_text("[workspace]\nresolver = \"2\"\nmembers = [%s]\n"
                                       % ", ".join(f'"{k}"' for k in specs))
    done = cargo(["build", "--offline", "--workspace"], folder, folder / "target")
    assert done.returncode == 0, done.stderr
    assert "warning" not in done.stderr, done.stderr
    return {key: folder / "target" / "debug" / name for key, name in members.items()}


@pytest.fixture(scope="module")
def binaries(request, tmp_path_factory):
    folder = tmp_path_factory.mktemp("rust_crates")
    specs = {p.stem: p for p in selected_specs(request, DEFAULT_SPECS)}
    keyword = folder / "keyword.yaml"
    keyword.write_text(KEYWORD_SPEC)
    specs["keyword"] = keyword
    pushed = folder / "pushed_pendulum.yaml"
    pushed.write_text(INPUT_SPEC)
    specs["pushed_pendulum"] = pushed
    specs["all_functions"] = ALL_FUNCTIONS
    return build_workspace(specs, folder / "ws")


def run(binary: Path, *args: str, stdin: str = "") -> subprocess.CompletedProcess:
    return subprocess.run([str(binary), *args], input=stdin, capture_output=True, text=True, timeout=300)


@pytest.mark.core_specs
@pytest.mark.parametrize("spec", DEFAULT_SPECS + [ALL_FUNCTIONS], ids=lambda p: p.stem)
def test_rhs_matches_engine(spec, binaries, derived, rng):
    d = derived(str(spec))
    cases = [c for c in random_inputs(d, rng, 6) if c["alpha"] == 0 and c["beta"] == 0]
    for case in cases:        # --rhs reads t, y, p: the inputs (spec `inputs:`) keep their defaults
        case["u"] = [float(u.value) for u in d.model.inputs]
    lines = "".join(" ".join(repr(float(v)) for v in [c["t"], *c["y"], *c["p"]]) + "\n" for c in cases)
    done = run(binaries[spec.stem], "--rhs", stdin=lines)
    assert done.returncode == 0, done.stderr
    rows = done.stdout.splitlines()
    assert len(rows) == len(cases)
    for case, row in zip(cases, rows):
        got = [float(v) for v in row.split()]
        assert got[:d.n] == [float(v) for v in case["y"][d.n:]]
        assert_close(got[d.n:], reference(d, case)["qdd"], f"{spec.stem}: q''")


def parse_csv(text: str):
    lines = text.strip().splitlines()
    return lines[0].split(","), np.array([[float(v) for v in line.split(",")] for line in lines[1:]])


def assert_rows_agree(header, rows, trajectory, tol: float, what: str) -> None:
    assert tuple(header) == trajectory.names, what
    expected = trajectory.data
    assert rows.shape == expected.shape, f"{what}: {rows.shape} rows vs {expected.shape}"
    worst = np.max(np.abs(rows - expected) / (1.0 + np.abs(expected)))
    assert worst <= tol, f"{what}: differs from lagcli simulate by {worst:.3g} (relative to 1 + |value|)"


@pytest.mark.core_specs
@pytest.mark.parametrize("spec", DEFAULT_SPECS, ids=lambda p: p.stem)
def test_example_csv_matches_simulate(spec, binaries):
    import lagcli

    done = run(binaries[spec.stem], "--t-end", str(SIM_T_END))
    assert done.returncode == 0, done.stderr
    header, rows = parse_csv(done.stdout)
    assert_rows_agree(header, rows, lagcli.load(spec).simulate(t_end=SIM_T_END), CSV_TOL, spec.stem)


@pytest.mark.parametrize("sets", [(), ("tau=-1.25",), ("tau=2", "m=1.5")], ids=["default", "set", "set-both"])
def test_example_takes_input_defaults_and_set(sets, binaries, tmp_path):
    """Inputs start at the spec's defaults and `--set NAME=VALUE` holds one, as in
    `lagcli simulate` (the engine's run, an independent integration of the same spec)."""
    import lagcli

    args = [arg for item in sets for arg in ("--set", item)]
    done = run(binaries["pushed_pendulum"], *args)
    assert done.returncode == 0, done.stderr
    header, rows = parse_csv(done.stdout)
    values = dict(item.split("=") for item in sets)
    inputs = {k: float(v) for k, v in values.items() if k == "tau"}
    parameters = {k: float(v) for k, v in values.items() if k != "tau"}
    spec = tmp_path / "pushed_pendulum.yaml"
    spec.write_text(INPUT_SPEC)
    expected = lagcli.load(spec).simulate(inputs=inputs, parameters=parameters)
    assert_rows_agree(header, rows, expected, CSV_TOL, f"pushed pendulum {sets}")
    still = lagcli.load(spec).simulate(inputs={"tau": 0.0}, parameters=parameters)
    assert np.max(np.abs(still.data[-1] - rows[-1])) > 1e-4, "the input must move the pendulum"


def test_keyword_names_and_escaped_text(binaries):
    lib = (binaries["keyword"].parents[2] / "keyword" / "src" / "lib.rs").read_text()
    assert "pub self_: f64" in lib and "pub mod_: f64" in lib and "pub type__: f64" in lib
    assert "pub const fn_: usize = 0;" in lib
    assert 'name = "type_"' in (binaries["keyword"].parents[2] / "keyword" / "Cargo.toml").read_text()
    assert "// a spec */ with // awkward ! text \"quoted\" \\ and a newline fn main() {}" in lib
    done = run(binaries["keyword"])
    assert done.returncode == 0 and done.stdout.startswith("t,fn,fn_dot,energy"), done.stderr


def test_driver_options_and_errors(binaries):
    binary = binaries["cartesian_pendulum"]
    done = run(binary, "--t-end", "0.02", "--dt=0.01", "--set", "g=1.62", "--method", "RK45")
    assert done.returncode == 0 and len(done.stdout.splitlines()) == 4, done.stderr
    bad = run(binary, "--set", "zz=1")
    assert bad.returncode == 2 and "--set zz=1: unknown parameter 'zz'" in bad.stderr
    inconsistent = run(binary, "--init", "x=0.5", "--t-end", "0.01")
    assert inconsistent.returncode == 0 and "violates the constraints" in inconsistent.stderr


def test_g17_matches_printf(tmp_path):
    """The driver's %.17g: a tiny program against Python's '%.17g' (C's printf)."""
    values = [0.0, -0.0, 1.0, 0.1, -2.5e-5, 1e-4, 123456789012345678.0, 1e17, 9.999999999999999e16,
              5e-324, 1.7976931348623157e308, float("inf"), float("-inf"), float("nan"), 0.029999999999999999]
    crate = tmp_path / "g"
    (crate / "src").mkdir(parents=True)
    (crate / "Cargo.toml").write_text('[package]\nname = "g"\nversion = "0.1.0"\nedition = "2021"\n')
    shutil.copy(ROOT / "lagcli" / "runtime" / "rust" / "driver.rs", crate / "src" / "driver.rs")
    shutil.copy(ROOT / "lagcli" / "runtime" / "rust" / "ode.rs", crate / "src" / "ode.rs")
    (crate / "src" / "main.rs").write_text(
        "#![allow(dead_code)]\nmod driver;\nmod ode;\nfn main() {\n"
        + "".join(f"    println!(\"{{}}\", driver::g17({v!r}_f64));\n" for v in values if np.isfinite(v))
        + "    println!(\"{}\", driver::g17(f64::INFINITY));\n    println!(\"{}\", driver::g17(f64::NEG_INFINITY));\n"
        + "    println!(\"{}\", driver::g17(f64::NAN));\n}\n")
    done = cargo(["run", "--offline", "-q"], crate, tmp_path / "target")
    assert done.returncode == 0, done.stderr
    expected = ["%.17g" % v for v in values if np.isfinite(v)] + ["inf", "-inf", "nan"]
    assert done.stdout.splitlines() == expected


def test_integrator_takes_scipys_steps(tmp_path):
    """ode.rs on a Van der Pol oscillator: the same nfev as solve_ivp and the same values
    at the output times (to rounding), for both methods."""
    from scipy.integrate import solve_ivp

    crate = tmp_path / "vdp"
    (crate / "src").mkdir(parents=True)
    (crate / "Cargo.toml").write_text('[package]\nname = "vdp"\nversion = "0.1.0"\nedition = "2021"\n')
    shutil.copy(ROOT / "lagcli" / "runtime" / "rust" / "ode.rs", crate / "src" / "ode.rs")
    (crate / "src" / "main.rs").write_text("""\
mod ode;
fn main() {
    let times: Vec<f64> = (1..=20).map(|k| k as f64 * 0.25).collect();
    for name in ["RK45", "DOP853"] {
        let mut last = 0.0;
        let stats = ode::integrate(ode::Method::from_name(name).unwrap(),
            |_t, y: &[f64], d: &mut [f64]| { d[0] = y[1]; d[1] = 2.0 * (1.0 - y[0] * y[0]) * y[1] - y[0]; true },
            |_t, y: &[f64]| { last = y[0]; true }, 0.0, &[2.0, 0.0], 5.0, &times, 1e-8, 1e-10, f64::INFINITY)
            .expect("integrates");
        println!("{} {} {:e}", name, stats.nfev, last);
        let _ = ode::OdeError::Args.message();
    }
}
""")
    done = cargo(["run", "--offline", "-q"], crate, tmp_path / "target")
    assert done.returncode == 0, done.stderr
    for line in done.stdout.splitlines():
        method, nfev, last = line.split()
        ref = solve_ivp(lambda t, y: [y[1], 2.0 * (1 - y[0] ** 2) * y[1] - y[0]], (0, 5), [2.0, 0.0],
                        method=method, t_eval=np.arange(1, 21) * 0.25, rtol=1e-8, atol=1e-10)
        assert int(nfev) == ref.nfev, method
        assert abs(float(last) - ref.y[0, -1]) <= 1e-12, method


def test_driver_numbers_are_lagclis():
    from lagcli import interface
    from lagcli.runtime import run_rules

    text = (ROOT / "lagcli" / "runtime" / "rust" / "driver.rs").read_text()
    for name, value in (("OUTPUT_SLACK", run_rules.OUTPUT_SLACK), ("END_TOLERANCE", run_rules.END_TOLERANCE),
                        ("CONSTRAINT_TOLERANCE", interface.CONSTRAINT_TOLERANCE)):
        assert float(re.search(rf"const {name}: f64 = ([0-9.e-]+);", text).group(1)) == value
    lib = (ROOT / "templates" / "rust" / "lib.rs.jinja").read_text()
    assert "BAUMGARTE" in lib      # the gains come from the interface (interface.DEFAULT_BAUMGARTE)


@pytest.mark.slow
@pytest.mark.timeout(600)       # the bicycle: ~5 s to derive, generate and run (a margin for a loaded machine)
@pytest.mark.parametrize("spec", [p for p in SPEC_FILES if p.stem in HEAVY_SPECS], ids=lambda p: p.stem)
def test_heavy_spec_builds_and_matches(spec, tmp_path, derived, rng):
    import lagcli

    binary = build_workspace({spec.stem: spec}, tmp_path / "ws")[spec.stem]
    d = derived(spec.stem)
    case = [c for c in random_inputs(d, rng, 2) if c["alpha"] == 0][0]
    done = run(binary, "--rhs", stdin=" ".join(repr(float(v)) for v in [case["t"], *case["y"], *case["p"]]))
    assert done.returncode == 0, done.stderr
    assert_close([float(v) for v in done.stdout.split()][d.n:], reference(d, case)["qdd"], spec.stem)
    done = run(binary, "--t-end", "0.05")
    header, rows = parse_csv(done.stdout)
    assert_rows_agree(header, rows, lagcli.load(spec).simulate(t_end=0.05), CSV_TOL, spec.stem)
