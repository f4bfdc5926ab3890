"""The System's analyses and the Trajectory as a notebook user meets them: typed values
with numpy arrays, checked against closed forms derived by hand here, and their
Jupyter displays (`_repr_latex_`, `_repr_html_`) well-formed."""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import lagcli
from lagcli.errors import UsageError

from conftest import SPECS


@pytest.fixture(scope="module")
def cart_pole():
    return lagcli.load(SPECS / "cart_pole.yaml")


@pytest.fixture(scope="module")
def hoop():
    return lagcli.load(SPECS / "bead_on_spinning_hoop.yaml")


def cart_pole_closed_form(mc: float, m: float, l: float, g: float):
    """The cart-pole linearized about upright, by hand. With L = (mc + m) x'^2/2
    + m l x' th' cos th + m l^2 th'^2/2 - m g l cos th, at th = 0:
        (mc + m) x'' + m l th'' = F,      x'' + l th'' = g th
    so x'' = -(m g/mc) th + F/mc and th'' = (mc + m) g th/(mc l) - F/(mc l); the
    second-order form has M = [[mc + m, m l], [m l, m l^2]], C = 0, K = diag(0, -m g l)."""
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                  [0, -m * g / mc, 0, 0], [0, (mc + m) * g / (mc * l), 0, 0]])
    B = np.array([[0], [0], [1 / mc], [-1 / (mc * l)]])
    M = np.array([[mc + m, m * l], [m * l, m * l ** 2]])
    K = np.array([[0, 0], [0, -m * g * l]])
    return A, B, M, K


@pytest.mark.parametrize("values", [{}, {"mc": 2.0, "m": 0.3, "l": 0.8, "g": 9.0}])
def test_cart_pole_A_B_are_the_textbook_ones(cart_pole, values):
    lin = cart_pole.linearize(parameters=values)
    p = {**cart_pole.layout.parameter_defaults, **values}
    A, B, M, K = cart_pole_closed_form(p["mc"], p["m"], p["l"], p["g"])
    assert lin.states == ("x", "theta", "x_dot", "theta_dot") and lin.inputs == ("F",)
    assert isinstance(lin.A, np.ndarray) and lin.A.shape == (4, 4) and lin.B.shape == (4, 1)
    scale = np.max(np.abs(A))
    assert np.allclose(lin.A, A, rtol=0, atol=1e-12 * scale)
    assert np.allclose(lin.B, B, rtol=0, atol=1e-12)
    assert np.allclose(lin.M, M, rtol=0, atol=1e-12) and np.allclose(lin.C, 0, atol=1e-12)
    assert np.allclose(lin.K, K, rtol=0, atol=1e-12 * np.max(np.abs(K)))
    rate = math.sqrt((p["mc"] + p["m"]) * p["g"] / (p["mc"] * p["l"]))
    assert sorted(lin.eigenvalues.real) == pytest.approx([-rate, rate], rel=1e-10)
    assert lin.neutral == ("x", "x_dot") and lin.verdict == "unstable"
    assert lin.point.state == {"x": 0, "theta": 0, "x_dot": 0, "theta_dot": 0}
    assert lin.point.parameters == p and lin.point.inputs == {"F": 0.0}


def test_cart_pole_hanging_down_is_not_unstable(cart_pole):
    """About theta = pi (an expression, as --at takes it), the pole swings at
    sqrt((mc + m) g/(mc l)): eigenvalues on the imaginary axis."""
    lin = cart_pole.linearize(at={"theta": "pi"})
    mc, m, l, g = (cart_pole.layout.parameter_defaults[k] for k in ("mc", "m", "l", "g"))
    assert lin.point.coordinates["theta"] == pytest.approx(math.pi, abs=1e-15)
    assert np.abs(lin.eigenvalues) == pytest.approx([math.sqrt((mc + m) * g / (mc * l))] * 2, rel=1e-10)
    assert np.all(lin.eigenvalues.real == 0) and lin.verdict != "unstable"


