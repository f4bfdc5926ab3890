"""The C integrator (lagcli/runtime/c/lagcli_ode.c) against scipy.

It re-implements scipy.integrate.solve_ivp's RK45 and DOP853: the
same tableaus, initial step, error norms, step-size control and dense output.
So for the same rtol/atol it must take the same accepted steps, spend the same
number of rhs evaluations (nfev) and print the same values at t_eval up to
rounding.  The harness (tests/c_harness/harness.c) includes the
shipped source and is compiled with the contract's strict flags.

Observed with scipy 1.17 (harmonic, Van der Pol, Lorenz; both methods;
rtol 1e-12 .. 1e-3): nfev equal in every case; outputs equal to 1e-13
relative or better in most cases, and up to 2e-10 (rtol 1e-9) or 2e-9
(rtol 1e-3) in a few.  Not bit-identical, because numpy's dot products
(OpenBLAS: fused multiply-add, its own summation order) round differently
from the C loops.  That is harmless except where the error estimate itself
is rounding noise: in the first, tiny steps (h from select_initial_step,
true local error ~ h^8 below eps, or a state component starting at 0 with a
1e-12 atol) the two estimates differ by up to tens of percent, the next step
sizes differ slightly, and from there each code follows its own, equally
valid step sequence.  Outputs then differ by a fraction of the global error,
never by more than the tolerance.  Hence CLOSE below; Lorenz from (1, 1, 1)
has no such noisy step and is held to 1e-11.
"""

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.integrate._ivp import dop853_coefficients
from scipy.integrate._ivp.rk import RK45

ROOT = Path(__file__).resolve().parent.parent
CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]
CC = shutil.which("cc")

pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler (cc)")

# Right-hand sides identical, operation for operation, to the harness's.
OMEGA, VDP_MU, L_SIGMA, L_RHO, L_BETA = 2.0, 1.0, 10.0, 28.0, 8 / 3
SYSTEMS = {
    "harmonic": (lambda t, y: [y[1], -(OMEGA * OMEGA) * y[0]], [1.0, 0.0]),
    "vdp": (lambda t, y: [y[1], VDP_MU * (1 - y[0] * y[0]) * y[1] - y[0]], [2.0, 0.0]),
    "lorenz": (
        lambda t, y: [
            L_SIGMA * (y[1] - y[0]),
            y[0] * (L_RHO - y[2]) - y[1],
            y[0] * y[1] - L_BETA * y[2],
        ],
        [1.0, 1.0, 1.0],
    ),
    "blowup": (lambda t, y: [y[0] * y[0]], [1.0]),
}
METHODS = ["RK45", "DOP853"]
CLOSE = 1e-8  # max relative difference from scipy allowed; see the module docstring


RUNTIME = ROOT / "lagcli" / "runtime" / "c"


