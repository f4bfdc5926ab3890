"""`lagcli generate --lang casadi` and `--lang jax`, run against the generated C, for every
bundled spec (the bicycles with `-m slow`) and tests/data/all_functions.yaml.

The reference is the generated C model compiled with the contract's strict flags and
called through ctypes (tests/test_codegen_c.py, itself checked against mpmath); without
`cc` it is the generated Python module (checked against mpmath by
tests/test_codegen_python.py), and the test says so in its output. At seeded random
states (random parameters, not on the constraints) and at consistent states (rows of
the C driver's trajectory at the spec's parameters):

- CasADi `rhs`, `multipliers`, `mass_matrix`, `forcing`, `invariants`, `energy` and
  JAX's (float64) equal the reference to 1e-10 relative (norm-wise);
- the implicit residual M q'' - F - A^T lambda and the acceleration rows A q'' - b are
  zero to 1e-10 (relative to the size of the terms) at q'' and lambda of the reference,
  and the position and velocity rows give the reference's constraint_residual;
- float32 JAX agrees to 1e-4 relative on the small specs.

Skipped, with the reason, when casadi or jax is not importable.
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from test_codegen_python import SPEC_FILES, assert_close, random_inputs, spec_id

ROOT = Path(__file__).resolve().parent.parent
RTOL = 1e-10
BICYCLES = ("benchmark_bicycle", "benchmark_bicycle_frames")
SMALL = ("double_pendulum", "cart_pole", "bead_on_spinning_hoop", "cartesian_pendulum", "atwood",
         "spherical_pendulum")
CONSISTENT_TIMES = ("0.125", "0.25", "0.375")   # exact in binary: k dt never passes t_end
ALL_FUNCTIONS = ROOT / "tests" / "data" / "all_functions.yaml"     # every function of the spec language
SPECS = [pytest.param(spec, marks=pytest.mark.slow) if spec.stem in BICYCLES else spec
         for spec in SPEC_FILES + [ALL_FUNCTIONS]]


def load_module(path: Path, name: str):
    """Import the generated file at `path` as module `name` (not on sys.path)."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def casadi():
    return pytest.importorskip("casadi", reason="casadi is not installed (pip install 'lagcli[casadi]')")


@pytest.fixture(scope="module")
def jax():
    jax = pytest.importorskip("jax", reason="jax is not installed (pip install 'lagcli[jax]')")
    jax.config.update("jax_enable_x64", True)     # float32 arrays stay float32 (test_float32)
    return jax


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """`get(spec, lang)` -> the generated module, made and imported once per spec."""
    from lagcli import commands

    folder = tmp_path_factory.mktemp("casadi_jax")
    made = {}

    def get(spec: Path, lang: str):
        if (spec, lang) not in made:
            path = folder / f"{spec.stem}_{lang}.py"
            commands.generate(str(spec), lang, str(path))
            made[spec, lang] = load_module(path, f"generated_{spec.stem}_{lang}")
        return made[spec, lang]

    return get


