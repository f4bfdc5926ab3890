"""Seed Ex 20: double pendulum hinged on the rim of a disk spinning at constant
Omega (horizontal plane). Coordinates q1, q2 are measured in the rotating frame.

Every term of the explicit form M q'' + G1 q'^2 + G2 q' + F(q) = Q is compared
with the notes. NOTE: the notes' final vector form prints the second entry of
F(q) as m l^2 Omega^2 [sin q1 - sin(q1 - q2)]; that is a typo. Their own
line-by-line q2 equation (and physics: -dT0/dq2) gives sin q2 - sin(q1 - q2),
which is what is checked here.
"""
import sympy as sp
from sympy import cos, sin

SPEC = "ex20_spinning_disk_double_pendulum"


def _syms(d):
    model = d.model
    q1, q2 = model.q
    q1d, q2d = model.qd
    m, l, W = (model.symbol(n) for n in ("m", "l", "Omega"))
    return q1, q2, q1d, q2d, m, l, W


def test_kinetic_energy_split(derived, assert_zero):
    d = derived(SPEC)
    q1, q2, q1d, q2d, m, l, W = _syms(d)
    T2 = m * l**2 / 2 * (2 * q1d**2 + 2 * q1d * q2d * cos(q1 - q2) + q2d**2)
    T1 = m * l**2 * W * (2 * q1d * (1 + cos(q1)) + q2d * (1 + cos(q2)) + (q1d + q2d) * cos(q1 - q2))
    T0 = m * l**2 * W**2 / 2 * (5 + 4 * cos(q1) + 2 * cos(q2) + 2 * cos(q1 - q2))
    assert_zero(d.T2 - T2, "T2")
    assert_zero(d.T1 - T1, "T1")
    assert_zero(d.T0 - T0, "T0")
    assert_zero(d.T - (T2 + T1 + T0), "T")
    a = sp.Matrix([sp.diff(T1, q1d), sp.diff(T1, q2d)])
    assert_zero(sp.Matrix(d.t1_coefficients) - a, "t1 coefficients")


def test_mass_matrix(derived, assert_zero):
    d = derived(SPEC)
    q1, q2, q1d, q2d, m, l, W = _syms(d)
    c = cos(q1 - q2)
    assert_zero(d.mass_matrix - m * l**2 * sp.Matrix([[2, c], [c, 1]]), "M")


def test_velocity_terms(derived, assert_zero):
    # notes: m l^2 [[0, s], [-s, 0]] (q1'^2, q2'^2)
    d = derived(SPEC)
    q1, q2, q1d, q2d, m, l, W = _syms(d)
    s = sin(q1 - q2)
    assert_zero(d.velocity_terms - m * l**2 * sp.Matrix([s * q2d**2, -s * q1d**2]), "c(q, q')")


def test_gyroscopic_matrix(derived, assert_zero):
    d = derived(SPEC)
    q1, q2, q1d, q2d, m, l, W = _syms(d)
    s = sin(q1 - q2)
    G = 2 * m * W * l**2 * sp.Matrix([[0, s], [-s, 0]])
    assert_zero(d.gyroscopic_matrix - G, "gamma")
    assert_zero(d.gyroscopic_matrix + d.gyroscopic_matrix.T, "gamma + gamma^T")


def test_position_terms_follow_physics_not_the_typo(derived, assert_zero):
    # Notes' matrix form has `sin q1 - sin(q1 - q2)` in row 2: a typo (see module doc).
    d = derived(SPEC)
    q1, q2, q1d, q2d, m, l, W = _syms(d)
    s = sin(q1 - q2)
    F = m * l**2 * W**2 * sp.Matrix([2 * sin(q1) + s, sin(q2) - s])
    assert_zero(d.position_terms - F, "F(q)")
    assert_zero(d.mass_rate_terms, "M_t q'")
    assert_zero(d.t1_rate_terms, "a_t")


def test_equations_as_simplified_in_notes(derived, assert_zero):
    d = derived(SPEC)
    q1, q2, q1d, q2d, m, l, W = _syms(d)
    q1dd, q2dd = d.model.qdd
    s, c = sin(q1 - q2), cos(q1 - q2)
    eq1 = (m * l**2 * (2 * q1dd + q2dd * c + q2d**2 * s) + 2 * m * l**2 * W * q2d * s
           + m * l**2 * (2 * W**2 * sin(q1) + W**2 * s))
    eq2 = (m * l**2 * (q1dd * c - q1d**2 * s + q2dd) - 2 * m * l**2 * W * q1d * s
           + m * l**2 * W**2 * (sin(q2) - s))
    e1, e2 = d.equations
    assert_zero(e1.lhs - eq1, "q1 equation")
    assert_zero(e2.lhs - eq2, "q2 equation")


def test_rheonomic_but_jacobi_integral_exists(derived, assert_zero):
    # Omega t cancels from L (only q - q differences and the disk-fixed angles
    # remain), so h = T2 - T0 + V is conserved although the system is rheonomic.
    d = derived(SPEC)
    assert d.scleronomic is False
    assert_zero(sp.diff(d.L, d.model.t), "dL/dt")
    assert d.jacobi_integral is not None
    assert_zero(d.jacobi_integral - (d.T2 - d.T0 + d.V), "h")
    assert d.energy_is_jacobi is False
    assert d.ignorable == ()
