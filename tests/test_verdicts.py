"""Stability verdicts that count correctly (issue 21), each against an independent oracle:
sympy's exact `Matrix.jordan_form`, closed forms, and sympy.physics.mechanics'
Linearizer (`LagrangesMethod.linearize`)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
import sympy as sp

import lagcli
from lagcli import commands
from lagcli.analysis.jordan import clustered, defective, drifting_states
from lagcli.analysis.stability import sorted_eigenvalues

from conftest import SPECS


def jordan_blocks(A: sp.Matrix) -> dict:
    """{eigenvalue: [block sizes]} of A's exact Jordan form (sympy)."""
    _, J = A.jordan_form()
    blocks, k, n = {}, 0, J.rows
    while k < n:
        size = 1
        while k + size < n and J[k + size - 1, k + size] == 1:
            size += 1
        blocks.setdefault(complex(J[k, k]), []).append(size)
        k += size
    return blocks


CRANE = dict(mt=sp.Integer(2), m=sp.Rational(1, 2), l=sp.Integer(1), g=sp.Rational(981, 100))


def crane_A() -> sp.Matrix:
    """The hanging gantry crane in (x, xl): mt x'' = m g (xl - x)/l, m xl'' = -m g (xl - x)/l."""
    mt, m, l, g = CRANE.values()
    a, b = m * g / (mt * l), g / l
    return sp.Matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-a, a, 0, 0], [b, -b, 0, 0]])


