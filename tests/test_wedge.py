"""Seed Ex 19 (text): block m2 on a smooth 45-degree wedge m1 on a smooth floor."""
import sympy as sp


def _syms(d):
    model = d.model
    return [model.symbol(n) for n in ("x1", "x2", "x1_dot", "x2_dot", "m1", "m2", "g")]


def test_kinetic_energy(derived, assert_zero):
    d = derived("ex19_wedge")
    x1, x2, x1d, x2d, m1, m2, g = _syms(d)
    T_notes = (m1 + m2) * x1d**2 / 2 + m2 * (x2d**2 - sp.sqrt(2) * x1d * x2d) / 2
    assert_zero(d.T - T_notes, "T")
    assert_zero(d.T - d.T2, "T - T2")
    assert_zero(d.mass_matrix - sp.Matrix([[m1 + m2, -m2 / sp.sqrt(2)], [-m2 / sp.sqrt(2), m2]]), "M")
    assert d.scleronomic is True


def test_generalized_forces(derived, assert_zero):
    # Gravity is a potential here, so the notes' Q are the total generalized forces.
    d = derived("ex19_wedge")
    x1, x2, x1d, x2d, m1, m2, g = _syms(d)
    assert_zero(d.generalized_forces - sp.Matrix([0, m2 * g / sp.sqrt(2)]), "Q")
    assert_zero(d.nonconservative_forces, "Q'")
    for q in (x1, x2):  # V = -m2 g x2 / sqrt(2) + const
        assert_zero(sp.diff(d.V + m2 * g * x2 / sp.sqrt(2), q), f"dV/d{q}")


def test_equations_of_motion(derived, assert_zero):
    d = derived("ex19_wedge")
    x1, x2, x1d, x2d, m1, m2, g = _syms(d)
    x1dd, x2dd = d.model.qdd
    e1, e2 = d.equations
    # (m1 + m2) x1'' - m2 x2''/sqrt2 = 0 ;  m2 x2'' - m2 x1''/sqrt2 = m2 g/sqrt2
    assert_zero(e1.lhs - ((m1 + m2) * x1dd - m2 * x2dd / sp.sqrt(2)), "x1 equation")
    assert_zero(e2.lhs - (m2 * x2dd - m2 * x1dd / sp.sqrt(2) - m2 * g / sp.sqrt(2)), "x2 equation")
    assert e1.rhs == 0 and e2.rhs == 0


def test_wedge_acceleration(derived, assert_zero):
    # Notes: x1'' = m2 g / (2 m1 + m2)
    d = derived("ex19_wedge")
    x1, x2, x1d, x2d, m1, m2, g = _syms(d)
    qdd = sp.Matrix(d.mass_matrix).LUsolve(sp.Matrix(d.forcing))
    assert_zero(qdd[0] - m2 * g / (2 * m1 + m2), "x1''")
    assert_zero(qdd[1] - (qdd[0] + g) / sp.sqrt(2), "x2''")


def test_x1_ignorable_momentum_conserved(derived, assert_zero):
    d = derived("ex19_wedge")
    x1, x2, x1d, x2d, m1, m2, g = _syms(d)
    assert d.ignorable == (x1,)
    (p,) = [c for c in d.conserved if c.kind == "momentum"]
    assert p.name == "p_x1"
    assert_zero(p.expr - ((m1 + m2) * x1d - m2 * x2d / sp.sqrt(2)), "p_x1")


def test_jacobi_integral_is_energy(derived, assert_zero):
    d = derived("ex19_wedge")
    assert d.jacobi_integral is not None
    assert d.energy_is_jacobi is True
    assert_zero(d.jacobi_integral - d.energy, "h - E")
    assert_zero(d.energy - (d.T + d.V), "E - (T + V)")
