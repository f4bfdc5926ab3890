"""The benchmark bicycle (specs/benchmark_bicycle.yaml) against the published numbers of
Meijaard, Papadopoulos, Ruina & Schwab, Proc. R. Soc. A 463 (2007).

Everything numeric comes from lagcli's derivation of the full nonlinear model (8
coordinates, 1 holonomic and 4 nonholonomic constraints): its M, F, the constraint
matrix A and bias, at states made consistent here. The linearization is this test's
own, independent of any lagcli analysis:

- a state near upright straight running is set by the independent quantities
  (roll phi, steer delta, their rates and the rear wheel rate theta_R' = -v/rR); the
  pitch theta solves the holonomic row by Newton, the dependent speeds (x', y', psi',
  theta', theta_F') solve A q' = 0, and the augmented system
  [[M, -A^T], [A, 0]] [q''; lambda] = [F + T; bias] with a roll torque T_phi and a
  steer torque T_delta on the phi and delta equations gives (phi'', delta'');
- its derivatives at the upright state by the complex step (f'(0) = Im f(ih)/h,
  exact to rounding: every function involved is analytic), so the linearized
  equations M x'' + v C1 x' + (g K0 + v^2 K2) x = T follow: M^-1 from d/dT,
  g K0 + v^2 K2 and v C1 from d/dx and d/dx'. (The forward speed equation decouples
  at first order by the bicycle's lateral symmetry.)

They must agree with the paper's eq. (5.4)/Table 2 matrices to 1e-10, its
eigenvalues at v = 0, 4, 5, 10 m/s and its weave and capsize speeds. The upright
straight run is an exact solution whose only constraint force is the front wheel's
normal force from static moment balance, and a simulated second keeps the
constraints and the energy.
"""
from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner
from scipy.optimize import brentq

from lagcli.cli import cli
from lagcli.run.rows import parse_csv

from conftest import spec_path

pytestmark = pytest.mark.slow          # deriving the bicycle takes ~20 s of CPU

SPEC = spec_path("benchmark_bicycle")
G = 9.81
RR, RF = 0.3, 0.35

# Meijaard et al. (2007), eq. (5.4) and Table 2.
PAPER_M = [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]
PAPER_C1 = [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]
PAPER_K0 = [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]
PAPER_K2 = [[0.0, 76.59734589573222], [0.0, 2.65431523794604]]
PAPER_EIGENVALUES = {
    0: [-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393],
    4: [-12.15861426576447, -1.42944427361326,
        0.41325331521125 - 3.07910818603206j, 0.41325331521125 + 3.07910818603206j],
    5: [-14.07838969279822, -0.32286642900409,
        -0.77534188219585 - 4.46486771378823j, -0.77534188219585 + 4.46486771378823j],
    10: [-24.62459635017404, 0.16105338653172,
         -3.72016840437287 - 10.90681139476287j, -3.72016840437287 + 10.90681139476287j],
}
PAPER_WEAVE_SPEED = 4.29238253634111
PAPER_CAPSIZE_SPEED = 6.02426201538837

# coordinate indices: x, y, psi, phi, theta, delta, theta_R, theta_F
PHI, THETA, DELTA, THETA_R, THETA_F = 3, 4, 5, 6, 7
DEPENDENT_SPEEDS = [0, 1, 2, THETA, THETA_F]
INDEPENDENT_SPEEDS = [PHI, DELTA, THETA_R]


