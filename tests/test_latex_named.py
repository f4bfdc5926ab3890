"""Big systems in the reports: named intermediate quantities (lagcli/report/naming.py).

A big report writes its recurring sums once, as X_1, X_2, ... in a last section, and
the expressions with the names. Checked here:

- the named form is the expression: the text report's equations, M and constraints,
  with the definitions substituted back, equal the unnamed ones (numerically);
- each name is defined once, before the definitions that use it, and used;
- the LaTeX document compiles with no line running off the page and few pages.

The default run uses the rolling disc and Ex 20 with the naming budgets lowered so
that their reports are "big" ones (cheap); the bicycle itself runs with `pytest -m slow`.
"""
from __future__ import annotations

import re

import numpy as np
import pytest
import sympy as sp
from sympy.parsing.sympy_parser import parse_expr, standard_transformations

import lagcli.report.naming as naming
from lagcli.report.latex import latex_document
from lagcli.report.naming import Namer
from lagcli.report.content import report_content, spec_printer
from test_latex import compile_pdf, needs_pdflatex, overfull

OVERFULL_TOLERANCE_PT = 5.0
NAME = re.compile(r"X_\{(\d+)\}")


@pytest.fixture
def low_budgets(monkeypatch):
    """Budgets low enough for the reports of the rolling disc and Ex 20 to be big ones."""
    monkeypatch.setattr(naming, "SHOW_MAX_NODES", 60)
    monkeypatch.setattr(naming, "BIG_SHOW_MAX_NODES", 20)
    monkeypatch.setattr(naming, "NAME_MIN_NODES", 6)


def named_section(document: str) -> tuple[str, list[tuple[int, str]]]:
    """(the document before "Named quantities", [(k, LaTeX of X_k's definition)])."""
    body, _, named = document.partition(r"\subsection*{Named quantities}")
    definitions = []
    for line in named.splitlines():
        row = line.strip().removesuffix(r"\\").strip()
        head = re.match(r"X_\{(\d+)\} &= ", row)
        if head:
            definitions.append((int(head.group(1)), row[head.end():]))
        elif row.startswith(r"&\quad") and definitions:
            k, text = definitions[-1]
            definitions[-1] = (k, f"{text} {row}")
    return body, definitions


def assert_defined_once_and_used(document: str, every_part: bool = True) -> int:
    body, definitions = named_section(document)
    numbers = [k for k, _ in definitions]
    assert numbers == sorted(set(numbers)), "each name defined once, in order"
    if every_part:
        assert numbers == list(range(1, len(numbers) + 1))
    used = {int(k) for k in NAME.findall(body)}
    for k, text in definitions:
        inside = {int(j) for j in NAME.findall(text)}
        assert all(j < k for j in inside), f"X_{k} uses a name defined after it"
        used |= inside
    assert used == set(numbers), "a name is used but not defined, or defined but not used"
    return len(numbers)


@needs_pdflatex
def test_a_part_lists_the_definitions_it_uses(derived, low_budgets, tmp_path):
    d = derived("ex20_spinning_disk_double_pendulum")
    whole = len(named_section(latex_document(d))[1])
    equations = latex_document(d, parts=("equations",))
    assert 0 < assert_defined_once_and_used(equations, every_part=False) < whole
    compile_pdf(equations, tmp_path)


# -- the named form is the expression ---------------------------------------------------

def _parse(text: str, names: dict) -> sp.Expr:
    return parse_expr(text, local_dict=names, transformations=standard_transformations)


@pytest.mark.parametrize("name", ["rolling_disc", "ex20_spinning_disk_double_pendulum"])
def test_named_text_report_is_the_expression(name, derived, low_budgets):
    d = derived(name)
    m = d.model
    named = report_content(d, spec_printer(), named=True)
    whole = report_content(d, spec_printer(), named=False)
    assert len(named["named_quantities"]) >= 2
    names = {s.name: s for s in (m.t, *m.q, *m.qd, *m.qdd, *m.parameter_symbols, *d.multipliers)}
    definitions = []
    for item in named["named_quantities"]:
        symbol = names[item["name"]] = sp.Symbol(item["name"], real=True)
        definitions.append((symbol, _parse(item["expr"], names)))

    def expanded(text: str) -> sp.Expr:
        expr = _parse(text, names)
        for symbol, value in reversed(definitions):    # later names use earlier ones
            expr = expr.xreplace({symbol: value})
        return expr

    pairs = [(a["lhs"], b["lhs"]) for a, b in zip(named["equations"], whole["equations"])]
    pairs += [(x, y) for ra, rb in zip(named["mass_matrix"], whole["mass_matrix"]) for x, y in zip(ra, rb)]
    pairs += [(a["expr"], b["expr"]) for a, b in zip(named["constraints"], whole["constraints"])]
    pairs.append((named["kinetic_energy"]["T"], whole["kinetic_energy"]["T"]))
    assert any(re.search(r"\bX\d+\b", a) for a, _ in pairs)
    rng = np.random.default_rng(5)
    for shown, full in pairs:
        difference = expanded(shown) - _parse(full, names)
        symbols = sorted(difference.free_symbols, key=sp.default_sort_key)
        for _ in range(3):
            values = {s: rng.uniform(0.3, 1.3) for s in symbols}
            assert abs(float(difference.xreplace(values))) < 1e-9, (shown, full)


def test_a_sum_gets_one_name_wherever_it_occurs(monkeypatch):
    monkeypatch.setattr(naming, "SHOW_MAX_NODES", 10)
    monkeypatch.setattr(naming, "BIG_SHOW_MAX_NODES", 10)
    monkeypatch.setattr(naming, "NAME_MIN_NODES", 6)
    a, b, c, x, y = sp.symbols("a b c x y", real=True)
    shared = a * sp.sin(x) + b * sp.cos(y) + c
    namer = Namer(["a", "b", "c", "x", "y", "X1"])
    first = namer(x ** 2 * shared + y * sp.sin(shared))
    second = namer(y ** 3 * shared - x * sp.cos(x * y))
    assert namer.prefix == "XX"                       # X1 is a spec's name: not reused
    [(symbol, value)] = namer.definitions
    assert value == shared and symbol.name == "XX1"
    assert symbol in first.free_symbols and symbol in second.free_symbols
    assert namer(x + y) == x + y                      # small: as it is


def test_a_small_system_has_no_names(derived):
    for name in ("ex20_spinning_disk_double_pendulum", "heavy_symmetric_top", "rolling_disc"):
        assert "Named quantities" not in latex_document(derived(name)), name


# -- the LaTeX document ----------------------------------------------------------------

def _pages(log: str) -> int:
    return int(re.search(r"Output written on \S+ \((\d+) pages?", log).group(1))


@needs_pdflatex
def test_named_document_compiles_short_and_within_the_margins(derived, low_budgets, tmp_path):
    document = latex_document(derived("rolling_disc"))
    assert assert_defined_once_and_used(document) >= 2
    log = compile_pdf(document, tmp_path)
    assert [w for w in overfull(log) if w > OVERFULL_TOLERANCE_PT] == []
    assert _pages(log) <= 6


@pytest.mark.slow
@needs_pdflatex
def test_bicycle_document_is_readable(derived, tmp_path):
    """The 8-coordinate bicycle (4 bodies, 5 constraints): tens of pages, not hundreds."""
    document = latex_document(derived("benchmark_bicycle"))
    assert assert_defined_once_and_used(document) > 100
    log = compile_pdf(document, tmp_path)
    assert [w for w in overfull(log) if w > OVERFULL_TOLERANCE_PT] == []
    assert _pages(log) <= 40
