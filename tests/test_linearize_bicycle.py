"""The benchmark bicycle linearized by lagcli against Meijaard et al. (2007).

J. P. Meijaard, J. M. Papadopoulos, A. Ruina, A. L. Schwab, "Linearized dynamics
equations for the balance and steer of a bicycle: a benchmark and review",
Proc. R. Soc. A 463 (2007): the roll-steer equations

    M q'' + v C1 q' + (g K0 + v^2 K2) q = f,    q = (phi, delta)

(their eq. 5.4 and the numerical values of Appendix A / Table 2 for the benchmark
parameters), eigenvalues at v = 0..10 m/s, weave and capsize speeds.

The linear model is taken about upright straight running: every coordinate 0, rear
wheel rate theta_R_dot = -v/rR, with the independent coordinates all but the pitch
and the independent speeds (roll, steer, rear wheel). Runs when
specs/benchmark_bicycle.yaml exists.
"""
from __future__ import annotations

import numpy as np
import pytest

from conftest import SPECS

SPEC = SPECS / "benchmark_bicycle.yaml"
pytestmark = pytest.mark.skipif(not SPEC.exists(), reason="specs/benchmark_bicycle.yaml not there yet")

INDEPENDENT = ["x", "y", "psi", "phi", "delta", "theta_R", "theta_F", "phi_dot", "delta_dot", "theta_R_dot"]
M_PAPER = np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]])
C1_PAPER = np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]])
K0_PAPER = np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]])
K2_PAPER = np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]])
WEAVE_SPEED = 4.29238253634111
CAPSIZE_SPEED = 6.02426201538837
G = 9.81


@pytest.fixture(scope="module")
def bicycle(derived):
    from lagcli.analysis.linearize import CompiledSystem
    from lagcli.analysis.operating_point import parse_assignments

    d = derived(str(SPEC))
    return CompiledSystem(d), parse_assignments(d, ["theta_R_dot=-v/rR"], "v")


def roll_steer(lm):
    """The (phi, delta) blocks of M, C and K."""
    speeds = [lm.speeds.index(s) for s in ("phi_dot", "delta_dot")]
    coordinates = [lm.coordinates.index(q) for q in ("phi", "delta")]
    return (lm.M[np.ix_(speeds, speeds)], lm.C[np.ix_(speeds, speeds)], lm.K[np.ix_(speeds, coordinates)])


def close(a, b, rel=1e-10):
    scale = np.max(np.abs(b))
    np.testing.assert_allclose(a, b, rtol=0, atol=rel * scale)


def test_mass_damping_and_stiffness_matrices(bicycle):
    from lagcli.analysis.linearize import linearize
    from lagcli.analysis.operating_point import evaluate

    system, at = bicycle
    d = system.derivation
    M0, C0, K_at_0 = roll_steer(linearize(system, evaluate(d, at, 0.0), INDEPENDENT))
    M3, C3, K_at_3 = roll_steer(linearize(system, evaluate(d, at, 3.0), INDEPENDENT))
    close(M0, M_PAPER)
    close(M3, M_PAPER)
    np.testing.assert_allclose(C0, 0, atol=1e-10 * np.max(np.abs(C1_PAPER)))   # v = 0: no C
    close(C3 / 3.0, C1_PAPER)
    close(K_at_0 / G, K0_PAPER)
    close((K_at_3 - K_at_0) / 9.0, K2_PAPER)


def test_eigenvalues_along_the_speed_against_the_papers_model(bicycle):
    from lagcli.analysis.sweep import sweep

    system, at = bicycle
    speeds = np.linspace(0, 10, 11)
    for point in sweep(system, at, speeds, INDEPENDENT):
        v = point.value
        K = G * K0_PAPER + v**2 * K2_PAPER
        A = np.block([[np.zeros((2, 2)), np.eye(2)],
                      [-np.linalg.solve(M_PAPER, K), -np.linalg.solve(M_PAPER, v * C1_PAPER)]])
        expected = np.sort_complex(np.linalg.eigvals(A))
        got = np.sort_complex(point.stability.eigenvalues)
        np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-9)


def test_weave_and_capsize_speeds(bicycle):
    from lagcli.analysis.sweep import critical_values, sweep

    system, at = bicycle
    points = sweep(system, at, np.linspace(0, 10, 101), INDEPENDENT)
    found = {(c.unstable_below, c.unstable_above): c.value for c in critical_values(system, at, points, INDEPENDENT)}
    assert found[(2, 0)] == pytest.approx(WEAVE_SPEED, abs=1e-9)
    assert found[(0, 1)] == pytest.approx(CAPSIZE_SPEED, abs=1e-9)
