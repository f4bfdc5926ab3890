"""The user's names win (issue 21, item 4): a spec whose parameters are called M, c, F, g,
T, V, L, h keeps those names in the text report, the LaTeX report, the notebook and the
page; the report's own quantities yield (bold M, script L, Mmat/Lag in text) and the
report's legend says what each one is."""
from __future__ import annotations

import json
import re
import shutil
import subprocess

import pytest
import sympy as sp

import lagcli

CLASH = """\
name: clash
description: A pendulum on a damped cart, its parameters named like the report's letters
coordinates: [x, theta]
parameters: {M: 2.0, m: 0.5, L: 1.0, g: 9.81, c: 0.3, F: 0.0, T: 0.1, V: 0.2, h: 0.4}
gravity: [0, -g]
bodies:
  cart: {mass: M, inertia: 0, position: [x, h], angle: 0}
particles:
  bob: {mass: m, position: [x + L*sin(theta), h - L*cos(theta)]}
forces:
  - {at: cart, force: [F, 0]}
potential: T*theta**2/2 + V*x**2/2
generalized_forces:
  x: -c*x_dot
initial: {theta: 0.2}
"""
USER = ("M", "c", "F", "g", "T", "V", "L", "h")


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    path = tmp_path_factory.mktemp("names") / "clash.yaml"
    path.write_text(CLASH)
    return lagcli.load(path)


def test_text_report_keeps_the_names_and_its_own_letters_yield(system):
    text = system.report("text")
    assert "parameters        : M = 2.0, m = 0.5, L = 1.0, g = 9.81, c = 0.3, F = 0.0, T = 0.1, V = 0.2, h = 0.4" in text
    assert not re.search(r"\b(M|c|F|g|T|V|L|h)_\b", text)              # no M_, c_ ...
    # the mass matrix as a hand derivation gives it, in the user's letters (M + m, L m cos)
    assert "  [M + m,  L*m*cos(theta)]" in text
    assert "[x]  (M + m)*x_ddot + L*m*theta_ddot*cos(theta) - L*m*theta_dot**2*sin(theta) + c*x_dot - F + V*x = 0" in text
    # the report's own quantities are named apart from every user name, and the legend says so
    for label in ("Tkin  = Tkin2 = ", "mass matrix Mmat (Tkin2 = 1/2 qdot' Mmat qdot)", "Vpot = ",
                  "Lag = Tkin - Vpot = ", "cvel(q, qdot) = "):
        assert label in text
    legend = next(line for line in text.splitlines() if line.startswith("notation"))
    for shown, meaning in (("Tkin", "kinetic energy"), ("Vpot", "potential energy"), ("Lag", "Lagrangian"),
                           ("Mmat", "mass matrix"), ("Fvec", "forcing"), ("cvel", "velocity terms")):
        assert f"{shown} = the {meaning}" in legend
    for line in text.splitlines():                  # no report label is a user name
        label = line.split(" = ")[0].strip()
        assert label not in USER, line


def test_json_keeps_every_name(system):
    report = json.loads(system.report("json"))
    assert list(report["parameters"]) == ["M", "m", "L", "g", "c", "F", "T", "V", "h"]
    assert report["renamed_parameters"] == {}
    M, m, L, theta = sp.symbols("M m L theta")
    assert sp.simplify(sp.sympify(report["mass_matrix"][0][0]) - (M + m)) == 0


def test_latex_report_keeps_the_names_and_compiles(system, tmp_path):
    tex = system.report("latex")
    assert not re.search(r"\\mathsf\{\w+\}", tex)             # no sans-serif user letters
    for name in USER:
        assert f"${name}$ & $" in tex                    # the parameter table, as named
    assert r"\mathbf{M} = \begin{pmatrix} M + m & L\,m\,\cos{\left(\theta \right)}" in tex
    assert r"\mathcal{L} &= \mathcal{T} - \mathcal{V}" in tex
    assert r"\mathbf{F}_{x} &= " in tex and r"\mathbf{c}_{x} &= " in tex
    legend = next(line for line in tex.splitlines() if line.startswith("Notation:"))
    assert r"$\mathbf{M}$ denotes the mass matrix" in legend and r"$\mathcal{L}$ denotes the Lagrangian" in legend
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex is not installed")
    (tmp_path / "clash.tex").write_text(system.report("latex-document"))
    run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "clash.tex"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-2000:]


def test_notebook_keeps_the_names(system):
    parts = system.parts
    assert repr(parts.mass_matrix).startswith("Mmat = [[M + m, L*m*cos(theta)]")
    assert parts.mass_matrix.latex.startswith(r"\mathbf{M} = \begin{pmatrix} M + m")
    assert parts.lagrangian.latex.startswith(r"\begin{aligned}\mathcal{L} &= \mathcal{T} - \mathcal{V}")
    assert parts.energy.latex.startswith(r"\begin{aligned}E &= \mathcal{T} + \mathcal{V} = ")
    shown = system._repr_latex_()
    assert r"\mathsf" not in shown and r"+ c\,\dot{x} - F + V\,x = 0" in shown


def test_page_keeps_the_names(system):
    html = system.page(pictures=False)
    for name in USER:
        assert f"<mi>{name}</mi>" in html
    assert "<mi>\U0001d4af</mi><mo>=</mo>" in html                 # 𝒯 = ... (script T: the kinetic energy)
    assert "\u2112 denotes the Lagrangian" in html                  # ℒ
    assert "<mi>M_</mi>" not in html and "mathsf" not in html


def test_a_spec_without_such_names_keeps_the_letters():
    system = lagcli.load("specs/double_pendulum.yaml")
    text = system.report("text")
    assert "notation " not in text and "L  = T - V = " in text and "mass matrix M (" in text
    assert "Notation:" not in system.report("latex")
    assert repr(system.parts.mass_matrix).startswith("M = [[")


HEIGHT_AND_RADIUS = """\
name: bowl
coordinates: [theta, phi]
parameters: {m: 1.0, R: 1.0, g: 9.81, H: 0.2}
gravity: [0, 0, -g]
particles:
  P: {mass: m, position: [R*sin(theta)*cos(phi), R*sin(theta)*sin(phi), H - R*cos(theta)]}
initial: {theta: 1.0, phi_dot: 1.0}
"""


def test_the_analyses_letters_yield_too(tmp_path):
    """A height H and a radius R: the Hamiltonian is Ham (script H), the Routhian Routh."""
    from lagcli import commands

    path = tmp_path / "bowl.yaml"
    path.write_text(HEIGHT_AND_RADIUS)
    text = commands.hamiltonian(str(path))
    ham = next(line for line in text.splitlines() if line.startswith("Ham = "))
    assert "\nH = " not in text and re.search(r"\bH\b", ham.removeprefix("Ham = "))   # the spec's H inside
    latex = commands.hamiltonian(str(path), fmt="latex")
    assert r"\mathcal{H} &= " in latex
    system = lagcli.load(path)
    assert r"\mathcal{H} &= " in system.hamiltonian()._repr_latex_()
    reduction = system.routh(momenta={"p_phi": 0.5}, guesses=[{"theta": 1.0}])
    assert "Routh = " in commands.routh(str(path), momenta=["p_phi=0.5"], guesses=["theta=1"])
    assert r"\mathcal{R} &= " in reduction._repr_latex_()