class Reference:
    """q'', lambda, M, F and the invariants of the generated C (or, without cc, Python)."""

    def __init__(self, spec: Path, d, folder: Path, python_module):
        self.d = d
        self.c = None
        if shutil.which("cc") is not None:
            from test_codegen_c import Built
            self.c = Built(spec, folder)
        else:
            warnings.warn(f"{spec.stem}: no C compiler (cc): compared with the generated Python module")
        self.python = python_module

    @property
    def source(self) -> str:
        return "the generated C" if self.c else "the generated Python module (no cc)"

    def evaluate(self, case: dict) -> dict:
        if self.c is not None:
            from test_codegen_c import call
            got = call(self.c, self.d, case)
            return {"rhs": got["rhs"], "lam": got["lam"], "qdd": got["qdd"], "M": got["M"], "F": got["F"],
                    "inv": got["inv"]}
        m, u = self.python, ((case["u"],) if self.d.model.inputs else ())
        qdd, lam = m.accelerations(case["t"], case["y"], case["p"], 0.0, 0.0, *u)
        return {"rhs": list(m.rhs(case["t"], case["y"], case["p"], *u)), "lam": list(lam), "qdd": list(qdd),
                "M": m.mass_matrix(case["t"], case["y"], case["p"]).ravel().tolist(),
                "F": list(m.forcing(case["t"], case["y"], case["p"], *u)),
                "inv": m.invariants(case["t"], case["y"], case["p"])}

    def consistent_cases(self) -> list[dict]:
        """States of the spec's own trajectory (on the constraints), at its parameters."""
        model = self.d.model
        p = [float(par.value) for par in model.parameters]
        u = [float(x.value) for x in model.inputs]
        if self.c is not None:
            done = self.c.run("--t-end", CONSISTENT_TIMES[-1], "--dt", CONSISTENT_TIMES[0])
            assert done.returncode == 0, done.stderr
            rows = np.array([[float(v) for v in line.split(",")] for line in done.stdout.splitlines()[1:]])
        else:
            rows = self.python.simulate(t_end=float(CONSISTENT_TIMES[-1]), dt=float(CONSISTENT_TIMES[0]))[1]
        n = self.d.n
        return [{"t": float(row[0]), "y": [float(v) for v in row[1:1 + 2 * n]], "p": p, "u": u,
                 "alpha": 0.0, "beta": 0.0} for row in rows[1:]]


@pytest.fixture(scope="module")
def reference(tmp_path_factory, derived):
    from lagcli import commands

    made = {}

    def get(spec: Path) -> Reference:
        if spec not in made:
            folder = tmp_path_factory.mktemp(f"ref_{spec.stem}")
            commands.generate(str(spec), "python", str(folder / "reference.py"))
            module = load_module(folder / "reference.py", f"reference_{spec.stem}")
            made[spec] = Reference(spec, derived(str(spec)), folder, module)
        return made[spec]

    return get


def cases_of(d, ref: Reference, rng) -> list[dict]:
    """Two random exact cases (random parameters, off the constraints) and the consistent ones."""
    exact = [case for case in random_inputs(d, rng) if case["alpha"] == 0.0]
    return exact + ref.consistent_cases()


def inputs_of(case: dict) -> list[float]:
    return case["u"] if case["u"] else []


@pytest.mark.core_specs
@pytest.mark.parametrize("spec", SPECS, ids=spec_id)
def test_casadi_agrees_with_reference(spec, casadi, generated, reference, derived, rng):
    d = derived(str(spec))
    module, ref = generated(spec, "casadi"), reference(spec)
    n = d.n
    assert module.STATE == [s.name for s in d.model.q + d.model.qd]
    assert list(module.PARAMETERS) == [p.symbol.name for p in d.model.parameters]
    assert list(module.INPUTS) == [x.symbol.name for x in d.model.inputs]
    for k, case in enumerate(cases_of(d, ref, rng)):
        label = f"{spec.stem} case {k} against {ref.source}"
        expected = ref.evaluate(case)
        args = (case["t"], case["y"], case["p"], inputs_of(case))
        value = lambda f: np.array(f(*args)).ravel()      # noqa: E731
        assert_close(value(module.rhs), expected["rhs"], f"{label}: rhs", RTOL)
        assert_close(value(module.multipliers), expected["lam"], f"{label}: multipliers", RTOL)
        assert_close(value(module.mass_matrix), expected["M"], f"{label}: mass_matrix", RTOL)
        assert_close(value(module.forcing), expected["F"], f"{label}: forcing", RTOL)
        assert_close(value(module.invariants), [expected["inv"][c] for c in module.INVARIANTS],
                     f"{label}: invariants", RTOL)
        assert_close(value(module.energy), [expected["inv"]["energy"]], f"{label}: energy", RTOL)
        check_implicit(module, case, expected, n, label)


