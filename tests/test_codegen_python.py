"""`lagcli generate --lang python`, run against the engine, for every bundled spec.

The generated module is imported in a subprocess where sympy cannot be imported
(`sys.modules['sympy'] = None`), evaluated at seeded random states, and compared with a
reference computed here, independently of lagcli's emitters: the Derivation's
mass_matrix, forcing, constraint_matrix and constraint_bias with the numbers
substituted, and the augmented system [[M, -A^T], [A, 0]] [q''; lambda] =
[F; b - 2 alpha (A q' + d) - beta^2 phi] solved with mpmath at 30 digits. q'' and lambda
must agree to 1e-12 relative (norm-wise, per vector), for the exact equations
(alpha = beta = 0) and for the Baumgarte-stabilised ones.

`reference(d, t, y, p, alpha, beta)` and `random_inputs(d, rng)` are shared with
test_codegen_c.py.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest
import sympy as sp

ROOT = Path(__file__).resolve().parent.parent
SPEC_FILES = sorted((ROOT / "specs").glob("*.yaml"))
RTOL = 1e-12
STATES = 4

RUNNER = r"""
import importlib.util, json, sys
sys.modules["sympy"] = None                       # the module must not need sympy
spec = importlib.util.spec_from_file_location("generated", sys.argv[1])
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
cases = json.load(sys.stdin)
out = []
for case in cases:
    t, y, p, a, b = case["t"], case["y"], case["p"], case["alpha"], case["beta"]
    u = (case["u"],) if hasattr(module, "INPUTS") else ()   # a spec with inputs: u given
    qdd, lam = module.accelerations(t, y, p, a, b, *u)
    out.append({
        "rhs": [float(v) for v in module.rhs(t, y, p, *u)],
        "qdd": [float(v) for v in qdd], "lam": [float(v) for v in lam],
        "M": module.mass_matrix(t, y, p).tolist(), "F": module.forcing(t, y, p, *u).tolist(),
        "inv": {k: float(v) for k, v in module.invariants(t, y, p).items()},
        "dict_rhs": [float(v) for v in module.rhs(t, y, dict(zip(module.PARAMETERS, p)),
                                                  *(dict(zip(module.INPUTS, case["u"])),) if u else ())],
    })
print(json.dumps({"cases": out, "names": [module.COORDINATES, module.STATE, list(module.PARAMETERS),
                                          module.MULTIPLIERS, module.INVARIANTS]}))