class Bicycle:
    """lagcli's derived M, F, A, bias as numpy functions of (q, q', g), every other
    parameter at its paper value; complex arguments welcome."""

    def __init__(self, d):
        model = d.model
        self.q, self.qd = list(model.q), list(model.qd)
        self.g = next(p.symbol for p in model.parameters if p.symbol.name == "g")
        self.values = {p.symbol: sp.Float(p.value) for p in model.parameters if p.symbol != self.g}
        self.mass, self.forcing = self._numeric(d.mass_matrix), self._numeric(d.forcing)
        self.A, self.bias = self._numeric(d.constraint_matrix), self._numeric(d.constraint_bias)
        ground = next(row.expr for row in d.constraints if row.kind == "holonomic")
        self.ground = self._numeric([ground])
        self.ground_slope = self._numeric([sp.diff(ground, self.q[THETA])])
        self.multipliers = [str(m) for m in d.multipliers]

    def _numeric(self, expr):
        matrix = sp.Matrix(expr).xreplace(self.values)
        return sp.lambdify([self.q, self.qd, self.g], matrix, modules="numpy", cse=True)

    def state(self, phi, delta, phi_dot, delta_dot, v, g):
        """q and q' on the constraints: pitch by Newton, dependent speeds from A q' = 0."""
        q = np.zeros(8, dtype=complex)
        q[PHI], q[DELTA] = phi, delta
        for _ in range(30):
            step = self.ground(q, q, g)[0, 0] / self.ground_slope(q, q, g)[0, 0]
            q[THETA] -= step
            if abs(step) < 1e-300:
                break
        qd = np.zeros(8, dtype=complex)
        qd[PHI], qd[DELTA], qd[THETA_R] = phi_dot, delta_dot, -v / RR
        A = self.A(q, qd, g)
        qd[DEPENDENT_SPEEDS] = np.linalg.solve(A[:, DEPENDENT_SPEEDS], -A[:, INDEPENDENT_SPEEDS] @ qd[INDEPENDENT_SPEEDS])
        return q, qd

    def accelerations(self, q, qd, g, torques=(0.0, 0.0)):
        """(q'', lambda) from [[M, -A^T], [A, 0]] [q''; lambda] = [F + T; bias]."""
        M, A = self.mass(q, qd, g), self.A(q, qd, g)
        F = self.forcing(q, qd, g).ravel().astype(complex)
        F[PHI] += torques[0]
        F[DELTA] += torques[1]
        m = A.shape[0]
        K = np.block([[M, -A.T], [A, np.zeros((m, m))]])
        sol = np.linalg.solve(K, np.concatenate([F, self.bias(q, qd, g).ravel()]))
        return sol[:8], sol[8:]

    def lateral(self, x, v, g):
        """(phi'', delta'') at x = (phi, delta, phi', delta', T_phi, T_delta)."""
        q, qd = self.state(*x[:4], v, g)
        qdd, _ = self.accelerations(q, qd, g, x[4:])
        return qdd[[PHI, DELTA]]

    def jacobian(self, v, g, h=1e-30):
        """d(phi'', delta'')/d(phi, delta, phi', delta', T_phi, T_delta) at upright
        straight running, by the complex step."""
        J = np.zeros((2, 6))
        for k in range(6):
            x = np.zeros(6, dtype=complex)
            x[k] = 1j * h
            J[:, k] = self.lateral(x, v, g).imag / h
        return J

    def state_matrix(self, v, g=G):
        J = self.jacobian(v, g)
        return np.block([[np.zeros((2, 2)), np.eye(2)], [J[:, 0:2], J[:, 2:4]]])


@pytest.fixture(scope="module")
def bicycle(derived):
    return Bicycle(derived("benchmark_bicycle"))


@pytest.fixture(scope="module")
def linearized(bicycle):
    """(M, C1, K0, K2) from the engine's nonlinear equations."""
    still = bicycle.jacobian(0.0, G)               # v = 0: gravity only
    M = np.linalg.inv(still[:, 4:6])
    K0 = -M @ still[:, 0:2] / G
    moving = bicycle.jacobian(1.0, 0.0)            # v = 1, g = 0: the speed terms only
    M_moving = np.linalg.inv(moving[:, 4:6])
    return M, -M_moving @ moving[:, 2:4], K0, -M_moving @ moving[:, 0:2], M_moving


def test_check_counts():
    result = CliRunner().invoke(cli, ["check", str(SPEC)])
    assert result.exit_code == 0, result.output
    assert "(n = 8)" in result.stdout
    assert "1 holonomic, 4 nonholonomic" in result.stdout
    assert "DOF         : 3" in result.stdout


def test_derivation_counts(derived):
    d = derived("benchmark_bicycle")
    kinds = [row.kind for row in d.constraints]
    assert (len(d.model.q), kinds.count("holonomic"), kinds.count("nonholonomic"), d.dof) == (8, 1, 4, 3)
    assert d.scleronomic and d.energy_is_jacobi