EXACT = {
    "crane": crane_A(),
    "free coordinate and an oscillator": sp.Matrix([[0, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, -4, 0]]),
    "(s^2 + 1)^2, one eigenvector": sp.Matrix([[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [-1, 0, -2, 0]]),
    "two equal oscillators": sp.Matrix([[0, 1, 0, 0], [-4, 0, 0, 0], [0, 0, 0, 1], [0, 0, -4, 0]]),
    "a damped free coordinate": sp.Matrix([[0, 1], [0, -1]]),
}


@pytest.mark.parametrize("name", list(EXACT))
def test_defective_eigenvalues_on_the_axis_are_those_of_the_exact_jordan_form(name):
    exact = EXACT[name]
    A = np.array(exact.evalf(), dtype=float)
    values = clustered(A, sorted_eigenvalues(A))
    found = defective(A, values, lambda s: abs(s.real) <= 1e-9)
    expected = {s for s, sizes in jordan_blocks(exact).items() if abs(s.real) < 1e-12 and max(sizes) > 1}
    assert sorted({round(abs(s.imag), 9) for s in found}) == sorted({round(abs(s.imag), 9) for s in expected})
    states = [f"s{k}" for k in range(A.shape[0])]
    assert bool(drifting_states(A, states, values)) == (0j in expected)


def test_gantry_crane_drifts_and_is_stable_in_its_swing_not_marginally_stable():
    """The hanging load swings at sqrt(g (mt + m)/(mt l)); trolley and load together are
    free: s = 0 is a 2 x 2 Jordan block (sympy), so x and xl drift at their common speed."""
    lin = lagcli.load(SPECS / "gantry_crane.yaml").linearize()
    exact = crane_A()
    np.testing.assert_allclose(lin.A, np.array(exact.evalf(), dtype=float), atol=1e-12)
    assert jordan_blocks(exact)[0j] == [2]
    mt, m, l, g = (float(v) for v in CRANE.values())
    swing = math.sqrt(g * (mt + m) / (mt * l))
    assert lin.eigenvalues == pytest.approx([complex(0, swing), complex(0, -swing)], abs=1e-12)
    assert lin.drift == ("x", "xl") and lin.neutral == ("x + xl", "x_dot + xl_dot")
    assert lin.verdict == "stable" and "Lagrange-Dirichlet" in lin.evidence
    text = commands.linearize(str(SPECS / "gantry_crane.yaml"))
    assert "marginally stable" not in text
    assert "drift: x, xl grow linearly with time" in text


def test_cart_pole_hanging_and_the_crane_say_the_same_of_their_free_cart():
    cart = lagcli.load(SPECS / "cart_pole.yaml").linearize(at={"theta": "pi"})
    crane = lagcli.load(SPECS / "gantry_crane.yaml").linearize()
    assert cart.neutral == ("x", "x_dot") and cart.drift == ("x",)
    assert cart.verdict == crane.verdict == "stable"
    mc, m, l, g = 1.0, 0.1, 0.5, 9.81       # specs/cart_pole.yaml
    assert cart.frequencies == pytest.approx((math.sqrt((mc + m) * g / (mc * l)),), rel=1e-12)
    upright = lagcli.load(SPECS / "cart_pole.yaml").linearize()
    assert upright.verdict == "unstable" and upright.drift == ("x",)


@pytest.mark.parametrize("omega", [3.0, 6.0])
def test_bead_on_hoop_verdicts_and_frequencies_on_both_sides_of_the_bifurcation(omega):
    """theta'' = (Omega^2 cos th - g/R) sin th: below Omega^2 = g/R the bottom oscillates at
    sqrt(g/R - Omega^2); above it grows at sqrt(Omega^2 - g/R) and the off-axis pair
    cos th = g/(R Omega^2) oscillates at Omega sin th."""
    system = lagcli.load(SPECS / "bead_on_spinning_hoop.yaml")
    g, R = 9.81, 0.5
    found = system.equilibria(parameters={"Omega": omega})
    bottom = next(e for e in found if e.point["theta"] == 0)
    if omega ** 2 < g / R:
        assert bottom.verdict == "stable"
        assert bottom.frequencies == pytest.approx((math.sqrt(g / R - omega ** 2),), rel=1e-10)
        assert len(found) == 2
    else:
        assert bottom.verdict == "unstable" and bottom.frequencies == ()
        assert sorted(bottom.eigenvalues.real) == pytest.approx([-math.sqrt(omega ** 2 - g / R),
                                                                 math.sqrt(omega ** 2 - g / R)], rel=1e-10)
        off = [e for e in found if 0 < e.point["theta"] < math.pi]
        (side,) = off
        assert side.point["theta"] == pytest.approx(math.acos(g / (R * omega ** 2)), rel=1e-12)
        assert side.verdict == "stable"
        assert side.frequencies == pytest.approx((omega * math.sin(side.point["theta"]),), rel=1e-9)


def test_double_pendulum_hangs_stably_at_the_closed_form_frequencies():
    """Equal masses and rods: omega^2 = (2 -+ sqrt 2) g / l; h has a strict minimum."""
    lin = lagcli.load(SPECS / "double_pendulum.yaml").linearize()
    g, l = 9.81, 1.0
    assert lin.verdict == "stable" and "Lagrange-Dirichlet" in lin.evidence
    assert lin.frequencies == pytest.approx(sorted([math.sqrt((2 - math.sqrt(2)) * g / l),
                                                    math.sqrt((2 + math.sqrt(2)) * g / l)]), rel=1e-12)


def ex20_oracle(q1: float, q2: float) -> np.ndarray:
    """Eigenvalues of Ex. 20 (double pendulum on the rim of a disc spinning at Omega, in the
    disc's frame) at (q1, q2) by sympy.physics.mechanics' LagrangesMethod.linearize."""
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

    a, b = dynamicsymbols("a b")
    t = dynamicsymbols._t
    m, l, W = 1.0, 0.5, 2.0
    rA = sp.Matrix([l + l * sp.cos(a), l * sp.sin(a)])
    rB = rA + sp.Matrix([l * sp.cos(b), l * sp.sin(b)])

    def velocity(r):        # d/dt in the disc's frame plus Omega z x r
        d = r.diff(t)
        return sp.Matrix([d[0] - W * r[1], d[1] + W * r[0]])

    L = m / 2 * (velocity(rA).dot(velocity(rA)) + velocity(rB).dot(velocity(rB)))
    method = LagrangesMethod(L, [a, b])
    method.form_lagranges_equations()
    point = {a: q1, b: q2, a.diff(): 0, b.diff(): 0, a.diff(t, 2): 0, b.diff(t, 2): 0}
    A, _, _ = method.linearize(q_ind=[a, b], qd_ind=[a.diff(), b.diff()], op_point=point, A_and_B=True)
    return np.linalg.eigvals(np.array(A, dtype=float))


def test_ex20_spirals_are_described_as_spirals_with_no_small_oscillation_frequency():
    found = lagcli.load(SPECS / "ex20_spinning_disk_double_pendulum.yaml").equilibria()
    spirals = [e for e in found if np.all(e.eigenvalues.imag != 0) and np.all(e.eigenvalues.real != 0)]
    assert len(spirals) == 2
    for e in spirals:
        oracle = ex20_oracle(e.point["q1"], e.point["q2"])
        assert sorted(e.eigenvalues, key=lambda s: (s.real, s.imag)) == pytest.approx(
            sorted(oracle, key=lambda s: (s.real, s.imag)), abs=1e-8)
        assert e.verdict == "unstable" and e.frequencies == ()
        assert {m.kind for m in e.linearization.modes} == {"growing spiral", "decaying spiral"}
    text = commands.equilibria(str(SPECS / "ex20_spinning_disk_double_pendulum.yaml"))
    for block in text.split("\n3. ")[1:] + text.split("\n6. ")[1:]:
        entry = block.split("\n4. ")[0].split("\n7. ")[0]
        assert "growing spiral 0.96933162 +- 1.3575086i" in entry
        assert "small-oscillation" not in entry


def test_gyroscopic_verdict_shows_its_evidence_and_needs_a_steady_motion():
    """The upright disc rolling at w = 5 (w^2 > g/(3 r)): lean mode +-i sqrt((12 r w^2 - 4 g)/(5 r)),
    K of the lean negative. The sphere on a turntable off its centre at rest is no
    equilibrium (it gets a verdict no more)."""
    disc = lagcli.load(SPECS / "rolling_disc.yaml").linearize(at={"phi_dot": 5, "x_dot": 1.5})
    r, g, w = 0.3, 9.81, 5.0
    lean = math.sqrt((12 * r * w ** 2 - 4 * g) / (5 * r))
    assert disc.verdict == "gyroscopically stabilized"
    assert "1 negative eigenvalue" in disc.evidence and "K of theta" in disc.evidence
    assert sorted(abs(s.imag) for s in disc.eigenvalues) == pytest.approx([0, lean, lean], abs=1e-9)
    sphere = lagcli.load(SPECS / "sphere_on_turntable.yaml").linearize(at={"x": 0.3})
    assert sphere.verdict == "no verdict" and "b_dot'" in sphere.evidence


def test_every_surface_shows_the_same_verdict_evidence_and_drift():
    path = str(SPECS / "gantry_crane.yaml")
    lin = lagcli.load(path).linearize()
    content = json.loads(commands.linearize(path, fmt="json"))
    assert (content["verdict"], content["evidence"], tuple(content["drift"])) == (lin.verdict, lin.evidence, lin.drift)
    assert [m["kind"] for m in content["modes"]] == ["oscillation", "oscillation"]
    text = commands.linearize(path)
    assert f"verdict: {lin.verdict} ({lin.evidence})" in text
    assert repr(lin).endswith(f": {lin.verdict}; eigenvalues 0 + 3.50179i, 0 - 3.50179i; drift: x, xl>")
    for shown in (lin._repr_html_(), commands.linearize(path, fmt="latex"), lin._repr_latex_()):
        assert lin.verdict in shown and "Lagrange-Dirichlet" in shown and "drift" in shown


def test_the_page_linearizes_at_the_spec_initial_state_and_names_the_point_and_command():
    """specs/cart_pole.yaml's initial: gives x = 0, theta = 0.05; the velocities are not
    given and are 0, as `lagcli linearize --at` takes them; the page says so and prints the
    command whose output agrees."""
    import shlex

    from click.testing import CliRunner

    from lagcli.cli import cli
    from lagcli.report.page import _linearization_section

    system = lagcli.load(SPECS / "cart_pole.yaml")
    html = _linearization_section(system)
    assert "The point: x = 0, theta = 0.05 from the spec's <code>initial:</code>" in html
    assert "x_dot = 0, theta_dot = 0 as <code>lagcli linearize</code> takes" in html
    command = html.split("The same: <code>")[1].split("</code>")[0]
    assert command == "lagcli linearize cart_pole.yaml --at x=0.0 --at theta=0.05"
    args = shlex.split(command)[1:]
    args[1] = str(SPECS / args[1])
    content = json.loads(CliRunner().invoke(cli, [*args, "--json"]).output)
    assert content["operating_point"] == {"x": 0.0, "theta": 0.05, "x_dot": 0.0, "theta_dot": 0.0}
    assert f"<b>{content['verdict']}</b> ({content['evidence']})".replace("'", "&#x27;") in html
    assert content["verdict"] == "no verdict" and "theta_dot' = " in content["evidence"]


def test_an_equilibrium_at_a_coordinate_singularity_prints_its_chart_modes():
    """The top hanging at theta = pi (Euler angles singular there) swings at
    sqrt(m g h / (A + m h^2)) in the chart assembled from the other descriptions."""
    text = commands.equilibria(str(SPECS / "heavy_symmetric_top.yaml"))
    m, h, A, g = 0.5, 0.04, 2.0e-4, 9.81
    swing = math.sqrt(m * g * h / (A + m * h ** 2))
    hanging = text.split("\n2. ")[1]
    assert hanging.startswith("psi = 0, theta = 3.14159265359, phi = 0: stable")
    assert f"small-oscillation frequencies (rad/s): {swing:.10g}" in hanging
    assert "Lagrange-Dirichlet" in hanging


FOLLOWER = """name: follower
description: two equal oscillators, the second pushing the first (a circulatory force)
coordinates: [x, y]
parameters: {m: 1.0, k: 4.0, c: C}
particles:
  P: {mass: m, position: [x, y]}
generalized_forces: {x: -k*x + c*y, y: -k*y}
"""


@pytest.mark.parametrize("c", [0.5, 0.0])
def test_a_repeated_frequency_with_one_mode_is_linearly_unstable(c):
    """x'' = -k x + c y, y'' = -k y: s = +-2i twice; with c != 0 one eigenvector each (sympy's
    Jordan form), x = (c t / 4) sin 2t grows; with c = 0 two, bounded."""
    lin = lagcli.load(FOLLOWER.replace("C}", f"{c}}}")).linearize()
    exact = sp.Matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-4, sp.nsimplify(c), 0, 0], [0, -4, 0, 0]])
    np.testing.assert_allclose(lin.A, np.array(exact.evalf(), dtype=float), atol=1e-12)
    blocks = jordan_blocks(exact)
    if c:
        assert blocks[2j] == [2] and lin.verdict == "linearly unstable"
        assert [m.kind for m in lin.modes] == ["growing oscillation"] * 4 and lin.frequencies == ()
        assert "+-2i" in lin.evidence
    else:
        assert blocks[2j] == [1, 1] and lin.verdict == "marginally stable"
        assert lin.frequencies == pytest.approx((2.0,))
