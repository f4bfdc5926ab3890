"""Input laws in the CasADi and JAX modules: `inputs(t, x, p)` (the spec's laws) and
`rhs_closed_loop(t, x, p)`, against the Derivation with the laws substituted (sympy,
solved by numpy), the closed-loop A - B K of an LQR design made with scipy, and a run of
`lagcli simulate`."""
from __future__ import annotations

import importlib.util

import numpy as np
import pytest
import sympy as sp

import lagcli
from lagcli.derive.closed_loop import closed_loop

from test_hybrid_events import HYBRID
from test_hybrid_laws import cart_pole_lqr

SPEC = HYBRID / "cart_pole_lqr.yaml"


def load_module(system, lang: str, folder):
    (text,) = system.generate(lang).values()
    path = folder / f"cart_pole_lqr_{lang}.py"
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def system():
    return lagcli.load(SPEC)


def reference_rhs(system):
    """dy/dt of the closed loop from the Derivation: M q'' = F(t, q, q', law) solved by numpy."""
    d = closed_loop(system.derivation)
    model = d.model
    args = (model.t, *model.q, *model.qd, *model.parameter_symbols)
    M = sp.lambdify(args, d.mass_matrix)
    F = sp.lambdify(args, d.forcing)
    n = len(model.q)

    def rhs(t, y, p):
        qdd = np.linalg.solve(np.array(M(t, *y, *p), dtype=float), np.array(F(t, *y, *p), dtype=float).ravel())
        return np.concatenate([y[n:], qdd])
    return rhs


def states(count=20, seed=4):
    return np.random.default_rng(seed).uniform(-1, 1, (count, 4))


def test_jax_closed_loop_rhs_and_its_jacobian(system, tmp_path):
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    module = load_module(system, "jax", tmp_path)
    p = np.array(list(module.PARAMETERS.values()))
    reference = reference_rhs(system)
    for y in states():
        assert np.allclose(module.rhs_closed_loop(0.0, y, p), reference(0.0, y, p), rtol=1e-12, atol=1e-12)
        K = [module.PARAMETERS[f"k{j}"] for j in range(1, 5)]
        assert float(module.inputs(0.0, y, p)[0]) == pytest.approx(-np.dot(K, y), rel=1e-14, abs=1e-14)
    A, B, K = cart_pole_lqr()
    p = np.array([1.0, 0.1, 0.5, 9.81, *K])
    jacobian = jax.jacfwd(module.rhs_closed_loop, argnums=1)(0.0, np.zeros(4), p)
    assert np.allclose(jacobian, A - np.outer(B, K), rtol=1e-9, atol=1e-9)


def test_casadi_closed_loop_rhs_and_a_run(system, tmp_path):
    casadi = pytest.importorskip("casadi")
    module = load_module(system, "casadi", tmp_path)
    p = np.array(list(module.PARAMETERS.values()))
    reference = reference_rhs(system)
    for y in states():
        got = np.array(module.rhs_closed_loop(0.0, y, p)).ravel()
        assert np.allclose(got, reference(0.0, y, p), rtol=1e-12, atol=1e-12)
    x, t = casadi.SX.sym("x", 4), casadi.SX.sym("t")
    dae = {"t": t, "x": x, "ode": module.rhs_closed_loop(t, x, p)}
    times = np.linspace(0.0, 2.0, 21)
    integrator = casadi.integrator("I", "cvodes", dae, 0.0, times[1:], {"reltol": 1e-12, "abstol": 1e-14})
    final = np.array(integrator(x0=module.INITIAL)["xf"]).T
    run = system.simulate(t_end=2.0, dt=0.1, rtol=1e-12, atol=1e-14, backend="python")
    expected = np.column_stack([run[name] for name in module.STATE])[1:]
    assert np.allclose(final, expected, rtol=0, atol=1e-8)
