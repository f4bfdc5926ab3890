"""Seed Ex 19: pendulum with a vertically oscillating support f(t), and Kapitza's
pendulum (the same system in standard axes, used by the simulation tests)."""
import sympy as sp
from sympy import cos, sin


def test_kinetic_energy_as_in_notes(derived, assert_zero):
    d = derived("ex19_oscillating_support")
    model = d.model
    theta, m, l, a, w = (model.symbol(n) for n in ("theta", "m", "l", "a", "w"))
    (thd,) = model.qd
    t = model.t
    fd = sp.diff(a * cos(w * t), t)
    T_notes = m / 2 * (l**2 * thd**2 + fd**2 - 2 * l * thd * fd * sin(theta))
    assert_zero(d.T - T_notes, "T")
    assert_zero(d.T2 - m * l**2 * thd**2 / 2, "T2")
    assert d.scleronomic is False


def test_generalized_force_of_gravity(derived, assert_zero):
    # Notes: F = m g j, delta r_P = (l cos th i - l sin th j) dth  ->  Q = -m g l sin th
    d = derived("ex19_oscillating_support")
    model = d.model
    theta, m, l, g = (model.symbol(n) for n in ("theta", "m", "l", "g"))
    assert_zero(d.generalized_forces[0] + m * g * l * sin(theta), "Q_theta")
    assert_zero(d.nonconservative_forces[0], "Q'_theta")


def test_equation_of_motion(derived, assert_zero):
    # Notes: theta_ddot + (g - f_ddot) sin(theta) / l = 0
    d = derived("ex19_oscillating_support")
    model = d.model
    theta, m, l, g, a, w = (model.symbol(n) for n in ("theta", "m", "l", "g", "a", "w"))
    (thdd,) = model.qdd
    t = model.t
    fdd = sp.diff(a * cos(w * t), t, 2)
    (eq,) = d.equations
    assert eq.rhs == 0
    assert_zero(eq.lhs / (m * l**2) - (thdd + (g - fdd) * sin(theta) / l), "EOM")


def test_kapitza_equation(derived, assert_zero):
    # Standard axes (y up), pivot y_p = a cos(w t), r_P = (l sin th, y_p - l cos th):
    # T = m/2 [l^2 thd^2 + yp_dot^2 + 2 l thd yp_dot sin th], V = m g (y_p - l cos th)
    # -> m l^2 thdd + m l yp_ddot sin th + m g l sin th = 0
    # -> theta_ddot = -(g + yp_ddot) sin(theta) / l
    d = derived("kapitza_pendulum")
    model = d.model
    theta, m, l, g, a, w = (model.symbol(n) for n in ("theta", "m", "l", "g", "a", "w"))
    (thdd,) = model.qdd
    t = model.t
    ypdd = sp.diff(a * cos(w * t), t, 2)
    (eq,) = d.equations
    assert_zero(eq.lhs / (m * l**2) - (thdd + (g + ypdd) * sin(theta) / l), "EOM")
    assert d.scleronomic is False
    assert d.jacobi_integral is None


def test_kapitza_parameters_stabilise_inverted_position(derived):
    # Stability of the inverted pendulum needs a^2 w^2 > 2 g l (fast-shaking limit).
    d = derived("kapitza_pendulum")
    p = {info.symbol.name: info.value for info in d.model.parameters}
    assert p["a"] ** 2 * p["w"] ** 2 > 2 * p["g"] * p["l"]
    assert p["a"] < 0.2 * p["l"]  # small amplitude: the averaged theory applies
    assert abs(d.model.initial["theta"] - sp.pi.evalf()) < 0.3
