"""`simulate --method variational` (docs/simulate.md, "The variational integrator"), checked
against results that do not come from it:

- order: the global error on a pendulum against scipy's DOP853 at rtol 1e-13 on the
  pendulum equation written here by hand shrinks 4x when dt halves (second order); the
  same on a damped oscillator against its closed form (discrete Lagrange-d'Alembert)
  and on a pendulum on a driven support (rheonomic) against DOP853 on lagcli's equations;
- long runs (10^4 steps here, 10^6 in the slow versions) of a pendulum, Kepler's orbit of
  eccentricity 0.6, the spherical pendulum and the bead on a spinning hoop: the energy
  (Jacobi integral) error stays bounded - its maximum over the last tenth of the run is
  not above that over the first tenth (up to 1%: the maximum of a periodic error sampled
  at the steps) - while DOP853 given as many function evaluations drifts (its error over
  the last tenth is more than twice that over the first); p_phi of the spherical
  pendulum stays constant to 1e-12 relative; the Cartesian pendulum's constraint residual
  stays below 1e-12;
- the C and Python backends agree to 1e-10 on the same steps; the generated module's
  `simulate(method="variational")` gives the backend's rows;
- the generated Jacobian is the derivative of the generated momenta (central finite
  differences);
- a nonholonomic spec is refused naming its constraint (exit 2), a Newton failure ends
  the run with exit 1, the time and the hint to reduce dt.
"""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.integrate import solve_ivp

import lagcli
from lagcli.cli import cli
from lagcli.errors import UsageError

from conftest import ROOT, SPECS

needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
KEPLER = ROOT / "tests" / "data" / "kepler.yaml"
PENDULUM = """
name: pendulum
coordinates: [theta]
parameters: {m: 1.0, l: 1.0, g: 9.81}
gravity: [0, -g]
particles:
  P: {mass: m, position: [l*sin(theta), -l*cos(theta)]}
initial: {theta: 1.0, theta_dot: 0.0}
"""
DAMPED = """
name: damped
coordinates: [x]
parameters: {m: 2.0, k: 8.0, c: 0.4}
potential: k*x**2/2
kinetic: m*x_dot**2/2
generalized_forces: {x: -c*x_dot}
initial: {x: 1.0, x_dot: 0.0}
"""


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def final_error(system, dt, reference, t_end=2.0, backend="python", column="theta"):
    traj = system.simulate(t_end=t_end, dt=dt, method="variational", backend=backend)
    return abs(traj[column][-1] - reference)


def assert_second_order(errors):
    ratios = [a / b for a, b in zip(errors, errors[1:])]
    assert all(3.6 < r < 4.4 for r in ratios), (errors, ratios)


def test_second_order_on_a_pendulum():
    g = 9.81
    ref = solve_ivp(lambda t, y: [y[1], -g * np.sin(y[0])], (0, 2.0), [1.0, 0.0], method="DOP853",
                    rtol=1e-13, atol=1e-13).y[0, -1]
    system = lagcli.load(PENDULUM)
    assert_second_order([final_error(system, dt, ref) for dt in (0.02, 0.01, 0.005)])


def test_second_order_with_a_damper_against_the_closed_form():
    """m x'' + c x' + k x = 0: x = e^(-zeta w t) (cos(wd t) + zeta w / wd sin(wd t))."""
    m, k, c, t = 2.0, 8.0, 0.4, 3.0
    w = np.sqrt(k / m)
    zeta = c / (2 * np.sqrt(k * m))
    wd = w * np.sqrt(1 - zeta ** 2)
    exact = np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta * w / wd * np.sin(wd * t))
    system = lagcli.load(DAMPED)
    assert_second_order([final_error(system, dt, exact, t, column="x") for dt in (0.04, 0.02, 0.01)])


def test_second_order_on_a_rheonomic_spec():
    """The pendulum on a support driven as a cos(w t): against DOP853 at rtol 1e-12 on
    lagcli's equations (a second method)."""
    system = lagcli.load(Path(SPECS / "ex19_oscillating_support.yaml"))
    ref = system.simulate(t_end=0.5, dt=0.5, rtol=1e-12, atol=1e-12, backend="python")["theta"][-1]
    assert_second_order([final_error(system, dt, ref, 0.5) for dt in (0.002, 0.001, 0.0005)])


