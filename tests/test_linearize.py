"""Linearization (lagcli/analysis/linearize.py) against closed forms and sympy's Linearizer."""
from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner

from lagcli.analysis.linearize import CompiledSystem, linearize
from lagcli.analysis.operating_point import evaluate, parse_assignments
from lagcli.analysis.stability import stability
from lagcli.cli import cli

from conftest import spec_path


def linear(d, at=(), inputs=(), independent=(), sweep=None, value=None):
    system = CompiledSystem(d, inputs)
    return linearize(system, evaluate(d, parse_assignments(d, at, sweep), value), independent)


def test_cartesian_pendulum_in_its_independent_coordinate(derived):
    d = derived("cartesian_pendulum")
    lm = linear(d, ["y=-l"])
    g, l = 9.81, 1.0
    assert lm.states == ("x", "x_dot") and lm.dependent == ("y", "y_dot")
    np.testing.assert_allclose(lm.A, [[0, 1], [-g / l, 0]], atol=1e-12)
    assert stability(lm).verdict == "stable"


def test_dependent_coordinate_is_solved_for(derived):
    d = derived("cartesian_pendulum")
    lm = linear(d, ["x=0.6", "y=-0.7"], independent=["x", "x_dot"])   # y is put back on the rod: -0.8
    assert lm.point.q[1] == pytest.approx(-0.8, abs=1e-13)
    assert any("y" in note for note in lm.point.notes)


def test_disc_on_incline_rolls_down_with_two_thirds_g_sin_alpha(derived):
    d = derived("disc_on_incline")
    for chosen in (["s", "s_dot"], ["theta", "theta_dot"]):
        lm = linear(d, independent=chosen)
        np.testing.assert_allclose(lm.A, [[0, 1], [0, 0]], atol=1e-12)
        rate = 2 / 3 * 9.81 * np.sin(np.pi / 6) / (1 if chosen[0] == "s" else 0.1)
        assert lm.speed_rates[0] == pytest.approx(rate, rel=1e-12)


# -- cart-pole with a force input: closed form and sympy.physics.mechanics ---------

def cart_pole_closed_form(mc, m, l, g):
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, -m * g / mc, 0, 0], [0, (mc + m) * g / (mc * l), 0, 0]])
    B = np.array([[0], [0], [1 / mc], [-1 / (mc * l)]])
    return A, B


def cart_pole_sympy_linearizer(mc, m, l, g):
    """The same plant built from scratch with sympy.physics.mechanics (Kane), linearized by its
    Linearizer (KanesMethod.linearize) about the upright position."""
    import sympy.physics.mechanics as me

    x, th = me.dynamicsymbols("x theta")
    u1, u2 = me.dynamicsymbols("u1 u2")
    F = me.dynamicsymbols("F")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    cart = O.locatenew("C", x * N.x)
    cart.set_vel(N, u1 * N.x)
    bob = cart.locatenew("B", l * sp.sin(th) * N.x + l * sp.cos(th) * N.y)
    bob.set_vel(N, bob.pos_from(O).dt(N).subs({x.diff(): u1, th.diff(): u2}))
    bodies = [me.Particle("pc", cart, mc), me.Particle("pb", bob, m)]
    loads = [(cart, F * N.x - mc * g * N.y), (bob, -m * g * N.y)]
    kane = me.KanesMethod(N, q_ind=[x, th], u_ind=[u1, u2], kd_eqs=[x.diff() - u1, th.diff() - u2])
    kane.kanes_equations(bodies, loads)
    A, B, _ = kane.linearize(A_and_B=True, op_point={x: 0, th: 0, u1: 0, u2: 0, F: 0})
    return np.array(A, dtype=float), np.array(B, dtype=float)


def test_cart_pole_against_the_textbook_and_sympy(derived):
    d = derived("cart_pole")
    lm = linear(d, inputs=["F"])
    values = dict(mc=1.0, m=0.1, l=0.5, g=9.81)
    assert lm.states == ("x", "theta", "x_dot", "theta_dot") and lm.inputs == ("F",)
    A, B = cart_pole_closed_form(**values)
    np.testing.assert_allclose(lm.A, A, atol=1e-12)
    np.testing.assert_allclose(lm.B, B, atol=1e-12)
    A2, B2 = cart_pole_sympy_linearizer(**values)
    np.testing.assert_allclose(lm.A, A2, atol=1e-12)
    np.testing.assert_allclose(lm.B, B2, atol=1e-12)
    assert stability(lm).verdict == "unstable"


def test_cart_pole_at_other_parameters(derived):
    d = derived("cart_pole")
    lm = linear(d, ["mc=2", "m=0.5", "l=1.5"], inputs=["F"])
    A, B = cart_pole_closed_form(2.0, 0.5, 1.5, 9.81)
    np.testing.assert_allclose(lm.A, A, atol=1e-12)
    np.testing.assert_allclose(lm.B, B, atol=1e-12)


