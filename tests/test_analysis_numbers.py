"""Analysis numbers a reader can trust (issue 21): round-off is not printed as data, a
zero gyroscopic matrix is not printed as a physical effect, and the verdict counts the
eigenvalues it speaks of. Each system's matrices are checked against a closed form."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import lagcli
from lagcli import commands

from conftest import SPECS

SPRING_CART = """\
name: spring_cart_pendulum
coordinates: [x, theta]
parameters: {M: 1.0, m: 0.3, l: 0.7, k: 5.0, c: 0.4, g: 9.81}
gravity: [0, -g]
particles:
  cart: {mass: M, position: [x, 0]}
  bob: {mass: m, position: [x + l*sin(theta), -l*cos(theta)]}
springs:
  - {between: [cart, [0, 0]], stiffness: k, rest_length: 0}
generalized_forces:
  x: -c*x_dot
"""

TWO_OSCILLATORS = """\
name: two_oscillators
coordinates: [x, y]
parameters: {m: 1.0, k: 4.0, c: 0.5}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: k*(x**2 + y**2)/2
generalized_forces:
  x: -c*x_dot
"""


def spec_file(tmp_path, text: str) -> str:
    path = tmp_path / "spec.yaml"
    path.write_text(text)
    return str(path)


def test_round_off_is_shown_as_zero_and_kept_in_json(tmp_path):
    """Spring-cart pendulum hanging down, by hand: M = [[M + m, m l], [m l, m l^2]],
    C = diag(c, 0), K = diag(k, m g l). The computed C and K carry ~1e-16 round-off
    off the diagonal (and so a skew part G ~ 1e-19): the text shows 0 and no G."""
    path = spec_file(tmp_path, SPRING_CART)
    lin = lagcli.load(SPRING_CART).linearize()
    M, m, l, k, c, g = 1.0, 0.3, 0.7, 5.0, 0.4, 9.81
    assert np.allclose(lin.M, [[M + m, m * l], [m * l, m * l ** 2]], rtol=0, atol=1e-14)
    assert np.allclose(lin.C, [[c, 0], [0, 0]], rtol=0, atol=1e-14)
    assert np.allclose(lin.K, [[k, 0], [0, m * g * l]], rtol=0, atol=1e-13)
    text = commands.linearize(path)
    matrices = text[text.index("second-order form"):text.index("eigenvalues")]  # M: M_lin
    assert "e-1" not in matrices and "gyroscopic" not in matrices
    assert "  theta_dot       0 2.0601" in matrices                # K's second row
    content = json.loads(commands.linearize(path, fmt="json"))
    assert content["round_off"]["relative"] == pytest.approx(1000 * np.finfo(float).eps)
    assert content["second_order"]["K"] == lin.K.tolist()         # every float as computed
    latex = commands.linearize(path, fmt="latex")
    assert "e-1" not in latex
    assert "e-1" not in lin._repr_latex_() and "e-1" not in lin._repr_html_()


def test_cart_pole_K_has_no_round_off_entry():
    text = commands.linearize(str(SPECS / "cart_pole.yaml"))
    assert "e-17" not in text and "e-16" not in text
    assert "  theta_dot        0 -0.4905" in text


def test_marginal_verdict_counts_the_eigenvalues_on_the_axis(tmp_path):
    """x damped, y not: x has -c/2 +- i sqrt(k/m - c^2/4), y +- i sqrt(k/m)."""
    lin = lagcli.load(TWO_OSCILLATORS).linearize()
    m, k, c = 1.0, 4.0, 0.5
    expected = [complex(0, math.sqrt(k / m)), complex(0, -math.sqrt(k / m)),
                complex(-c / 2, math.sqrt(k / m - c ** 2 / 4)), complex(-c / 2, -math.sqrt(k / m - c ** 2 / 4))]
    assert lin.eigenvalues == pytest.approx(expected, abs=1e-12)
    assert lin.verdict == "marginally stable"
    text = commands.linearize(spec_file(tmp_path, TWO_OSCILLATORS))
    assert ("verdict: marginally stable (2 of 4 eigenvalues on the imaginary axis, the others to its left, "
            "each with its own eigenvectors: the linear model does not decide)") in text
    assert "all eigenvalues on the imaginary axis" not in text


def test_cart_pole_A_and_B_shown_are_the_closed_form_with_exact_zeros():
    """Upright cart-pole (specs/cart_pole.yaml's header): x'' = -(m g / mc) theta + F / mc,
    theta'' = (mc + m) g / (mc l) theta - F / (mc l). What text, LaTeX and the notebook show
    (`report.shown`) has exact zeros where the closed form has them, and the text no e-1x."""
    from lagcli.analysis.report import shown

    lin = lagcli.load(SPECS / "cart_pole.yaml").linearize()
    mc, m, l, g = 1.0, 0.1, 0.5, 9.81
    A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, -m * g / mc, 0, 0], [0, (mc + m) * g / (mc * l), 0, 0]])
    B = np.array([[0], [0], [1 / mc], [-1 / (mc * l)]])
    for got, closed in ((lin.A, A), (lin.B, B)):
        np.testing.assert_allclose(got, closed, rtol=1e-12, atol=1e-14)
        assert np.all(shown(got)[closed == 0] == 0)
    assert np.count_nonzero(shown(lin.K)) == 1              # K = [[0, 0], [0, -m g l]]: round-off gone
    text = commands.linearize(str(SPECS / "cart_pole.yaml"))
    assert not any(f"e-{k}" in text for k in range(10, 20))