"""


def spec_id(path: Path) -> str:
    return path.stem


def random_inputs(d, rng, count: int = STATES) -> list[dict]:
    """Seeded random (t, y, p, u) with Baumgarte gains: the first half exact (alpha = beta = 0)."""
    n, k = d.n, len(d.model.parameters)
    cases = []
    for i in range(count):
        stabilized = i >= count // 2
        cases.append({
            "t": float(rng.uniform(0.1, 2.0)),
            "y": [float(v) for v in np.concatenate([rng.uniform(0.2, 1.2, n), rng.uniform(-1.0, 1.0, n)])],
            "p": [float(v) for v in rng.uniform(0.5, 2.0, k)],
            "alpha": float(rng.uniform(1, 10)) if stabilized else 0.0,
            "beta": float(rng.uniform(1, 10)) if stabilized else 0.0,
            "u": [float(v) for v in rng.uniform(-2.0, 2.0, len(d.model.inputs))],
        })
    return cases


def _numbers(d, case: dict) -> dict:
    model = d.model
    values = {model.t: case["t"]}
    values.update(zip(model.q + model.qd, case["y"]))
    values.update(zip(model.parameter_symbols, case["p"]))
    values.update(zip(model.input_symbols, case.get("u", ())))
    return {s: sp.Float(v, 30) for s, v in values.items()}


def _evaluate(exprs, subs) -> list:
    return [mpmath.mpf(sp.N(sp.sympify(e).xreplace(subs), 30)) for e in exprs]


def reference(d, case: dict) -> dict:
    """q'', lambda, M, F and the invariants at `case`, from the Derivation with mpmath."""
    with mpmath.workdps(30):
        subs = _numbers(d, case)
        n, m = d.n, len(d.constraints)
        M = _evaluate(d.mass_matrix, subs)
        F = _evaluate(d.forcing, subs)
        A = _evaluate(d.constraint_matrix, subs)
        b = _evaluate(d.constraint_bias, subs)
        qd = case["y"][n:]
        for j, row in enumerate(d.constraints):
            w = sum(A[j * n + k] * qd[k] for k in range(n)) + _evaluate([row.d], subs)[0]
            phi = _evaluate([row.expr], subs)[0] if row.kind == "holonomic" else 0
            b[j] -= 2 * case["alpha"] * w + case["beta"] ** 2 * phi
        K = mpmath.matrix(n + m, n + m)
        for i in range(n):
            for k in range(n):
                K[i, k] = M[i * n + k]
            for j in range(m):
                K[i, n + j] = -A[j * n + i]
                K[n + j, i] = A[j * n + i]
        x = mpmath.lu_solve(K, mpmath.matrix(F + b))
        return {
            "qdd": np.array([float(x[i]) for i in range(n)]),
            "lam": np.array([float(x[n + j]) for j in range(m)]),
            "M": np.array([float(v) for v in M]).reshape(n, n),
            "F": np.array([float(v) for v in F]),
            "inv": reference_invariants(d, case, subs),
        }


def reference_invariants(d, case: dict, subs: dict) -> dict:
    values = {"energy": float(sp.N(d.energy.xreplace(subs), 30))}
    if d.jacobi_integral is not None:
        values["jacobi"] = float(sp.N(d.jacobi_integral.xreplace(subs), 30))
    for c in d.conserved:
        if c.kind == "momentum":
            values[c.name] = float(sp.N(c.expr.xreplace(subs), 30))
    if d.constraints:
        qd = sp.Matrix(d.model.qd).xreplace(subs)
        worst = 0.0
        for row in d.constraints:
            w = sum(a.xreplace(subs) * v for a, v in zip(row.a, qd)) + row.d.xreplace(subs)
            worst = max(worst, abs(float(sp.N(w, 30))))
            if row.kind == "holonomic":
                worst = max(worst, abs(float(sp.N(row.expr.xreplace(subs), 30))))
        values["constraint_residual"] = worst
    return values


def assert_close(actual, expected, what: str, rtol: float = RTOL) -> None:
    """Norm-wise relative agreement: max |a - e| <= rtol * max(max |e|, 1e-300)."""
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    if expected.size == 0:
        return
    scale = max(float(np.max(np.abs(expected))), 1e-300)
    error = float(np.max(np.abs(actual - expected)))
    assert error <= rtol * scale, f"{what}: error {error:.3g} > {rtol:g} * {scale:.3g}\n{actual}\n{expected}"


def compare(d, case: dict, got: dict, label: str) -> None:
    ref = reference(d, case)
    n = d.n
    assert_close(got["qdd"], ref["qdd"], f"{label}: q''")
    assert_close(got["lam"], ref["lam"], f"{label}: lambda")
    assert_close(np.reshape(got["M"], (n, n)), ref["M"], f"{label}: mass_matrix")
    assert_close(got["F"], ref["F"], f"{label}: forcing")
    assert list(got["inv"]) == list(ref["inv"]), f"{label}: invariant columns"
    for name, value in ref["inv"].items():
        # the residual of a random (inconsistent) state is a difference of O(1) terms
        assert_close([got["inv"][name]], [value], f"{label}: {name}",
                     rtol=RTOL if name != "constraint_residual" else 1e-10)


@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    """`get(spec_path)` -> path of the generated module, made once per spec."""
    from lagcli import commands

    folder = tmp_path_factory.mktemp("python_modules")
    made = {}

    def get(spec: Path) -> Path:
        if spec not in made:
            made[spec] = folder / f"{spec.stem}.py"
            commands.generate(str(spec), "python", str(made[spec]))
        return made[spec]

    return get


def run_module(path: Path, cases: list[dict]) -> dict:
    done = subprocess.run([sys.executable, "-c", RUNNER, str(path)], input=json.dumps(cases),
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.mark.core_specs
@pytest.mark.parametrize("spec", SPEC_FILES, ids=spec_id)
def test_module_agrees_with_engine_without_sympy(spec, generated, derived, rng):
    d = derived(spec.name)
    cases = random_inputs(d, rng)
    result = run_module(generated(spec), cases)
    coordinates, state, parameters, multipliers, invariants = result["names"]
    assert coordinates == [s.name for s in d.model.q]
    assert state == [s.name for s in d.model.q + d.model.qd]
    assert parameters == [p.symbol.name for p in d.model.parameters]
    assert multipliers == [s.name for s in d.multipliers]
    for i, (case, got) in enumerate(zip(cases, result["cases"])):
        label = f"{spec.stem} state {i} (alpha={case['alpha']:.3g})"
        compare(d, case, got, label)
        n = d.n
        if case["alpha"] == 0.0:
            assert_close(got["rhs"], case["y"][n:] + got["qdd"], f"{label}: rhs")
            assert_close(got["dict_rhs"], got["rhs"], f"{label}: rhs with p as a dict", rtol=0)


def test_module_interface_and_simulate(generated):
    """Constants, p as a dict with defaults, simulate() rows like the CSV of `lagcli simulate`."""
    import importlib.util

    path = generated(ROOT / "specs" / "ex6_9_two_wheels_axle.yaml")
    spec = importlib.util.spec_from_file_location("two_wheels", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.NAME == "ex6_9_two_wheels_axle" and module.SPEC_FILE == "ex6_9_two_wheels_axle.yaml"
    assert module.MULTIPLIERS == ["lambda_1"]
    assert module.INVARIANTS == ["energy", "jacobi", "p_phi", "constraint_residual"]   # phi is ignorable
    y = module.INITIAL
    assert np.array_equal(module.rhs(0.0, y, {"l": 0.5}), module.rhs(0.0, y, [1.0, 0.5]))
    with pytest.raises(KeyError):
        module.rhs(0.0, y, {"nope": 1.0})
    header, rows = module.simulate(t_end=1.0, dt=0.25)
    assert header == ["t", "x", "y", "phi", "x_dot", "y_dot", "phi_dot", "lambda_1", "energy", "jacobi",
                      "p_phi", "constraint_residual"]
    assert np.allclose(rows[:, 0], [0, 0.25, 0.5, 0.75, 1.0])
    # Ex 6-9: from (v0, w) = (1, 2): x = (v0/w) sin wt, lambda = -2 m v0 w
    assert np.allclose(rows[:, 1], 0.5 * np.sin(2 * rows[:, 0]), atol=1e-7)
    assert np.allclose(rows[:, 7], -4.0, atol=1e-6)
    assert list(module.output_times(0.3, 0.1)) == [0.0, 0.1, 0.2, 0.30000000000000004]
    assert list(module.output_times(0.25, 0.1)) == [0.0, 0.1, 0.2, 0.25]


def test_generate_python_cli_writes_stdout_or_file(tmp_path):
    from click.testing import CliRunner

    from lagcli.cli import cli

    spec = str(ROOT / "specs" / "double_pendulum.yaml")
    result = CliRunner().invoke(cli, ["generate", spec, "--lang", "python"])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("# Generated by lagcli")
    out = tmp_path / "dp.py"
    result = CliRunner().invoke(cli, ["generate", spec, "--lang", "python", "-o", str(out)])
    assert result.exit_code == 0 and out.read_text().startswith("# Generated by lagcli")


def test_symbol_without_slot_is_refused():
    """The printer refuses a symbol that is not t, a coordinate, velocity or parameter."""
    from lagcli.targets import codegen
    from lagcli.targets.python import PythonPrinter
    from lagcli.errors import EmitError

    x, stray = sp.symbols("x stray")
    printer = PythonPrinter({x: "y[0]"})
    assert printer.code(x**2 + sp.pi) == "(y[0]*y[0]) + 3.14159265358979323846"
    with pytest.raises(EmitError, match="stray"):
        codegen.check_slots([x + stray], printer.slots)
    with pytest.raises(EmitError, match="stray"):
        printer.code(stray)


def test_simulate_ends_at_t_end_when_a_grid_time_passes_it_by_round_off(tmp_path):
    """3 * 0.1 = 0.30000000000000004 > 0.3: the module's simulate still integrates to its
    last output time (it raised scipy's "t_eval not within t_span"), and its end state
    agrees with scipy's own run of the module's rhs to t_end."""
    import importlib.util

    import numpy as np
    from scipy.integrate import solve_ivp

    import lagcli

    path = tmp_path / "dp_round.py"
    lagcli.load(str(ROOT / "specs" / "double_pendulum.yaml")).generate("python", path)
    spec = importlib.util.spec_from_file_location("dp_round", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    header, rows = module.simulate(t_end=0.3, dt=0.1)
    assert len(rows) == 4
    n = len(module.COORDINATES)
    p = [module.PARAMETERS[name] for name in module.PARAMETERS]
    reference = solve_ivp(lambda s, x: module.rhs(s, x, p), (0.0, rows[-1][0]), rows[0][1:1 + 2 * n],
                          method="DOP853", rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(rows[-1][1:1 + 2 * n], reference.y[:, -1], rtol=1e-7, atol=1e-9)