# --- long runs: bounded energy error against DOP853's drift ----------------------------

LONG_RUNS = [(PENDULUM, 0.05), (KEPLER, 0.05), (SPECS / "spherical_pendulum.yaml", 0.05),
             (SPECS / "bead_on_spinning_hoop.yaml", 0.05)]
LONG_IDS = ["pendulum", "kepler", "spherical_pendulum", "bead_on_spinning_hoop"]


def load(source):
    return lagcli.load(Path(source) if isinstance(source, Path) else source)


def bench(system, *args) -> dict[str, float]:
    """The compiled driver's --bench-integration line (steps, iterations or nfev)."""
    driver = system.program("c", "variational")
    done = subprocess.run([driver.binary, *args, "--max-steps", "1000000000", "--bench-integration", "1"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return {k: float(v) for k, v in re.findall(r"(\w+) ([0-9.e+-]+)", done.stderr)}


def evaluations(system, t_end, dt) -> float:
    """Model evaluations of a variational run: per step the predictor's accelerations,
    the momenta after Newton and the Legendre transform (3), and per Newton iteration
    the momenta and their Jacobian (2)."""
    b = bench(system, "--method", "variational", "--t-end", repr(t_end), "--dt", repr(dt))
    return 2 * b["iterations"] + 3 * b["steps"]


def dop853_tolerance(system, t_end, target) -> float:
    """The rtol = atol (10^(-k/2)) at which DOP853's nfev is closest to `target`."""
    def nfev(r):
        return bench(system, "--method", "DOP853", "--rtol", repr(r), "--atol", repr(r),
                     "--t-end", repr(t_end), "--dt", repr(t_end))["nfev"]
    candidates = [10 ** (-k / 2) for k in range(6, 29)]
    return min(candidates, key=lambda r: abs(np.log(nfev(r) / target)))


def error_by_tenth(traj) -> tuple[float, float]:
    """max |E - E(0)| over the first and the last tenth of the rows (E: the Jacobi integral)."""
    E = traj["jacobi"]
    err = np.abs(E - E[0])
    tenth = len(err) // 10
    return err[1:tenth + 1].max(), err[-tenth:].max()


def long_run(source, dt, steps, steps_per_row):
    system = load(source)
    t_end = dt * steps
    traj = system.simulate(t_end=t_end, dt=dt * steps_per_row, method="variational", backend="c",
                           steps_per_row=steps_per_row)
    assert traj.failure is None and abs(traj.t[-1] - t_end) < 1e-9
    first, last = error_by_tenth(traj)
    assert last <= 1.01 * first, (first, last)
    rtol = dop853_tolerance(system, t_end, evaluations(system, t_end, dt))
    dop = system.simulate(t_end=t_end, dt=dt * steps_per_row, rtol=rtol, atol=rtol, backend="c")
    dop_first, dop_last = error_by_tenth(dop)
    assert dop_last > 2 * dop_first, (rtol, dop_first, dop_last)
    return traj


def check_spherical_momentum(traj):
    p = traj["p_phi"]
    assert np.max(np.abs(p - p[0])) <= 1e-12 * abs(p[0])


@needs_cc
@pytest.mark.parametrize("source, dt", LONG_RUNS, ids=LONG_IDS)
def test_energy_error_bounded_over_1e4_steps(source, dt):
    traj = long_run(source, dt, 10_000, 1)
    if "p_phi" in traj.names:
        check_spherical_momentum(traj)


@pytest.mark.slow
@needs_cc
@pytest.mark.parametrize("source, dt", LONG_RUNS, ids=LONG_IDS)
def test_energy_error_bounded_over_1e6_steps(source, dt):
    traj = long_run(source, dt, 1_000_000, 100)
    if "p_phi" in traj.names:
        check_spherical_momentum(traj)


@needs_cc
@pytest.mark.parametrize("steps, per_row", [(10_000, 1), pytest.param(1_000_000, 100, marks=pytest.mark.slow)])
def test_cartesian_pendulum_keeps_its_constraint(steps, per_row):
    """|x^2 + y^2 - l^2| and |x x' + y y'| (the residual column) below 1e-12 at every row;
    the multipliers are those of the exact equations (the rod's tension: finite, nonzero)."""
    system = load(SPECS / "cartesian_pendulum.yaml")
    traj = system.simulate(t_end=0.02 * steps, dt=0.02 * per_row, method="variational", backend="c",
                           steps_per_row=per_row)
    assert traj.failure is None
    assert traj["constraint_residual"].max() < 1e-12
    x, y, l = traj["x"], traj["y"], system.layout.parameter_defaults["l"]
    assert np.max(np.abs(x ** 2 + y ** 2 - l ** 2)) < 1e-12
    first, last = error_by_tenth(traj)
    assert last <= 1.01 * first


# --- the two backends, the generated module -----------------------------------------------

AGREEMENT = [(PENDULUM, {}), (KEPLER, {}), (SPECS / "spherical_pendulum.yaml", {}),
             (SPECS / "cartesian_pendulum.yaml", {}), (SPECS / "bead_on_spinning_hoop.yaml", {}),
             (SPECS / "ex19_oscillating_support.yaml", {}), (DAMPED, {}),
             (SPECS / "cart_pole.yaml", {"F": 0.3}), (SPECS / "double_pendulum.yaml", {})]


@needs_cc
@pytest.mark.parametrize("source, inputs", AGREEMENT,
                         ids=["pendulum", "kepler", "spherical", "cartesian", "hoop", "support", "damped",
                              "cart_pole", "double_pendulum"])
def test_c_and_python_agree(source, inputs):
    system = load(source)
    runs = [system.simulate(t_end=5.0, dt=0.005, method="variational", backend=b, inputs=inputs)
            for b in ("python", "c")]
    p, c = (run.data for run in runs)
    assert p.shape == c.shape == (1001, len(system.layout.header))
    scale = np.maximum(1.0, np.abs(p))
    assert np.max(np.abs(p - c) / scale) <= 1e-10


def test_generated_module_simulate_gives_the_backend_rows(tmp_path):
    system = load(SPECS / "spherical_pendulum.yaml")
    (source,) = system.generate("python").values()
    namespace: dict = {}
    exec(compile(source, "spherical_pendulum.py", "exec"), namespace)
    header, rows = namespace["simulate"](t_end=1.0, dt=0.02, method="variational", steps_per_row=2)
    traj = system.simulate(t_end=1.0, dt=0.02, method="variational", steps_per_row=2)
    assert header == list(system.layout.header)
    assert np.array_equal(rows, traj.data)


def test_steps_per_row_is_the_step():
    """4 steps per row of 0.04 are the steps of dt = 0.01 (to rounding of the times)."""
    system = lagcli.load(PENDULUM)
    fine = system.simulate(t_end=1.0, dt=0.01, method="variational")
    coarse = system.simulate(t_end=1.0, dt=0.04, method="variational", steps_per_row=4)
    assert np.max(np.abs(fine.data[::4] - coarse.data)) < 1e-12


@pytest.mark.parametrize("spec", ["double_pendulum", "cart_pole"])
def test_jacobian_is_the_derivative_of_the_momenta(spec, rng):
    """dg/dq, dg/dq', df/dq, df/dq' of the generated module against central differences of
    its g and f (cart_pole: with its input force; plus a velocity-dependent force below)."""
    check_jacobian(load(SPECS / f"{spec}.yaml"), rng)


def test_jacobian_with_a_damper(rng):
    from test_damped_spring_pendulum import SPHERICAL

    check_jacobian(lagcli.load(SPHERICAL), rng)


def check_jacobian(system, rng):
    (source,) = system.generate("python").values()
    ns: dict = {}
    exec(compile(source, "module.py", "exec"), ns)
    n = len(system.layout.coordinates)
    model = ns["variational_model"]()
    for _ in range(3):
        q, v, t, eps = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n), rng.uniform(0, 1), 1e-6
        gq, gv, fq, fv = model.jacobian(t, q, v)
        for j in range(n):
            e = np.eye(n)[j] * eps
            for analytic, shift in ((np.column_stack([gq[:, j], fq[:, j]]), (e, 0 * e)),
                                    (np.column_stack([gv[:, j], fv[:, j]]), (0 * e, e))):
                plus = np.column_stack(model.momenta(t, q + shift[0], v + shift[1]))
                minus = np.column_stack(model.momenta(t, q - shift[0], v - shift[1]))
                numeric = (plus - minus) / (2 * eps)
                assert np.allclose(analytic, numeric, rtol=1e-6, atol=1e-6)


# --- refusals and failures ----------------------------------------------------------------

def invoke(*args):
    return CliRunner().invoke(cli, ["simulate", *map(str, args)])


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_cc)])
def test_nonholonomic_spec_is_refused_naming_the_constraint(backend):
    spec = SPECS / "chaplygin_sled.yaml"
    result = invoke(spec, "--method", "variational", "--backend", backend)
    assert result.exit_code == 2
    assert "constraint 'knife'" in result.stderr and "nonholonomic" in result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""
    with pytest.raises(UsageError, match="knife"):
        lagcli.load(spec).simulate(method="variational")