def check_implicit(module, case: dict, expected: dict, n: int, label: str) -> None:
    """The implicit form at (q, q', q'', lambda) of the reference."""
    y, qdd, lam = case["y"], expected["qdd"], expected["lam"]
    out = module.implicit(case["t"], y[:n], y[n:], qdd, lam, case["p"], inputs_of(case))
    residual, position, velocity, acceleration = (np.array(v).ravel() for v in out)
    M, A = np.reshape(expected["M"], (n, n)), np.reshape(
        np.array(module.constraint_matrix(case["t"], y, case["p"], inputs_of(case))), (len(lam), n))
    # the size of the terms that cancel: |M| |q''| + |F| + |A^T| |lambda|, |A| |q''| + |b|
    scale = (np.abs(M) @ np.abs(qdd) + np.abs(expected["F"]) + np.abs(A.T) @ np.abs(lam)).max()
    assert np.abs(residual).max() <= RTOL * scale, f"{label}: residual {residual} (scale {scale:.3g})"
    if lam:
        bias = np.array(module.constraint_bias(case["t"], y, case["p"], inputs_of(case))).ravel()
        scale = (np.abs(A) @ np.abs(qdd) + np.abs(bias)).max()
        assert np.abs(acceleration).max() <= RTOL * scale, f"{label}: acceleration rows {acceleration}"
        worst = np.abs(np.concatenate([position, velocity])).max()
        assert abs(worst - expected["inv"]["constraint_residual"]) <= RTOL * max(1.0, worst), \
            f"{label}: position/velocity rows {position} {velocity} vs {expected['inv']}"
    else:
        assert position.size == velocity.size == acceleration.size == 0


@pytest.mark.core_specs
@pytest.mark.parametrize("spec", SPECS, ids=spec_id)
def test_jax_agrees_with_reference(spec, jax, generated, reference, derived, rng):
    import jax.numpy as jnp

    d = derived(str(spec))
    module, ref = generated(spec, "jax"), reference(spec)
    assert module.STATE == [s.name for s in d.model.q + d.model.qd]
    assert list(module.INPUTS) == [x.symbol.name for x in d.model.inputs]
    for k, case in enumerate(cases_of(d, ref, rng)):
        label = f"{spec.stem} case {k} against {ref.source}"
        expected = ref.evaluate(case)
        t, y, p = case["t"], jnp.array(case["y"]), jnp.array(case["p"])
        u = jnp.array(case["u"]) if case["u"] else None
        for function in (module.rhs, module.mass_matrix, module.forcing, module.constraint_matrix,
                         module.multipliers):
            assert function(t, y, p, u).dtype == jnp.float64, function
        assert_close(module.rhs(t, y, p, u), expected["rhs"], f"{label}: rhs", RTOL)
        assert_close(module.multipliers(t, y, p, u), expected["lam"], f"{label}: multipliers", RTOL)
        assert_close(module.mass_matrix(t, y, p, u).ravel(), expected["M"], f"{label}: mass_matrix", RTOL)
        assert_close(module.forcing(t, y, p, u), expected["F"], f"{label}: forcing", RTOL)
        got = module.invariants(t, y, p, u)
        assert list(got) == module.INVARIANTS == list(expected["inv"])
        assert_close([got[c] for c in got], [expected["inv"][c] for c in got], f"{label}: invariants", RTOL)


@pytest.mark.parametrize("name", SMALL)
def test_jax_float32(name, jax, generated, reference, derived, rng):
    """float32 arguments give float32 values within 1e-4 (relative, norm-wise) of the reference."""
    import jax.numpy as jnp

    spec = ROOT / "specs" / f"{name}.yaml"
    d = derived(str(spec))
    module, ref = generated(spec, "jax"), reference(spec)
    for case in cases_of(d, ref, rng):
        expected = ref.evaluate(case)
        y, p = jnp.array(case["y"], dtype=jnp.float32), jnp.array(case["p"], dtype=jnp.float32)
        u = jnp.array(case["u"], dtype=jnp.float32) if case["u"] else None
        got = jax.jit(module.rhs)(jnp.float32(case["t"]), y, p, u)
        assert got.dtype == module.forcing(case["t"], y, p, u).dtype == jnp.float32
        assert_close(got, expected["rhs"], f"{name} float32 rhs", 1e-4)


