"""Bead on a hoop spinning at prescribed Omega about its vertical diameter."""
import sympy as sp
from sympy import cos, sin

SPEC = "bead_on_spinning_hoop"


def _syms(d):
    model = d.model
    (th,) = model.q
    (thd,) = model.qd
    (thdd,) = model.qdd
    m, R, g, W = (model.symbol(n) for n in ("m", "R", "g", "Omega"))
    return th, thd, thdd, m, R, g, W


def test_energies(derived, assert_zero):
    d = derived(SPEC)
    th, thd, thdd, m, R, g, W = _syms(d)
    assert_zero(d.T2 - m * R**2 * thd**2 / 2, "T2")
    assert_zero(d.T1, "T1")
    assert_zero(d.T0 - m * R**2 * W**2 * sin(th) ** 2 / 2, "T0")
    assert_zero(sp.diff(d.V + m * g * R * cos(th), th), "dV/dtheta")


def test_equation_of_motion(derived, assert_zero):
    # m R^2 th'' - m R^2 W^2 sin th cos th + m g R sin th = 0
    # -> th'' = (W^2 cos th - g/R) sin th
    d = derived(SPEC)
    th, thd, thdd, m, R, g, W = _syms(d)
    (eq,) = d.equations
    (sol,) = sp.solve(eq.lhs, thdd)
    assert_zero(sol - (W**2 * cos(th) - g / R) * sin(th), "theta''")


def test_relative_equilibrium(derived, assert_zero):
    # For W^2 > g/R the bead can ride at cos th = g / (R W^2).
    d = derived(SPEC)
    th, thd, thdd, m, R, g, W = _syms(d)
    F = d.forcing[0].subs(thd, 0).subs(th, sp.acos(g / (R * W**2)))
    assert_zero(F, "forcing at the relative equilibrium")


def test_rheonomic_with_jacobi_integral(derived, assert_zero):
    d = derived(SPEC)
    th, thd, thdd, m, R, g, W = _syms(d)
    assert d.scleronomic is False
    assert_zero(sp.diff(d.L, d.model.t), "dL/dt")  # Omega t cancels
    assert d.jacobi_integral is not None
    assert d.energy_is_jacobi is False
    h = m * R**2 * thd**2 / 2 - m * R**2 * W**2 * sin(th) ** 2 / 2 - m * g * R * cos(th)
    assert_zero(sp.diff(d.jacobi_integral - h, th), "dh/dtheta")
    assert_zero(sp.diff(d.jacobi_integral - h, thd), "dh/dtheta_dot")
    assert_zero(d.jacobi_integral - (d.T2 - d.T0 + d.V), "h = T2 - T0 + V")


def test_at_the_bifurcation_the_bottom_is_linearly_unstable_not_neutral():
    """At Omega^2 = g/R exactly the bottom's linear model is theta'' = (Omega^2 - g/R) theta
    = 0: A = [[0, 1], [0, 0]], a Jordan block of s = 0 (sympy's jordan_form of the closed
    form), so the linear solutions grow like t and the verdict is "linearly unstable" (the
    nonlinear terms decide; here they hold the bead: V' ~ m g R theta^4 / 8). The zero
    stiffness is a coincidence of the parameters' values, not structure: theta is not
    left out as neutral (it was: "neutral, every mode is neutral by structure"). On both
    sides the verdict follows the sign of Omega^2 - g/R."""
    import math

    import lagcli
    from conftest import spec_path

    g, R, Omega, th = sp.symbols("g R Omega theta", positive=True)
    stiffness = sp.diff((Omega**2 * cos(th) - g / R) * sin(th), th).subs(th, 0)
    A = sp.Matrix([[0, 1], [stiffness, 0]]).subs(Omega, sp.sqrt(g / R))
    _, J = A.jordan_form()
    assert J == sp.Matrix([[0, 1], [0, 0]])

    system = lagcli.load(spec_path(SPEC))
    critical = math.sqrt(9.81 / 0.5)
    lin = system.linearize(parameters={"Omega": critical})
    assert lin.verdict == "linearly unstable" and "theta" not in lin.neutral
    assert system.linearize(parameters={"Omega": 0.99 * critical}).verdict == "stable"
    assert system.linearize(parameters={"Omega": 1.01 * critical}).verdict == "unstable"