@needs_cc
def test_nonholonomic_refusal_on_the_warm_path_names_the_constraint():
    spec = SPECS / "chaplygin_sled.yaml"
    assert invoke(spec, "--t-end", "0.1").exit_code == 0            # the driver is now cached
    result = invoke(spec, "--method", "variational")
    assert result.exit_code == 2 and f"{spec}: --method variational: constraint 'knife'" in result.stderr


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_cc)])
def test_newton_failure_ends_the_run_with_the_time_and_a_hint(backend):
    result = invoke(SPECS / "double_pendulum.yaml", "--method", "variational", "--dt", "2", "--t-end", "4",
                    "--backend", backend)
    assert result.exit_code == 1
    assert "integration failed at t = 0:" in result.stderr and "reduce dt" in result.stderr
    assert result.stdout.count("\n") == 2                              # the header and the row at t = 0


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_cc)])
def test_end_of_run_line_gives_the_drift_of_each_integral(backend):
    result = invoke(SPECS / "spherical_pendulum.yaml", "--method", "variational", "--t-end", "1",
                    "--backend", backend)
    assert result.exit_code == 0
    line = result.stderr.strip()
    assert line.startswith("variational: 101 rows, step 0.01; drift of the integrals")
    jacobi, p_phi = (float(re.search(rf"{name} ([0-9.e+-]+)", line).group(1)) for name in ("jacobi", "p_phi"))
    assert 0 < jacobi < 1e-3 and p_phi < 1e-14
    rheonomic = invoke(SPECS / "ex19_oscillating_support.yaml", "--method", "variational", "--t-end", "0.1",
                       "--backend", backend)
    assert rheonomic.exit_code == 0 and "energy is not an invariant" in rheonomic.stderr