def test_jax_jacobian_of_cart_pole_equals_linearize(jax, generated):
    """jax.jacfwd of the generated rhs at the upright state equals `lagcli linearize`'s A and B
    (finite-dimensional Jacobians of lagcli's own linearisation, another route) to 1e-9."""
    import jax.numpy as jnp

    module = generated(ROOT / "specs" / "cart_pole.yaml", "jax")
    done = subprocess.run([sys.executable, "-m", "lagcli", "linearize", str(ROOT / "specs" / "cart_pole.yaml"),
                           "--input", "F", "--json"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    linear = json.loads(done.stdout)
    assert linear["states"] == module.STATE and linear["inputs"] == list(module.INPUTS)
    y, p, u = jnp.zeros(4), module.parameter_vector(linear["parameters"]), jnp.zeros(1)
    A = jax.jacfwd(module.rhs, argnums=1)(0.0, y, p, u)
    B = jax.jacfwd(module.rhs, argnums=3)(0.0, y, p, u)
    assert np.abs(np.array(A) - np.array(linear["A"])).max() <= 1e-9
    assert np.abs(np.array(B) - np.array(linear["B"])).max() <= 1e-9


def test_casadi_integrator_follows_lagcli_simulate(casadi, generated, tmp_path):
    """`casadi.integrator` (CVODES) on the module's `dae()` follows `lagcli simulate` of the
    double pendulum (scipy's DOP853) over 2 s to 1e-7."""
    module = generated(ROOT / "specs" / "double_pendulum.yaml", "casadi")
    done = subprocess.run([sys.executable, "-m", "lagcli", "simulate", str(ROOT / "specs" / "double_pendulum.yaml"),
                           "--t-end", "2", "--dt", "0.5", "--backend", "python", "-o", str(tmp_path / "dp.csv")],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    rows = np.loadtxt(tmp_path / "dp.csv", delimiter=",", skiprows=1)
    integrator = casadi.integrator("I", "cvodes", module.dae(), 0.0, list(rows[1:, 0]),
                                   {"abstol": 1e-13, "reltol": 1e-12})
    xf = np.array(integrator(x0=module.INITIAL, p=module.parameter_vector())["xf"]).T
    assert np.abs(xf - rows[1:, 1:5]).max() <= 1e-7


def test_jax_grad_of_energy_is_the_momentum(jax, generated, rng):
    """jax.grad of the energy T + V with respect to q' is M q' (T = q'^T M q' / 2, V(q)):
    the gradient of one generated function against another (the double pendulum)."""
    import jax.numpy as jnp

    module = generated(ROOT / "specs" / "double_pendulum.yaml", "jax")
    p = module.parameter_vector()
    for _ in range(3):
        y = jnp.asarray(rng.uniform(-1.0, 1.0, 4))
        gradient = jax.grad(lambda y: module.invariants(0.0, y, p)["energy"])(y)
        assert_close(gradient[2:], module.mass_matrix(0.0, y, p) @ y[2:], "dE/dq'", RTOL)


def test_jax_default_is_float32(generated):
    """Without jax_enable_x64 (jax's default, in a fresh process), the module computes in float32."""
    pytest.importorskip("jax", reason="jax is not installed (pip install 'lagcli[jax]')")
    module = generated(ROOT / "specs" / "double_pendulum.yaml", "jax")
    script = ("import importlib.util, sys; import jax.numpy as jnp\n"
              "spec = importlib.util.spec_from_file_location('m', sys.argv[1])\n"
              "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)\n"
              "print(m.rhs(0.0, jnp.asarray(m.INITIAL), m.parameter_vector()).dtype)\n")
    env = {k: v for k, v in os.environ.items() if k != "JAX_ENABLE_X64"}
    done = subprocess.run([sys.executable, "-c", script, module.__file__], capture_output=True, text=True,
                          timeout=300, env=env)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "float32"
