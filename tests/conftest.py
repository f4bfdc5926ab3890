"""Shared test fixtures.

- `SPECS`: the bundled specs directory (`specs/` at the project root).
- `derived(name)`: the `Derivation` of `specs/<name>.yaml`, cached for the session
  (a spec is loaded and derived once however many tests use it).
- `rng`: a seeded numpy Generator, so "random states" are the same on every run.
- `assert_zero(expr)`: asserts that a sympy expression (or matrix) is identically 0,
  numerically (20 digits) at seeded random values of its symbols.
- `augmented(d, values)`: q'' and lambda at one numeric state, by solving the
  augmented system [[M, -A^T], [A, 0]] [q''; lambda] = [F; bias] with numpy.
- `ddt(model, expr)`: the total time derivative of an expression in t, q, q'
  (an independent oracle for hand-written Lagrangians).

The engine is imported inside the fixtures, so test collection works even while
parts of it are missing.
"""
from __future__ import annotations

import signal
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

# The signal tests send SIGHUP and SIGINT and expect lagcli to end a run like Ctrl-C. A
# suite started under `nohup` inherits SIGHUP ignored, one started as a background job of
# a script (`cmd &` in a non-interactive shell) inherits SIGINT ignored, and lagcli rightly
# leaves an ignored signal alone, so those tests would hang: the suite restores the
# defaults for itself and its children (a handled signal is reset to the default at exec).
if signal.getsignal(signal.SIGHUP) == signal.SIG_IGN:
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

# hypothesis draws the same examples on every run and keeps no database of failures:
# a test's verdict depends on the code only, never on the run or a local `.hypothesis`.
from hypothesis import settings as _hypothesis_settings  # noqa: E402

_hypothesis_settings.register_profile("same-every-run", derandomize=True, database=None)
_hypothesis_settings.load_profile("same-every-run")

ROOT = Path(__file__).resolve().parent.parent
SPECS = ROOT / "specs"

_DERIVED: dict[str, object] = {}
_SIMPLIFY_MAX_OPS = 600


def nlink_spec(folder: Path, n: int) -> Path:
    """bench/nlink.py's planar N-link pendulum (positions as flat sums), written to
    folder/nlinkN.yaml: the chain the scale tests and the benchmarks share."""
    import sys

    sys.path.insert(0, str(ROOT / "bench"))
    from nlink import nlink_spec_text

    path = folder / f"nlink{n}.yaml"
    path.write_text(nlink_spec_text(n))
    return path


def spec_path(name: str) -> Path:
    """`specs/<name>.yaml` (or the name as given when it has a suffix)."""
    path = SPECS / name
    return path if path.suffix else path.with_suffix(".yaml")


@pytest.fixture(scope="session")
def specs_dir() -> Path:
    return SPECS


@pytest.fixture(scope="session")
def derived():
    """Return `get(name)` -> Derivation of specs/<name>.yaml, cached per session."""
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive

    def get(name: str):
        key = str(spec_path(name))
        if key not in _DERIVED:
            _DERIVED[key] = derive(load_model(key))
        return _DERIVED[key]

    return get


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240617)


def _numeric_zero(expr: sp.Expr, rng: np.random.Generator, trials: int = 4) -> tuple[bool, complex]:
    symbols = sorted(expr.free_symbols, key=sp.default_sort_key)
    worst = 0j
    for _ in range(trials):
        values = {s: sp.Float(rng.uniform(0.3, 1.3)) for s in symbols}
        value = complex(sp.N(expr.xreplace(values), 20))
        if abs(value) > abs(worst):
            worst = value
    return abs(worst) < 1e-9, worst


def _assert_zero(expr, what: str = "") -> None:
    """Zero at seeded random points (20 digits), else a failure that shows the expression
    (simplified when small). Numeric first: sympy's simplify can take minutes on a
    600-operation trigonometric expression that is plainly zero at every point."""
    rng = np.random.default_rng(7)
    items = list(expr) if isinstance(expr, sp.MatrixBase) else [expr]
    for i, item in enumerate(items):
        item = sp.sympify(item)
        if item == 0:
            continue
        ok, worst = _numeric_zero(item, rng)
        label = f"{what}[{i}]" if len(items) > 1 else what
        shown = sp.simplify(item) if sp.count_ops(item) <= _SIMPLIFY_MAX_OPS // 10 else item
        assert ok, f"{label} is not identically zero: {shown} (e.g. {worst:.3g})"


