"""The notebook shows what `lagcli derive` shows (issue 21: one display form everywhere).

For every bundled spec, `system.parts.mass_matrix`, `.equations` and `.constraints` are
the rows of `lagcli derive --latex` (the same tidying, q'' terms first, the same named
quantities), and no notebook surface of any bundled spec (each part's text and LaTeX,
`System._repr_latex_`) holds an untidied sin(x)**2 + cos(x)**2, sqrt(1 - sin(x)**2) or
x/Abs(x). The checks compare against the independent report path and against sympy:
a left-over Pythagorean pair is found by `sympy.trigsimp` shrinking an entry.
"""
from __future__ import annotations

import re

import pytest
import sympy as sp

import lagcli
from conftest import SPECS

BUNDLED = sorted(p.relative_to(SPECS).with_suffix("").as_posix()
                 for p in [*SPECS.glob("*.yaml"), *SPECS.glob("hybrid/*.yaml")])
UNTIDY = [re.compile(r"sin\((\w+)\)\*\*2 \+ \w*\**cos\(\1\)\*\*2"), re.compile(r"sqrt\(1 - (sin|cos)\("),
          re.compile(r"Abs\(")]


@pytest.fixture(scope="module")
def systems():
    return {}


def system_of(systems, name):
    if name not in systems:
        systems[name] = lagcli.load(SPECS / f"{name}.yaml")
    return systems[name]


@pytest.mark.parametrize("name", BUNDLED)
def test_notebook_parts_are_the_latex_report_rows(systems, name):
    system = system_of(systems, name)
    fragment = system.report("latex")
    wanted = ["mass_matrix", "equations"] + (["constraints"] if system.derivation.constraints else [])
    for part_name in wanted:
        part = getattr(system.parts, part_name)
        assert part.rows, part_name
        for row in part.rows:
            assert row in fragment, f"{name}: {part_name} row not in derive --latex:\n{row}"
    shown = system._repr_latex_()
    assert all(row in shown for row in system.parts.equations.rows)
    assert list(system.parts.equations.rows) == block_rows(fragment, r"\subsection*{Equations of motion}")
    if system.derivation.constraints:
        assert list(system.parts.constraints.rows) == constraint_rows(fragment)


def block_rows(fragment: str, heading: str) -> list[str]:
    """The rows of the first align* block after `heading` in a LaTeX report."""
    body = fragment.split(heading, 1)[1].split(r"\begin{align*}", 1)[1].split(r"\end{align*}", 1)[0]
    return [line.strip().removesuffix(r"\\").strip() for line in body.strip().splitlines()]


def constraint_rows(fragment: str) -> list[str]:
    """Each constraint's `= 0` row (with its `&\\quad` continuations, before its row of a) in
    the Constraints section."""
    section = fragment.split(r"\subsection*{Constraints}", 1)[1].split(r"\subsection*", 1)[0]
    rows = []
    for item in section.split(r"\noindent Constraint ")[1:]:
        block = item.split(r"\begin{align*}", 1)[1].split(r"\end{align*}", 1)[0]
        lines = [line.strip().removesuffix(r"\\").strip() for line in block.strip().splitlines()]
        rows += lines[:next(k for k, line in enumerate(lines) if k and not line.startswith("&"))]
    return rows


@pytest.mark.parametrize("name", BUNDLED)
def test_no_untidy_forms_on_notebook_surfaces(systems, name):
    system = system_of(systems, name)
    texts = [repr(getattr(system.parts, p)) for p in dir(system.parts)]
    for text in texts:
        for pattern in UNTIDY:
            assert not pattern.search(text), f"{name}: {pattern.pattern} in\n{text[:400]}"
    entries = system.report("dict")["mass_matrix"]
    assert system.parts.mass_matrix.text == "M = [" + ", ".join(
        "[" + ", ".join(row) + "]" for row in entries) + "]"
    if len(entries) <= 6:              # an independent look: trigsimp finds nothing to shrink
        from lagcli.render.spec_printer import parse_output

        for text in [e for row in entries for e in row if "sin" in e or "cos" in e][:12]:
            value = parse_output(text, system.model)
            assert sp.count_ops(sp.trigsimp(value)) >= sp.count_ops(value), text