def test_linearize_refuses_unknown_names_like_simulate(cart_pole):
    with pytest.raises(UsageError, match="unknown parameter 'M'"):
        cart_pole.linearize(parameters={"M": 1.0})
    with pytest.raises(UsageError, match=r"at=: unknown name 'tehta'[\s\S]*did you mean 'theta'"):
        cart_pole.linearize(at={"tehta": 0.1})


def hoop_equilibria(system, omega: float) -> dict[float, str]:
    found = system.equilibria(parameters={"Omega": omega})
    return {round(e.point["theta"] % (2 * math.pi), 9): e for e in found}


@pytest.mark.parametrize("omega", [3.0, 4.0, 6.0, 9.0])
def test_bead_on_hoop_equilibria_on_both_sides_of_the_bifurcation(hoop, omega):
    """theta'' = (Omega^2 cos th - g/R) sin th: th = 0 and th = pi always; cos th =
    g/(R Omega^2) too when Omega^2 > g/R, oscillating there at Omega sin th. The
    bottom: stable below (frequency sqrt(g/R - Omega^2)), unstable above; the top
    always unstable (rate sqrt(Omega^2 + g/R))."""
    g, R = (hoop.layout.parameter_defaults[k] for k in ("g", "R"))
    found = hoop_equilibria(hoop, omega)
    expected = {0.0, round(math.pi, 9)}
    above = omega ** 2 > g / R
    if above:
        off = math.acos(g / (R * omega ** 2))
        expected |= {round(off, 9), round(2 * math.pi - off, 9)}
    assert set(found) == expected
    bottom, top = found[0.0], found[round(math.pi, 9)]
    assert top.verdict == "unstable"
    assert np.abs(top.eigenvalues) == pytest.approx([math.sqrt(omega ** 2 + g / R)] * 2, rel=1e-9)
    assert bottom.verdict == ("unstable" if above else "stable")
    assert np.abs(bottom.eigenvalues) == pytest.approx([math.sqrt(abs(omega ** 2 - g / R))] * 2, rel=1e-9)
    for theta, e in found.items():
        if theta not in (0.0, round(math.pi, 9)):
            assert e.verdict == "stable"
            assert e.frequencies == pytest.approx((omega * math.sin(off),), rel=1e-9)
            assert np.all(e.eigenvalues.real == 0)
            assert e.linearization.point.coordinates["theta"] == e.point["theta"]


def test_equilibria_closed_forms_are_sympy_expressions(hoop):
    import sympy as sp

    found = hoop.equilibria()
    off = next(e for e in found if 0 < e.point["theta"] < math.pi / 2)
    R, g, omega = (hoop.model.symbol(n) for n in ("R", "g", "Omega"))
    assert sp.simplify(sp.cos(off.closed_form["theta"]) - g / (R * omega ** 2)) == 0


def test_hamiltonian_and_routh_are_values(hoop):
    import sympy as sp

    h = hoop.hamiltonian()
    m, R, g, omega = (hoop.model.symbol(n) for n in ("m", "R", "g", "Omega"))
    theta, theta_dot = hoop.model.symbol("theta"), hoop.model.symbol("theta_dot")
    p = sp.Symbol("p_theta", real=True)
    # p = m R^2 th', H = p^2/(2 m R^2) - m R^2 Omega^2 sin^2 th/2 - m g R cos th (by hand)
    assert sp.simplify(h.momenta["p_theta"] - m * R ** 2 * theta_dot) == 0
    assert sp.simplify(h.H - (p ** 2 / (2 * m * R ** 2) - m * R ** 2 * omega ** 2 * sp.sin(theta) ** 2 / 2
                              - m * g * R * sp.cos(theta))) == 0
    assert set(h.equations) == {"theta_dot", "p_theta_dot"}
    sphere = lagcli.load(SPECS / "spherical_pendulum.yaml")
    routh = sphere.routh(momenta={"p_phi": 0.5}, guesses=[{"theta": 1.0}])
    (motion,) = routh.steady_motions
    th0 = motion.coordinates["theta"]
    g, L = (sphere.layout.parameter_defaults[k] for k in ("g", "L"))
    # conical motion: phi_dot^2 = g/(L cos th0), small oscillations at phi_dot sqrt(1 + 3 cos^2 th0)
    rate = motion.cyclic_rates["phi_dot"]
    assert rate ** 2 == pytest.approx(g / (L * math.cos(th0)), rel=1e-9)
    assert motion.frequencies == pytest.approx((rate * math.sqrt(1 + 3 * math.cos(th0) ** 2),), rel=1e-9)
    assert routh.cyclic == ("phi",) and routh.momenta == ("p_phi",)


