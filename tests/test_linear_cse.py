"""The CSE of a big system (`lagcli.targets.cse.linear_cse`, lagcli/targets/shared_dag.py).

No bundled spec is big enough to use it (checked here), so its code is tested on bundled
specs with the budget lowered to 0: the generated Python module and C model evaluate to
the Derivation's values at seeded random states (the mpmath reference of
test_codegen_python.py), the code is the same in another process with another hash seed,
and the graph's own rewritings (weighted sums factored, tails of sums nested) keep the
values of what they rewrite.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from test_codegen_python import compare, random_inputs, run_module

ROOT = Path(__file__).resolve().parent.parent
SPECS = ["double_pendulum", "ex6_9_two_wheels_axle", "rolling_disc", "heavy_symmetric_top",
         "bead_on_spinning_hoop", "ex18_slider_compound_pendulum", "benchmark_bicycle"]


@pytest.fixture
def linear(monkeypatch):
    """Every CSE through `linear_cse`; the list of its calls."""
    from lagcli.targets import cse

    calls = []
    real = cse.linear_cse

    def spy(exprs, symbols):
        calls.append(len(exprs))
        return real(exprs, symbols)

    monkeypatch.setattr(cse, "LINEAR_CSE_MIN_NODES", 0)
    monkeypatch.setattr(cse, "linear_cse", spy)
    return calls


@pytest.mark.parametrize("name", SPECS)
def test_python_module_agrees_with_engine(name, linear, derived, rng, tmp_path):
    from lagcli import commands

    path = tmp_path / f"{name}.py"
    commands.generate(str(ROOT / "specs" / f"{name}.yaml"), "python", str(path))
    assert linear, "the linear CSE was not used"
    d = derived(f"{name}.yaml")
    cases = random_inputs(d, rng)
    for i, (case, got) in enumerate(zip(cases, run_module(path, cases)["cases"])):
        compare(d, case, got, f"{name} state {i}")


@pytest.mark.parametrize("name", SPECS)
def test_c_model_agrees_with_engine(name, linear, derived, rng, tmp_path):
    test_codegen_c = pytest.importorskip("test_codegen_c")
    if test_codegen_c.CC is None:
        pytest.skip("no C compiler (cc)")
    built = test_codegen_c.Built(ROOT / "specs" / f"{name}.yaml", tmp_path)
    assert linear, "the linear CSE was not used"
    d = derived(f"{name}.yaml")
    for i, case in enumerate(random_inputs(d, rng)):
        compare(d, case, test_codegen_c.call(built, d, case), f"{name} state {i}")


GENERATE = """
import json, sys
sys.path.insert(0, sys.argv[1])
from lagcli.targets import cse
cse.LINEAR_CSE_MIN_NODES = 0
from lagcli.derive.pipeline import derive_file
from lagcli.targets import generate
print(json.dumps({lang: generate(derive_file(sys.argv[2]), lang) for lang in ("c", "python")}))
"""


def test_same_code_in_another_process(linear):
    from lagcli.derive.pipeline import derive_file
    from lagcli.targets import generate

    spec = ROOT / "specs" / "ex6_9_two_wheels_axle.yaml"
    here = {lang: generate(derive_file(spec), lang) for lang in ("c", "python")}
    env = {**os.environ, "PYTHONHASHSEED": "4321"}
    done = subprocess.run([sys.executable, "-c", GENERATE, str(ROOT), str(spec)], capture_output=True,
                          text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout) == here


def test_no_bundled_spec_reaches_the_budget(derived):
    from lagcli.interface import layout_of
    from lagcli.targets.cse import LINEAR_CSE_MIN_NODES, few_nodes
    from lagcli.targets.expressions import collect

    for spec in sorted((ROOT / "specs").glob("*.yaml")):
        d = derived(spec.name)
        outputs = collect(d, layout_of(d), tidy=False).groups().values()
        assert few_nodes([sp.sympify(e) for exprs in outputs for e in exprs], LINEAR_CSE_MIN_NODES), spec.name


def _values(temporaries, reduced, numbers: dict) -> list[float]:
    numbers = dict(numbers)
    for symbol, value in temporaries:
        numbers[symbol] = value.xreplace(numbers)
    return [float(e.xreplace(numbers)) for e in reduced]


def test_weighted_sums_are_factored_and_tails_nested():
    from lagcli.targets.cse import linear_cse

    n = 6
    m, l, q = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}"), sp.symbols(f"q1:{n + 1}")
    g = sp.Symbol("g")
    # the chain's mass matrix and gravity terms as derived: sum_k m_k * (...) term by term
    exprs = [sp.Add(*(m[k] * l[i] * l[j] * sp.cos(q[i] - q[j]) for k in range(max(i, j), n)))
             for i in range(n) for j in range(n)]
    exprs += [sp.Add(*(-g * l[i] * m[k] * sp.sin(q[i]) for k in range(i, n))) for i in range(n)]
    temporaries, reduced = linear_cse(exprs, sp.numbered_symbols("x", cls=sp.Dummy))
    numbers = {s: sp.Float(0.3 + 0.1 * k) for k, s in enumerate((*m, *l, *q, g))}
    expected = [float(e.xreplace(numbers)) for e in exprs]
    assert _values(temporaries, reduced, numbers) == pytest.approx(expected, rel=1e-13)
    sums = [v for _, v in temporaries if v.is_Add and v.free_symbols <= set(m) | {s for s, _ in temporaries}]
    assert len(sums) == n - 1 and all(len(v.args) == 2 for v in sums)     # m5 + m6, x0 + m4, ...
    additions = sum(len(e.args) - 1 for e in [*reduced, *(v for _, v in temporaries)] if e.is_Add)
    assert additions <= n * (n + 1) // 2 + n        # no entry adds its masses again


def _variational_values(source: str, n: int, rng_seed: int) -> list:
    import numpy as np

    namespace: dict = {}
    exec(compile(source, "module.py", "exec"), namespace)
    model = namespace["variational_model"]()
    rng = np.random.default_rng(rng_seed)
    values = []
    for _ in range(3):
        t, q, v = rng.uniform(0, 1), rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
        values += [np.ravel(x) for x in (*model.momenta(t, q, v), *model.jacobian(t, q, v), *model.holonomic(t, q))]
    return values


@pytest.mark.parametrize("name", ["double_pendulum", "cartesian_pendulum", "ex18_slider_compound_pendulum"])
def test_variational_functions_agree(name, monkeypatch):
    """The variational integrator's functions (their own CSE, lagcli/targets/discrete_code.py)
    through `linear_cse` give the values of those through sympy.cse."""
    import numpy as np
    from lagcli import system
    from lagcli.targets import cse

    loaded = system.load(ROOT / "specs" / f"{name}.yaml")
    (usual,) = loaded.generate("python").values()
    monkeypatch.setattr(cse, "LINEAR_CSE_MIN_NODES", 0)
    (linear,) = loaded.generate("python").values()
    assert linear != usual
    n = len(loaded.layout.coordinates)
    for got, expected in zip(_variational_values(linear, n, 5), _variational_values(usual, n, 5)):
        assert np.allclose(got, expected, rtol=1e-12, atol=1e-12)
