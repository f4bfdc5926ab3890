"""One notation per output for `linearize` (issue 21): x' = A x + B u and
M v' + C v + K q = F u, no letter used for two things in one output, none of the
output's own letters a name the spec uses there (the cart-pole's coordinate x and
input F), the same letters in text, LaTeX, JSON and the notebook's displays."""
from __future__ import annotations

import json
import re

import pytest
from click.testing import CliRunner

import lagcli
from lagcli.cli import cli
from lagcli.report.notation import linear_letters

FIRST = re.compile(r"^(\w+)' = (\w+) (\w+)(?: \+ (\w+) (\w+))?,  (\w+) = \(([^)]*)\)(?:, (\w+) = \(([^)]*)\))?$")
SECOND = re.compile(r"^second-order form  (\w+) (\w+)' \+ (\w+) (\w+) \+ (\w+) (\w+) = (?:(\w+) (\w+)|0),"
                    r"  (\w+) = \(([^)]*)\), (\w+) = \(([^)]*)\)$")


def _linearize(spec: str, *args: str) -> str:
    result = CliRunner().invoke(cli, ["linearize", spec, *args])
    assert result.exit_code == 0, result.output
    return result.output


def _names(line: str, prefix: str) -> set[str]:
    """The names of `name = value, ...` after `prefix`."""
    return {item.split(" = ")[0] for item in line[len(prefix):].split(", ")}


@pytest.mark.parametrize("spec", ["specs/cart_pole.yaml", "specs/double_pendulum.yaml",
                                  "specs/atwood.yaml"])
def test_one_letter_one_thing_in_the_text(spec):
    text = _linearize(spec)
    lines = text.splitlines()
    first = next(FIRST.match(line) for line in lines if FIRST.match(line))
    second = next(SECOND.match(line) for line in lines if SECOND.match(line))
    x, A, x1, B, u, x2, states, u2, inputs = first.groups()
    assert x == x1 == x2 and (B is None or u == u2)
    M, v, C, v1, K, q, F, u3, v2, speeds, q2, coordinates = second.groups()
    assert v == v1 == v2 and q == q2 and (F is None or u3 == u)
    own = [x, A, M, C, K, v, q] + ([B, u, F] if B else [])
    assert len(own) == len(set(own)), own                      # each letter one thing
    spec_names = set(states.split(", ")) | set(coordinates.split(", ")) | set(speeds.split(", "))
    spec_names |= _names(next(line for line in lines if line.startswith("parameters: ")), "parameters: ")
    if inputs:
        spec_names |= set(inputs.split(", "))
    assert not spec_names & set(own), spec_names & set(own)    # and none a name of the spec
    labels = {line[:-2] for line in lines if line.endswith(" =")}
    assert labels <= set(own), labels - set(own)               # every matrix printed is one of them


def test_cart_pole_letters_in_every_display():
    """The cart-pole has a coordinate x and an input F: the state is z, F's matrix H."""
    text = _linearize("specs/cart_pole.yaml")
    assert "z' = A z + B u,  z = (x, theta, x_dot, theta_dot), u = (F)" in text
    assert "second-order form  M v' + C v + K q = H u,  v = (x_dot, theta_dot), q = (x, theta)" in text
    content = json.loads(_linearize("specs/cart_pole.yaml", "--json"))
    assert content["notation"]["x"] == "z" and content["notation"]["F"] == "H"
    assert content["second_order"]["B"] == [[1.0], [0.0]]            # the keys kept
    latex = _linearize("specs/cart_pole.yaml", "--latex")
    assert r"z' &= A\,z + B\,u" in latex and r"M\,v' + C\,v + K\,q &= H\,u" in latex
    lin = lagcli.load("specs/cart_pole.yaml").linearize()
    assert lin.letters == content["notation"]
    shown = lin._repr_latex_()
    assert r"z' &= A\,z + B\,u" in shown and r"H = \begin{bmatrix}" in shown and "u_in" not in shown
    assert "z&#x27; = A z + B u; M v&#x27; + C v + K q = H u" in lin._repr_html_()


def test_a_matrix_letter_the_spec_takes_yields():
    letters = linear_letters(["K", "x", "u", "w"])
    assert letters["K"] == "K_lin" and letters["x"] == "z" and letters["u"] == "e"
    assert len(set(letters.values())) == len(letters)
