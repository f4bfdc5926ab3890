"""Spherical pendulum (lecture notes): phi is ignorable, energy is the Jacobi integral."""
import sympy as sp
from sympy import cos, sin

SPEC = "spherical_pendulum"


def _syms(d):
    model = d.model
    th, ph = model.q
    thd, phd = model.qd
    m, L, g = (model.symbol(n) for n in ("m", "L", "g"))
    return th, ph, thd, phd, m, L, g


def test_energies_as_in_notes(derived, assert_zero):
    d = derived(SPEC)
    th, ph, thd, phd, m, L, g = _syms(d)
    assert_zero(d.T - m / 2 * ((L * thd) ** 2 + (phd * L * sin(th)) ** 2), "T")
    V_notes = m * g * L * (1 - cos(th))
    for q in (th, ph):  # the engine's V may differ by a constant
        assert_zero(sp.diff(d.V - V_notes, q), f"dV/d{q}")
    assert d.scleronomic is True


def test_equations_of_motion(derived, assert_zero):
    d = derived(SPEC)
    th, ph, thd, phd, m, L, g = _syms(d)
    thdd, phdd = d.model.qdd
    e_th, e_ph = d.equations
    assert_zero(e_th.lhs - (m * L**2 * thdd - m * L**2 * sin(th) * cos(th) * phd**2
                            + m * g * L * sin(th)), "theta equation")
    assert_zero(e_ph.lhs - m * L**2 * (sin(th) ** 2 * phdd + 2 * sin(th) * cos(th) * thd * phd),
                "phi equation")


def test_phi_ignorable(derived, assert_zero):
    d = derived(SPEC)
    th, ph, thd, phd, m, L, g = _syms(d)
    assert d.ignorable == (ph,)
    (p,) = [c for c in d.conserved if c.kind == "momentum"]
    assert p.name == "p_phi"
    assert_zero(p.expr - m * L**2 * sin(th) ** 2 * phd, "p_phi")


def test_energy_is_jacobi_integral(derived, assert_zero):
    d = derived(SPEC)
    assert d.jacobi_integral is not None
    assert d.energy_is_jacobi is True
    assert_zero(d.jacobi_integral - d.energy, "h - E")