def compile_harness(directory):
    exe = directory / "harness"
    proc = subprocess.run(
        [CC, *CFLAGS, "-I", str(RUNTIME), str(ROOT / "tests" / "c_harness" / "harness.c"),
         "-o", str(exe), "-lm"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    return exe


@pytest.fixture(scope="module")
def harness(tmp_path_factory):
    return compile_harness(tmp_path_factory.mktemp("c_integrator"))


@pytest.fixture(scope="module")
def codes():
    """Return codes, read from the integrator's header so the test cannot drift."""
    text = (RUNTIME / "lagcli_ode.h").read_text()
    return {name: int(value) for name, value in re.findall(r"LAGCLI_ODE_(\w+) = (\d+)", text)}


class Run:
    def __init__(self, stdout):
        lines = stdout.strip().splitlines()
        rc, nfev, n_accepted, n_rejected, t = lines[-1].split()[1:]
        self.rc, self.nfev = int(rc), int(nfev)
        self.n_accepted, self.n_rejected, self.t = int(n_accepted), int(n_rejected), float(t)
        rows = np.array([[float(v) for v in line.split()] for line in lines[:-1]])
        self.times = rows[:, 0] if len(rows) else np.empty(0)
        self.y = rows[:, 1:].T if len(rows) else np.empty((0, 0))


def run(harness, system, method, t_eval, t0=0.0, t_end=None, rtol=1e-9, atol=1e-12,
        max_step="inf", stop_after=0):
    t_end = t_eval[-1] if t_end is None else t_end
    stdin = f"{len(t_eval)}\n" + "\n".join(repr(float(t)) for t in t_eval) + "\n"
    args = [system, method, rtol, atol, t0, t_end, max_step, stop_after]
    proc = subprocess.run(
        [str(harness), "run", *map(str, args)], input=stdin, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    return Run(proc.stdout)


def output_times(t_end, dt, t0=0.0):
    """0, dt, ..., t_end as the driver makes them (i * dt, last one t_end)."""
    n = int(round((t_end - t0) / dt))
    times = t0 + np.arange(n + 1) * dt
    times[-1] = t_end
    return times


def assert_matches_scipy(result, system, method, t_eval, rtol, atol, t0=0.0, t_end=None,
                         max_step=np.inf, close=CLOSE):
    fun, y0 = SYSTEMS[system]
    t_end = t_eval[-1] if t_end is None else t_end
    ref = solve_ivp(fun, (t0, t_end), y0, method=method, t_eval=t_eval, rtol=rtol,
                    atol=atol, max_step=max_step)
    # Same steps: the same number of rhs evaluations, to the unit.
    assert result.nfev == ref.nfev
    assert result.times.tolist() == ref.t.tolist()
    scale = np.maximum(1.0, np.abs(ref.y))
    assert np.max(np.abs(result.y - ref.y) / scale, initial=0.0) < close
    return ref


def test_coefficients_are_scipys_to_the_bit(harness):
    out = subprocess.run([str(harness), "coeffs"], capture_output=True, text=True, check=True)
    tables = {}
    for line in out.stdout.splitlines():
        name, *values = line.split()
        tables[name.removeprefix("LAGCLI_ODE_")] = np.array([float(v) for v in values])
    d = dop853_coefficients
    expected = {
        "RK45_A": np.pad(RK45.A, ((0, 0), (0, 16 - RK45.A.shape[1]))),
        "RK45_B": RK45.B,
        "RK45_C": RK45.C,
        "RK45_E": RK45.E,
        "RK45_P": RK45.P,
        "DOP853_A": d.A,  # 16 x 16, row 12 = b, rows 13-15 the dense-output stages
        "DOP853_C": d.C,
        "DOP853_E3": d.E3,
        "DOP853_E5": d.E5,
        "DOP853_D": d.D,
    }
    assert set(tables) == set(expected)
    for name, value in expected.items():
        assert tables[name].tolist() == np.ravel(value).tolist(), name


@pytest.mark.parametrize("method", METHODS)
def test_harmonic_oscillator_matches_closed_form(harness, codes, method):
    t_eval = output_times(10.0, 0.01)
    result = run(harness, "harmonic", method, t_eval)
    assert result.rc == codes["OK"]
    assert result.t == 10.0
    exact = np.array([np.cos(OMEGA * t_eval), -OMEGA * np.sin(OMEGA * t_eval)])
    # Global error over ~3 periods at rtol 1e-9, atol 1e-12: observed 4.3e-9 (both).
    assert np.max(np.abs(result.y - exact)) < 2e-8
    assert_matches_scipy(result, "harmonic", method, t_eval, 1e-9, 1e-12)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("rtol, atol", [(1e-9, 1e-12), (1e-6, 1e-9), (1e-3, 1e-6)])
def test_van_der_pol_matches_scipy(harness, method, rtol, atol):
    t_eval = output_times(10.0, 0.05)
    result = run(harness, "vdp", method, t_eval, rtol=rtol, atol=atol)
    assert result.rc == 0
    assert_matches_scipy(result, "vdp", method, t_eval, rtol, atol)


@pytest.mark.parametrize("method", METHODS)
def test_lorenz_matches_scipy(harness, method):
    t_eval = output_times(2.0, 0.01)
    result = run(harness, "lorenz", method, t_eval, rtol=1e-8, atol=1e-10)
    assert result.rc == 0
    assert result.n_rejected > 0  # the rejection branch of the control is exercised
    assert_matches_scipy(result, "lorenz", method, t_eval, 1e-8, 1e-10, close=1e-11)


@pytest.mark.parametrize("method", METHODS)
def test_max_step_and_t_eval_off_the_end(harness, method):
    # t_end = 3.03 is not an output time; max_step limits every step.
    t_eval = output_times(3.0, 0.1)
    result = run(harness, "vdp", method, t_eval, t_end=3.03, max_step=0.07)
    assert result.rc == 0 and result.t == 3.03
    assert result.n_accepted >= 3.03 / 0.07
    assert_matches_scipy(result, "vdp", method, t_eval, 1e-9, 1e-12, t_end=3.03,
                         max_step=0.07)


@pytest.mark.parametrize("method", METHODS)
def test_backward_integration_matches_scipy(harness, method):
    t_eval = output_times(0.0, -0.1, t0=4.0)
    result = run(harness, "vdp", method, t_eval, t0=4.0)
    assert result.rc == 0 and result.t == 0.0
    assert_matches_scipy(result, "vdp", method, t_eval, 1e-9, 1e-12, t0=4.0)


@pytest.mark.parametrize("method", METHODS)
def test_blow_up_fails_like_scipy_near_the_singularity(harness, codes, method):
    # y' = y^2, y(0) = 1 blows up at t = 1; scipy stops with "Required step size
    # is less than spacing between numbers" (status -1) there.
    t_eval = output_times(2.0, 0.01)
    result = run(harness, "blowup", method, t_eval, rtol=1e-9, atol=1e-12)
    assert result.rc == codes["ERR_STEP_TOO_SMALL"]
    assert abs(result.t - 1.0) < 1e-6
    ref = solve_ivp(SYSTEMS["blowup"][0], (0.0, 2.0), [1.0], method=method, t_eval=t_eval,
                    rtol=1e-9, atol=1e-12)
    assert ref.status == -1
    assert result.nfev == ref.nfev
    assert result.times.tolist() == ref.t.tolist()  # outputs before the failure
    # Away from the singularity (at t = 1 the value itself is ill-conditioned).
    before = ref.t < 1.0
    assert np.allclose(result.y[:, before], ref.y[:, before], rtol=1e-10, atol=0)


@pytest.mark.parametrize("method", METHODS)
def test_rhs_failure_is_reported_with_its_time(harness, codes, method):
    result = run(harness, "rhsfail", method, output_times(2.0, 0.1))
    assert result.rc == codes["ERR_RHS"]
    assert 0.0 < result.t <= 0.5
    assert result.times[-1] <= result.t


@pytest.mark.parametrize("method", METHODS)
def test_nan_rhs_is_reported_as_non_finite(harness, codes, method):
    # Steps reaching past t = 0.5 see nan, are rejected as scipy would, and
    # shrink until too small; the fragment then names the cause.
    result = run(harness, "nanrhs", method, output_times(2.0, 0.1))
    assert result.rc == codes["ERR_NONFINITE"]
    assert 0.4 < result.t <= 0.5


@pytest.mark.parametrize("method", METHODS)
def test_output_callback_can_stop_the_run(harness, codes, method):
    result = run(harness, "harmonic", method, output_times(10.0, 0.01), stop_after=5)
    assert result.rc == codes["INTERRUPTED"]
    assert result.times.tolist() == output_times(10.0, 0.01)[:5].tolist()


def test_empty_interval_outputs_the_initial_state(harness, codes):
    result = run(harness, "vdp", "DOP853", [0.0, 0.0], t_end=0.0)
    assert result.rc == codes["OK"]
    assert result.y.T.tolist() == [[2.0, 0.0], [2.0, 0.0]]
    assert result.nfev == 1  # f(t0, y0), as scipy


@pytest.mark.parametrize(
    "method, times, kwargs",
    [
        ("rk45", [0.0, 1.0], {}),  # scipy's names are case-sensitive
        ("Radau", [0.0, 1.0], {}),
        ("RK45", [0.0, 2.0, 1.0], {}),  # not increasing
        ("RK45", [0.0, 1.5], {"t_end": 1.0}),  # outside the interval
        ("RK45", [0.0, 1.0], {"max_step": 0.0}),
        ("RK45", [0.0, 1.0], {"atol": -1.0}),
        ("RK45", [0.0, 1.0], {"rtol": "nan"}),
    ],
)
def test_invalid_arguments(harness, codes, method, times, kwargs):
    result = run(harness, "harmonic", method, times, **kwargs)
    assert result.rc == codes["ERR_ARGS"]
    assert result.nfev == 0 and len(result.times) == 0