def test_linearize_sweep_finds_the_rolling_disc_critical_spin():
    """The upright rolling disc is stable for w^2 > g/(3 r)."""
    disc = lagcli.load(SPECS / "rolling_disc.yaml")
    g, r = (disc.layout.parameter_defaults[k] for k in ("g", "r"))
    found = disc.linearize_sweep("w", np.linspace(2, 6, 5), at={"phi_dot": "w", "x_dot": "r*w"},
                                 find_critical=True)
    assert found.values.tolist() == [2, 3, 4, 5, 6]
    assert found.verdicts[:2] == ("unstable",) * 2
    assert (critical := found.critical[0]).value == pytest.approx(math.sqrt(g / (3 * r)), rel=1e-4)
    assert (critical.unstable_below, critical.unstable_above) == (1, 0)


# -- displays ------------------------------------------------------------------------

def well_formed_latex(text: str) -> None:
    assert text.startswith("$$") and text.endswith("$$") and text.count("$$") == 2, text
    depth = 0
    for char in re.sub(r"\\[{}]", "", text):
        depth += {"{": 1, "}": -1}.get(char, 0)
        assert depth >= 0, text
    assert depth == 0, text
    environments = re.findall(r"\\(begin|end)\{(\w+\*?)\}", text)
    stack = []
    for kind, name in environments:
        if kind == "begin":
            stack.append(name)
        else:
            assert stack and stack.pop() == name, text
    assert not stack, text
    assert "\\\\ \\end" not in text and "&&" not in text


def well_formed_html(text: str) -> ET.Element:
    return ET.fromstring(f"<div>{text}</div>")        # raises on an unclosed or stray tag


def test_every_result_shows_itself_in_a_notebook(cart_pole, hoop):
    lin = cart_pole.linearize()
    well_formed_latex(lin._repr_latex_())
    html = well_formed_html(lin._repr_html_())
    assert [c.text for c in html.iter("caption")] == ["A", "B", "M", "C", "K", "H"]     # H: F is an input
    assert r"\dot{\theta}" in lin._repr_latex_() and "unstable" in lin._repr_latex_()
    assert repr(lin).startswith("<Linearization of cart_pole about x = 0, theta = 0") and len(repr(lin)) < 200
    found = hoop.equilibria()
    rows = well_formed_html(found._repr_html_()).findall(".//tr")
    assert len(rows) == 1 + len(found) == 5
    assert "4 found" in repr(found)
    for e in found:
        well_formed_latex(e.linearization._repr_latex_())
    well_formed_latex(hoop.hamiltonian()._repr_latex_())
    well_formed_latex(lagcli.load(SPECS / "spherical_pendulum.yaml").routh()._repr_latex_())
    sweep = lagcli.load(SPECS / "rolling_disc.yaml").linearize_sweep("w", [2, 4], at={"phi_dot": "w"})
    well_formed_html(sweep._repr_html_())


# -- the Trajectory ------------------------------------------------------------------