def test_declared_input_is_the_column_of_B_without_any_option(derived):
    """cart_pole declares `inputs: [F]`: B has its column with no --input; --input of a
    parameter adds that column after the declared inputs (B's m column: df/dm at the point,
    compared with a central difference of the closed form)."""
    d = derived("cart_pole")
    lm = linear(d)
    A, B = cart_pole_closed_form(1.0, 0.1, 0.5, 9.81)
    assert lm.inputs == ("F",)
    np.testing.assert_allclose(lm.B, B, atol=1e-12)
    theta, F = 0.2, 0.7
    lm = linear(d, [f"theta={theta}", f"F={F}"], inputs=["m", "F"])
    assert lm.inputs == ("F", "m")

    def accelerations(m, mc=1.0, l=0.5, g=9.81):   # the textbook's nonlinear cart-pole, at rest
        s, c = np.sin(theta), np.cos(theta)
        den = mc + m * s * s
        return np.array([(F - m * g * s * c) / den, ((mc + m) * g * s - F * c) / (l * den)])

    h = 1e-6
    dm = (accelerations(0.1 + h) - accelerations(0.1 - h)) / (2 * h)
    np.testing.assert_allclose(lm.B[2:, 1], dm, rtol=1e-7)
    np.testing.assert_allclose(lm.B[2:, 0],
                               [1 / (1.0 + 0.1 * np.sin(theta) ** 2),
                                -np.cos(theta) / (0.5 * (1.0 + 0.1 * np.sin(theta) ** 2))], rtol=1e-12)


# -- rolling disc: upright rolling stable iff spin^2 > g/(3 r) -------------------

@pytest.mark.parametrize("spin", [2.0, 3.2, 3.4, 6.0])
def test_rolling_disc_upright_stability(derived, spin):
    d = derived("rolling_disc")
    r, g = 0.3, 9.81
    lm = linear(d, ["phi_dot=w", "x_dot=r*w"], sweep="w", value=spin)
    st = stability(lm)
    # lean mode of a thin disc (I_axis = m r^2/2, I_diam = m r^2/4) rolling upright at spin w:
    # (I_d + m r^2) theta'' = -(I_a (I_a + m r^2) / I_d w^2 - m g r) theta  ->  s^2 = (4 g - 12 r w^2) / (5 r)
    s2 = (4 * g - 12 * r * spin**2) / (5 * r)
    expected = sorted([np.sqrt(complex(s2)), -np.sqrt(complex(s2)), 0], key=lambda s: (-s.real, -s.imag))
    np.testing.assert_allclose(st.eigenvalues, expected, atol=1e-9)
    if spin**2 > g / (3 * r):
        assert st.verdict == "gyroscopically stabilized" and st.negative_stiffness
    else:
        assert st.verdict == "unstable"
    assert set(st.neutral) == {"x", "y", "psi", "phi", "phi_dot"}


def test_bead_bottom_loses_stability_at_omega_squared_g_over_R():
    runner = CliRunner()
    result = runner.invoke(cli, ["linearize", str(spec_path("bead_on_spinning_hoop")), "--at", "theta=0",
                                 "--sweep", "Omega=4:8:5", "--find-critical", "--json"])
    assert result.exit_code == 0, result.output
    content = json.loads(result.output)
    (critical,) = content["critical"]
    assert critical["value"] == pytest.approx(np.sqrt(9.81 / 0.5), rel=1e-6)
    assert (critical["unstable_below"], critical["unstable_above"]) == (0, 1)
    for point in content["points"]:
        s2 = point["value"] ** 2 - 9.81 / 0.5
        largest = max(e[0] for e in point["eigenvalues"])
        assert largest == pytest.approx(np.sqrt(max(s2, 0.0)), abs=1e-9)


def test_cli_text_latex_and_errors():
    runner = CliRunner()
    path = str(spec_path("cart_pole"))
    text = runner.invoke(cli, ["linearize", path, "--input", "F"])
    assert text.exit_code == 0 and "verdict: unstable" in text.output
    latex = runner.invoke(cli, ["linearize", path, "--latex"])
    assert latex.exit_code == 0 and r"\begin{bmatrix}" in latex.output
    bad = runner.invoke(cli, ["linearize", path, "--at", "tehta=1"])
    assert bad.exit_code == 2 and "did you mean 'theta'" in bad.output
    bad = runner.invoke(cli, ["linearize", path, "--input", "G"])
    assert bad.exit_code == 2 and "not an input or a parameter" in bad.output
    bad = runner.invoke(cli, ["linearize", path, "--find-critical"])
    assert bad.exit_code == 2
    help_text = runner.invoke(cli, ["linearize", "--help"])
    assert "Examples:" in help_text.output