@pytest.mark.parametrize("v", [0.0, 1.0, 5.0, 10.0])
def test_upright_straight_running_is_a_solution(bicycle, v):
    """q = 0, x' = v, wheels rolling: on the constraints, every q'' = 0, and the only
    constraint force is the front normal force N_F of static balance about the rear
    contact, N_F w = g (mB xB + mH xH + mF w) (z down: the multiplier is -N_F)."""
    q = np.zeros(8)
    qd = np.zeros(8)
    qd[0], qd[THETA_R], qd[THETA_F] = v, -v / RR, -v / RF
    assert np.max(np.abs(bicycle.A(q, qd, G) @ qd)) < 1e-12
    qdd, lam = bicycle.accelerations(q, qd, G)
    assert np.max(np.abs(qdd)) < 1e-12
    normal = G * (85 * 0.3 + 4 * 0.9 + 3 * 1.02) / 1.02
    expected = {"lambda_front_ground": -normal}
    for name, value in zip(bicycle.multipliers, lam.real):
        assert value == pytest.approx(expected.get(name, 0.0), rel=1e-12, abs=1e-9), name


def _assert_matches(ours, paper, what):
    paper = np.array(paper)
    scale = np.max(np.abs(paper))
    np.testing.assert_allclose(ours, paper, rtol=1e-10, atol=1e-10 * scale, err_msg=what)


def test_linearized_matrices_match_the_paper(linearized):
    M, C1, K0, K2, M_moving = linearized
    _assert_matches(M, PAPER_M, "M")
    _assert_matches(M_moving, PAPER_M, "M (at 1 m/s)")
    _assert_matches(C1, PAPER_C1, "C1")
    _assert_matches(K0, PAPER_K0, "K0")
    _assert_matches(K2, PAPER_K2, "K2")


def test_linearization_is_quadratic_in_speed(bicycle, linearized):
    """At v = 5 with gravity the state matrix is the one of M, v C1, g K0 + v^2 K2."""
    M, C1, K0, K2, _ = linearized
    v = 5.0
    expected = np.block([[np.zeros((2, 2)), np.eye(2)],
                         [-np.linalg.solve(M, G * K0 + v**2 * K2), -np.linalg.solve(M, v * C1)]])
    np.testing.assert_allclose(bicycle.state_matrix(v), expected, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("v", sorted(PAPER_EIGENVALUES))
def test_eigenvalues_match_table_2(bicycle, v):
    ours = np.sort_complex(np.linalg.eigvals(bicycle.state_matrix(float(v))))
    np.testing.assert_allclose(ours, np.sort_complex(PAPER_EIGENVALUES[v]), rtol=0, atol=1e-10)


def test_weave_and_capsize_speeds(bicycle, linearized):
    """Self-stable between the weave speed (a complex pair crosses into the left half
    plane) and the capsize speed (a real eigenvalue crosses out of it)."""
    def abscissa(v):
        return np.max(np.linalg.eigvals(bicycle.state_matrix(v)).real)

    assert abscissa(3.0) > 0 > abscissa(5.0) and abscissa(7.0) > 0
    weave = brentq(abscissa, 4.0, 5.0, xtol=1e-14)
    capsize = brentq(abscissa, 6.0, 7.0, xtol=1e-14)
    assert weave == pytest.approx(PAPER_WEAVE_SPEED, abs=1e-10)
    assert capsize == pytest.approx(PAPER_CAPSIZE_SPEED, abs=1e-10)
    # capsize: det(g K0 + v^2 K2) = 0 (a zero eigenvalue); K2's first column is 0,
    # so the determinant is linear in v^2
    _, _, K0, K2, _ = linearized
    v2 = -G * np.linalg.det(K0) / (K0[0, 0] * K2[1, 1] - K0[1, 0] * K2[0, 1])
    assert np.sqrt(v2) == pytest.approx(PAPER_CAPSIZE_SPEED, abs=1e-10)


def test_simulation_keeps_constraints_and_energy(tmp_path, monkeypatch):
    """One second from the spec's `initial:` (5 m/s, roll rate 0.5 rad/s) with the
    python backend: the constraints hold, the energy (no dissipation) is constant,
    and at 5 m/s (self-stable) the bicycle stays upright."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    out = tmp_path / "traj.csv"
    result = CliRunner().invoke(cli, ["simulate", str(SPEC), "--t-end", "1", "--backend", "python",
                                      "-o", str(out)])
    assert result.exit_code == 0, result.output
    header, rows = parse_csv(out.read_text())
    data = np.array(rows)
    column = {name: data[:, header.index(name)] for name in header}
    assert column["t"][-1] == 1.0
    assert np.max(column["constraint_residual"]) < 1e-8
    energy = column["energy"]
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * abs(energy[0])
    assert np.max(np.abs(column["phi"])) < 0.2
    assert column["x"][-1] == pytest.approx(5.0, rel=0.05)