@pytest.fixture(scope="module")
def swing(tmp_path_factory):
    import os

    os.environ.setdefault("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("xdg-cache")))
    return lagcli.load(SPECS / "double_pendulum.yaml").simulate(t_end=5.0, dt=0.01)


def test_columns_are_names_and_each_indexes_the_trajectory(swing):
    assert swing.columns == ("t", "theta1", "theta2", "theta1_dot", "theta2_dot", "energy", "jacobi")
    for name in swing.columns:
        assert swing[name].shape == (501,)
    assert swing[swing.columns[1]][0] == swing.states[0, 0]
    assert [(c.name, c.kind) for c in swing.column_info][:2] == [("t", "time"), ("theta1", "coordinate")]
    with pytest.raises(KeyError, match="no column 'theta3'"):
        swing["theta3"]


def test_short_repr_and_html_table(swing):
    assert repr(swing) == "Trajectory of double_pendulum: 501 rows \u00d7 7 columns, t = 0\u20265"
    html = swing._repr_html_()
    table = well_formed_html(html).find("table")
    rows = table.findall("tr")
    assert [th.text for th in rows[0]] == list(swing.columns)
    assert len(rows) == 1 + 5 + 1 + 5                      # header, first five, ellipsis, last five
    assert all(td.text == "\u2026" for td in rows[6])
    assert [float(td.text) for td in rows[-1]][0] == 5.0 and "501 rows \u00d7 7 columns" in table.find("caption").text
    assert len(html) < 4000


def test_to_pandas_is_indexed_by_t(swing):
    pd = pytest.importorskip("pandas")
    frame = swing.to_pandas()
    assert isinstance(frame.index, pd.Index) and frame.index.name == "t"
    assert frame.shape == (501, 6) and list(frame.columns) == list(swing.columns[1:])
    assert frame.loc[2.5, "theta1"] == swing["theta1"][250]


MAGIC = {"png": (b"\x89PNG",), "svg": (b"<?xml", b"<svg"), "pdf": (b"%PDF",)}


@pytest.mark.parametrize("suffix", ["png", "svg", "pdf"])
def test_plot_and_simulate_plot_write_the_format_the_extension_names(tmp_path, suffix, monkeypatch):
    """The same figure from `Trajectory.plot` and `lagcli simulate --plot`, byte for byte,
    in the format the file name says; SVG and PDF the same bytes on every run."""
    pytest.importorskip("matplotlib")
    from click.testing import CliRunner

    from lagcli.cli import cli

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    spec = SPECS / "cart_pole.yaml"
    lagcli.load(spec).simulate(t_end=0.5, backend="python").plot(tmp_path / f"api.{suffix}")
    for name in ("cli", "again"):
        done = CliRunner().invoke(cli, ["simulate", str(spec), "--t-end", "0.5", "--backend", "python",
                                        "-o", str(tmp_path / "c.csv"), "--plot", str(tmp_path / f"{name}.{suffix}")])
        assert done.exit_code == 0, done.output
    data = (tmp_path / f"cli.{suffix}").read_bytes()
    assert data.startswith(MAGIC[suffix])
    assert data == (tmp_path / f"api.{suffix}").read_bytes() == (tmp_path / f"again.{suffix}").read_bytes()


@pytest.mark.parametrize("name", ["p.jpg", "plot"])
def test_plot_refuses_a_format_it_cannot_name(tmp_path, name):
    from click.testing import CliRunner

    from lagcli.cli import cli

    done = CliRunner().invoke(cli, ["simulate", str(SPECS / "cart_pole.yaml"), "--t-end", "0.1",
                                    "-o", str(tmp_path / "c.csv"), "--plot", str(tmp_path / name)])
    assert done.exit_code == 2 and "Traceback" not in done.output
    assert "extension names the picture's format: .png, .svg, .pdf" in done.output and "hint:" in done.output
    assert not (tmp_path / "c.csv").exists()                 # refused before any work


def test_animate_writes_one_frame_as_svg_or_pdf(tmp_path):
    pytest.importorskip("matplotlib")
    from click.testing import CliRunner

    from lagcli.cli import cli

    for suffix in ("svg", "pdf"):
        out = tmp_path / f"frame.{suffix}"
        done = CliRunner().invoke(cli, ["animate", str(SPECS / "cart_pole.yaml"), "--t-end", "0.2",
                                        "--frame", "0.1", "-o", str(out)])
        assert done.exit_code == 0, done.output
        assert out.read_bytes().startswith(MAGIC[suffix])
    done = CliRunner().invoke(cli, ["animate", str(SPECS / "cart_pole.yaml"), "-o", str(tmp_path / "m.svg")])
    assert done.exit_code == 2 and "one frame: give --frame T" in done.output


def test_repr_gives_the_time_unit_when_the_spec_gives_units(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    run = lagcli.load(SPECS.parent / "tests" / "data" / "units_cart_pendulum.yaml").simulate(t_end=0.5, dt=0.1)
    assert repr(run).endswith(", t = 0\u20260.5 s")