@pytest.fixture
def assert_zero():
    """`assert_zero(expr_or_matrix, what="")`: the expression is identically zero."""
    return _assert_zero


def _augmented(d, values: dict) -> tuple[np.ndarray, np.ndarray]:
    model = d.model
    subs = {p.symbol: p.value for p in model.parameters}
    subs.update(values)
    subs = {k: sp.Float(v) for k, v in subs.items()}

    def num(matrix) -> np.ndarray:
        return np.array(sp.Matrix(matrix).xreplace(subs).evalf(), dtype=float)

    n = len(model.q)
    m_rows = len(d.multipliers)
    M = num(d.mass_matrix)
    F = num(d.forcing).reshape(n)
    if m_rows == 0:
        return np.linalg.solve(M, F), np.zeros(0)
    A = num(d.constraint_matrix).reshape(m_rows, n)
    bias = num(d.constraint_bias).reshape(m_rows)
    K = np.block([[M, -A.T], [A, np.zeros((m_rows, m_rows))]])
    sol = np.linalg.solve(K, np.concatenate([F, bias]))
    return sol[:n], sol[n:]


@pytest.fixture
def augmented():
    """`augmented(d, {symbol: value})` -> (q'', lambda) as numpy arrays; parameters
    not given take the spec's default values."""
    return _augmented


def _ddt(model, expr):
    expr = sp.sympify(expr)
    rate = sp.diff(expr, model.t)
    for q, qd, qdd in zip(model.q, model.qd, model.qdd):
        rate += sp.diff(expr, q) * qd + sp.diff(expr, qd) * qdd
    return rate


@pytest.fixture
def ddt():
    """`ddt(model, expr)`: total time derivative along q(t)."""
    return _ddt


# Bundled specs that take minutes in the tests looping over every spec (derive, LaTeX,
# codegen, simulate); those cases run with `pytest -m slow`. Their own test files
# (e.g. tests/test_benchmark_bicycle.py, tests/test_linearize_bicycle.py) decide for themselves.
HEAVY_SPECS = ("benchmark_bicycle", "benchmark_bicycle_frames")


# A test marked `core_specs` sweeps the bundled specs but runs only on these by default
# (on all of them with `pytest -m slow`): together they hold each kind of system (plain,
# holonomic constraint, rolling and nonholonomic, time-dependent, an input, frames in 3D,
# impacts), so the default run meets every code path of the costly sweeps (compilers,
# Octave, FMUs, a browser) in a fraction of their time.
CORE_SPECS = ("double_pendulum", "cartesian_pendulum", "chaplygin_sled", "kapitza_pendulum", "cart_pole",
              "heavy_symmetric_top_frames", "rolling_disc", "atwood", "bouncing_ball", "pendulum_wall")


def bundled_spec_names() -> set[str]:
    return {p.stem for p in SPECS.glob("*.yaml")} | {p.stem for p in SPECS.glob("hybrid/*.yaml")}


def named_specs(case_id: str, names: set[str]) -> set[str]:
    """Those of `names` that a parametrized case's id names ("atwood-c",
    "hybrid/rimless_wheel", "sphere_on_turntable.yaml")."""
    tokens = {token.removeprefix("hybrid/").removesuffix(".yaml") for token in case_id.split("-")}
    return tokens & names


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    bundled = bundled_spec_names()
    for item in items:
        callspec = getattr(item, "callspec", None)
        if callspec is None:
            continue
        if any(name in callspec.id for name in HEAVY_SPECS) and "bicycle" not in item.module.__name__:
            item.add_marker(pytest.mark.slow)
        elif item.get_closest_marker("core_specs") and named_specs(callspec.id, bundled) \
                and not named_specs(callspec.id, set(CORE_SPECS)):
            item.add_marker(pytest.mark.slow)


def selected_specs(request, specs: list[Path]) -> list[Path]:
    """The core specs of `specs` and those a selected test of the requesting module names:
    a module fixture that builds every spec at once builds only what this run checks."""
    module = request.module.__name__
    ids = {item.callspec.id for item in request.session.items
           if item.module.__name__ == module and hasattr(item, "callspec")}
    return [p for p in specs if p.stem in CORE_SPECS or any(named_specs(case, {p.stem}) for case in ids)]
