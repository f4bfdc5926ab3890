"""Seed Ex 18: compound pendulum on a prescribed slider x(t), force F i at C.

Checks the notes' generalized forces of the applied force, their potential, and
the full equations against a hand-written Lagrangian (notes' axes: j points down
along the hanging pendulum, gravity +g j).
"""
import sympy as sp
from sympy import cos, sin

SPEC = "ex18_slider_compound_pendulum"


def _symbols(d):
    return [d.model.symbol(n) for n in ("theta1", "theta2", "m", "L", "g", "F", "a", "w")]


def test_generalized_forces_of_applied_force(derived, assert_zero):
    d = derived(SPEC)
    th1, th2, m, L, g, F, a, w = _symbols(d)
    Qp = d.nonconservative_forces
    assert Qp.shape == (2, 1)
    assert_zero(Qp[0] - F * L * (cos(th1) + cos(th1 + th2)), "Q'_1")
    assert_zero(Qp[1] - F * L * cos(th1 + th2), "Q'_2")


def test_total_generalized_forces_include_gravity(derived, assert_zero):
    # gravity m g j on B and C: V_g = -m g (y_B + y_C)
    d = derived(SPEC)
    th1, th2, m, L, g, F, a, w = _symbols(d)
    Q = d.generalized_forces
    assert_zero(Q[0] - (F * L * (cos(th1) + cos(th1 + th2))
                        - m * g * L * (2 * sin(th1) + sin(th1 + th2))), "Q_1")
    assert_zero(Q[1] - (F * L * cos(th1 + th2) - m * g * L * sin(th1 + th2)), "Q_2")


def test_applied_force_derives_from_potential(derived, assert_zero):
    # Notes: V = -F L {sin th1 + sin(th1 + th2)} + const, with Q_j = -dV/dq_j
    d = derived(SPEC)
    th1, th2, m, L, g, F, a, w = _symbols(d)
    assert d.forces_conservative is True
    Vp = d.force_potential
    assert Vp is not None
    notes_V = -F * L * (sin(th1) + sin(th1 + th2))
    for q in (th1, th2):
        assert_zero(sp.diff(Vp - notes_V, q), f"d(V' - V_notes)/d{q}")
    for j, q in enumerate((th1, th2)):
        assert_zero(-sp.diff(Vp, q) - d.nonconservative_forces[j], f"-dV'/d{q} - Q'")


def test_rheonomic_kinetic_energy(derived, assert_zero):
    # r_C = [x + L sin th1 + L sin(th1+th2)] i + L[cos th1 + cos(th1+th2)] j  (notes)
    d = derived(SPEC)
    th1, th2, m, L, g, F, a, w = _symbols(d)
    t = d.model.t
    th1d, th2d = d.model.qd
    xd = a * w * cos(w * t)
    vB = sp.Matrix([xd + L * cos(th1) * th1d, -L * sin(th1) * th1d])
    vC = vB + L * (th1d + th2d) * sp.Matrix([cos(th1 + th2), -sin(th1 + th2)])
    T = m / 2 * (vB.dot(vB) + vC.dot(vC))
    assert d.scleronomic is False
    assert_zero(d.T - T, "T")
    assert_zero(d.T0 - m * xd**2, "T0")  # both masses carried along by the slider
    assert_zero(d.T1 - m * xd * (L * cos(th1) * th1d + L * cos(th1) * th1d
                                 + L * cos(th1 + th2) * (th1d + th2d)), "T1")


def test_equations_match_hand_lagrangian(derived, assert_zero, ddt):
    d = derived(SPEC)
    th1, th2, m, L, g, F, a, w = _symbols(d)
    model = d.model
    t = model.t
    th1d, th2d = model.qd
    x = a * sin(w * t)
    rB = sp.Matrix([x + L * sin(th1), L * cos(th1)])
    rC = rB + L * sp.Matrix([sin(th1 + th2), cos(th1 + th2)])
    vB, vC = ddt(model, rB), ddt(model, rC)
    T = m / 2 * (vB.dot(vB) + vC.dot(vC))
    V = -m * g * (rB[1] + rC[1])
    Qp = [F * L * (cos(th1) + cos(th1 + th2)), F * L * cos(th1 + th2)]
    for eq, q, qd, Qj in zip(d.equations, model.q, model.qd, Qp):
        lag = T - V
        lhs = ddt(model, sp.diff(lag, qd)) - sp.diff(lag, q) - Qj
        assert eq.coordinate == q
        assert_zero(eq.lhs - lhs, f"equation {q}")
        assert eq.rhs == 0


def test_no_jacobi_integral(derived):
    # L depends explicitly on t through x(t), and Q' != 0: no Jacobi integral.
    d = derived(SPEC)
    assert d.jacobi_integral is None
    assert d.dof == 2 and d.n_holonomic == 0 and d.n_nonholonomic == 0
