"""Velocities and accelerations print as the lecture notes write them (q̇, q̈) under
sympy's own display printers, and as `q_dot` / `q_ddot` everywhere a machine reads
them back (spec language, JSON, generated code)."""
from __future__ import annotations

import pickle

import sympy as sp

import lagcli
from lagcli.render.spec_printer import parse_output, spec_str

from conftest import SPECS


def _pendulum():
    return lagcli.load(SPECS / "double_pendulum.yaml").model


def test_latex_and_pretty_show_dots():
    model = _pendulum()
    theta1_dot, theta2_ddot = model.qd[0], model.qdd[1]
    assert sp.latex(theta1_dot) == r"\dot{\theta}_{1}"
    assert sp.latex(theta2_ddot) == r"\ddot{\theta}_{2}"
    assert sp.pretty(theta1_dot) == "θ\N{COMBINING DOT ABOVE}₁"
    assert sp.pretty(theta2_ddot) == "θ\N{COMBINING DIAERESIS}₂"
    assert sp.pretty(theta1_dot, use_unicode=False) == "theta1_dot"
    assert sp.latex(theta1_dot ** 2 * sp.sin(model.q[0])) == r"\dot{\theta}_{1}^{2} \sin{\left(\theta_{1} \right)}"


def test_machine_readable_printers_keep_the_names():
    model = _pendulum()
    theta1_dot = model.qd[0]
    assert str(theta1_dot) == "theta1_dot"
    assert sp.ccode(theta1_dot) == "theta1_dot" and sp.pycode(theta1_dot) == "theta1_dot"
    expr = theta1_dot ** 2 * sp.cos(model.q[1]) + model.qdd[0]
    text = spec_str(expr)
    assert "theta1_dot" in text and "theta1_ddot" in text
    assert sp.simplify(parse_output(text, model) - expr) == 0


def test_symbols_stay_symbols():
    """Same sorting, equality after pickling, real: plain symbols in every other way."""
    model = _pendulum()
    theta1_dot = model.qd[0]
    assert pickle.loads(pickle.dumps(theta1_dot)) == theta1_dot
    assert theta1_dot.is_real and theta1_dot.is_Symbol
    assert theta1_dot.sort_key()[0] == sp.Symbol("x").sort_key()[0]


def test_a_user_latex_name_is_kept_by_lagcli_latex():
    system = lagcli.load(SPECS / "cartesian_pendulum.yaml")
    assert r"\ddot{x}" in system._repr_latex_()