def test_steps_per_row_needs_the_variational_method():
    result = invoke(SPECS / "double_pendulum.yaml", "--steps-per-row", "2")
    assert result.exit_code == 2 and "--steps-per-row" in result.stderr


def test_newton_constants_are_the_same_in_c_and_python():
    from lagcli.runtime import variational

    text = (ROOT / "lagcli" / "runtime" / "c" / "lagcli_variational.h").read_text()
    value = dict(re.findall(r"#define LAGCLI_(NEWTON_\w+) (\S+)", text))
    assert float(value["NEWTON_TOLERANCE"]) == variational.NEWTON_TOLERANCE
    assert int(value["NEWTON_MAX_ITERATIONS"]) == variational.NEWTON_MAX_ITERATIONS


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_cc)])
def test_the_step_budget_bounds_a_variational_run(backend):
    result = invoke(SPECS / "double_pendulum.yaml", "--method", "variational", "--t-end", "1",
                    "--steps-per-row", "10", "--max-steps", "25", "--backend", backend)
    assert result.exit_code == 1
    assert "integration failed at t = 0.02: the integration reached its bound of 25 steps" in result.stderr
    assert result.stdout.count("\n") == 4                              # the header and rows 0, 0.01, 0.02


def test_input_laws_are_refused():
    result = invoke(SPECS / "cart_pole.yaml", "--method", "variational", "--input", "F=-x")
    assert result.exit_code == 2 and "does not run events or input laws" in result.stderr