def test_symbolic_cart_pole_and_bead(derived, assert_zero):
    from lagcli.analysis.symbolic import symbolic_linear

    d = derived("cart_pole")
    lin = symbolic_linear(d, parse_assignments(d, []), ["F"])
    mc, m, l, g = (d.model.symbol(n) for n in ("mc", "m", "l", "g"))
    assert_zero(lin.A - sp.Matrix([[0, 0, 1, 0], [0, 0, 0, 1], [0, -m * g / mc, 0, 0], [0, (mc + m) * g / (mc * l), 0, 0]]))
    assert_zero(lin.B - sp.Matrix([0, 0, 1 / mc, -1 / (mc * l)]))
    # tidied as Hamilton's form and the Routhian are (issue 21): the textbook's closed form,
    # the same tree, not (g*m + g*mc)/(l*mc)
    assert lin.A[3, 1] == g * (m + mc) / (l * mc) and lin.A[2, 1] == -g * m / mc
    d = derived("bead_on_spinning_hoop")
    lin = symbolic_linear(d, parse_assignments(d, ["theta=acos(g/(R*Omega**2))"]))
    R, g, W = (d.model.symbol(n) for n in ("R", "g", "Omega"))
    # small oscillations about the off-axis equilibrium: omega^2 = Omega^2 sin^2(theta*)
    assert_zero(lin.A[1, 0] + W**2 * (1 - (g / (R * W**2))**2))
    with pytest.raises(Exception, match="unconstrained"):
        symbolic_linear(derived("cartesian_pendulum"), parse_assignments(derived("cartesian_pendulum"), []))


def test_a_damper_set_to_zero_with_at_gives_the_undamped_verdict(tmp_path):
    # docs/analysis.md: undamped, at rest, K positive definite -> "stable"; decided from the
    # values (c = 0 via --at), not from the spec having a damper. With c > 0 the eigenvalues
    # -c/2m +- i sqrt(k/m - c^2/4m^2) lie left of the axis: asymptotically stable.
    spec = tmp_path / "damped.yaml"
    spec.write_text("coordinates: [x]\nparameters: {m: 1.0, k: 4.0, c: 0.3}\n"
                    "particles: {P: {mass: m, position: [x, 0]}}\nsprings: [{between: [P, [0, 0]], stiffness: k}]\n"
                    "dampers: [{between: [P, [-1, 0]], damping: c}]\n")
    undamped = CliRunner().invoke(cli, ["linearize", str(spec), "--at", "c=0"])
    assert undamped.exit_code == 0, undamped.output
    assert "verdict: stable" in undamped.output
    damped = CliRunner().invoke(cli, ["linearize", str(spec)])
    assert "verdict: asymptotically stable" in damped.output


# -- a constrained spec linearized from its consistent initial state (issue 21) ------

def test_gantry_crane_is_linearized_about_the_load_hanging_below_its_initial_state():
    """No --at: the rope row has no gradient at all zeros, so the solve for the dependent
    yl starts from the spec's consistent initial state (yl = -0.8) and reaches the hanging
    load yl = -l; independent x, xl at 0. Against the closed form in the spec's header:
    x'' = m g / (mt l) (xl - x) + F / mt, xl'' = -g / l (xl - x)."""
    import lagcli

    system = lagcli.load(spec_path("gantry_crane"))
    p = system.layout.parameter_defaults
    mt, m, l, g = p["mt"], p["m"], p["l"], p["g"]
    lin = system.linearize()
    assert lin.point.coordinates == {"x": 0.0, "xl": 0.0, "yl": pytest.approx(-l, abs=1e-14)}
    assert lin.states == ("x", "xl", "x_dot", "xl_dot") and lin.dependent == ("yl", "yl_dot")
    k, w = m * g / (mt * l), g / l
    np.testing.assert_allclose(lin.A, [[0, 0, 1, 0], [0, 0, 0, 1], [-k, k, 0, 0], [w, -w, 0, 0]], atol=1e-12)
    np.testing.assert_allclose(lin.B, [[0], [0], [1 / mt], [0]], atol=1e-15)
    sway = np.sqrt(g * (mt + m) / (mt * l))
    assert max(abs(s.imag) for s in lin.eigenvalues) == pytest.approx(sway, rel=1e-12)


def test_cartesian_pendulum_linearizes_without_at_and_a_failed_solve_names_its_start():
    result = CliRunner().invoke(cli, ["linearize", str(spec_path("cartesian_pendulum")), "--json"])
    assert result.exit_code == 0, result.output
    content = json.loads(result.output)
    assert content["operating_point"]["y"] == pytest.approx(-1.0, abs=1e-14)     # hanging, from y = -0.8
    result = CliRunner().invoke(cli, ["linearize", str(spec_path("cartesian_pendulum")), "--at", "x=2", "--independent", "x"])
    assert result.exit_code == 2
    assert "could not be solved for the dependent coordinates y, starting from x = 2, y = -0.8" in result.output


def test_a_singular_point_is_named():
    result = CliRunner().invoke(cli, ["linearize", str(spec_path("spherical_pendulum"))])
    assert result.exit_code == 2
    assert "singular at theta = 0, phi = 0, theta_dot = 0, phi_dot = 0" in result.output
