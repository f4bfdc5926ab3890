"""LaTeX output: `derive --latex [--standalone]` and `generate --lang latex`.

- every bundled spec's document compiles with pdflatex, with no line running
  more than OVERFULL_LIMIT_PT past the margin (long expressions are broken);
- symbols: q, q_dot, q_ddot, parameters and multipliers are typeset from the
  model (no `x_{dot}`), text from the spec is escaped;
- the line breaking keeps the expression: run with a printer that prints the
  spec language instead of LaTeX, the broken lines parse back to the expression;
- golden files (tests/golden/latex/, rewrite with LAGCLI_UPDATE_GOLDEN=1), and
  the same spec gives the same bytes, also across processes.
"""
from __future__ import annotations

import difflib
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner
from sympy.parsing.sympy_parser import implicit_multiplication, parse_expr, standard_transformations

from lagcli.report.latex import latex_document, latex_fragment, latex_printer
from lagcli.render.escape import latex_text
from lagcli.report.latex_printer import LatexPrinter
from lagcli.render.spec_printer import spec_str

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "tests" / "golden" / "latex"
SPEC_NAMES = sorted(p.stem for p in (ROOT / "specs").glob("*.yaml"))
# The bicycles (tests/conftest.py HEAVY_SPECS) run with `pytest -m slow`.
LATEX_SPEC_NAMES = SPEC_NAMES
GOLDEN_SPECS = ["double_pendulum", "ex6_9_two_wheels_axle"]
OVERFULL_LIMIT_PT = 5.0
PDFLATEX = shutil.which("pdflatex")
needs_pdflatex = pytest.mark.skipif(PDFLATEX is None, reason="pdflatex is not installed "
                                    "(apt-get install texlive-latex-base texlive-latex-recommended)")


def compile_pdf(tex: str, directory: Path, stem: str = "doc") -> str:
    """Run pdflatex on `tex` in `directory`; returns the log (asserts success)."""
    (directory / f"{stem}.tex").write_text(tex, encoding="utf-8")
    run = subprocess.run([PDFLATEX, "-interaction=nonstopmode", "-halt-on-error", f"{stem}.tex"],
                         cwd=directory, capture_output=True, text=True, timeout=120)
    log = (directory / f"{stem}.log").read_text(encoding="latin-1")
    assert run.returncode == 0, f"pdflatex failed:\n{log[-3000:]}"
    assert (directory / f"{stem}.pdf").exists()
    return log


def overfull(log: str) -> list[float]:
    return [float(x) for x in re.findall(r"Overfull \\hbox \(([\d.]+)pt too wide\)", log)]


# -- every bundled spec ---------------------------------------------------------------

@needs_pdflatex
@pytest.mark.parametrize("name", LATEX_SPEC_NAMES)
def test_document_compiles_without_long_lines(name, derived, tmp_path):
    log = compile_pdf(latex_document(derived(name)), tmp_path)
    too_wide = [w for w in overfull(log) if w > OVERFULL_LIMIT_PT]
    assert not too_wide, f"{name}: lines too wide by {too_wide} pt"


@pytest.mark.parametrize("name", LATEX_SPEC_NAMES)
def test_fragment_symbols(name, derived):
    d = derived(name)
    fragment = latex_fragment(d)
    assert "dot}" not in fragment and "_{dot" not in fragment and "ddot}" not in fragment
    assert r"\begin{document}" not in fragment
    printer = latex_printer(d)
    for qd, qdd in zip(d.model.qd, d.model.qdd):
        assert printer.doprint(qd).startswith(r"\dot{")
        assert printer.doprint(qdd).startswith(r"\ddot{")
    for row in d.constraints:
        assert printer.doprint(row.multiplier).startswith(r"\lambda_{")
    for left, right in ((r"\biggl(", r"\biggr)"), (r"\Bigl(", r"\Bigr)"), (r"\bigl(", r"\bigr)")):
        assert fragment.count(left) == fragment.count(right)


# -- the symbol map and escaping ---------------------------------------------------------

SYMBOLS_SPEC = r"""
name: odd_names_1
description: 'Specials _ % & # $ { } ~ ^ \ < > | and unicode: café, θ, en–dash'
coordinates:
  - theta1
  - x
  - {name: phi2, latex: '\varphi_2'}
parameters:
  m: 1.0
  k: {value: 2.0, latex: '\kappa', description: 'stiffness, 100% of k_0 & more'}
  r: 0.5
potential: k*(x**2 + theta1**2 + phi2**2)/2
kinetic: m*(x_dot**2 + r**2*theta1_dot**2 + phi2_dot**2)/2
constraints:
  - {name: rolling, expr: x_dot - r*theta1_dot}
  - phi2_dot - x_dot
  - {name: roll_x, expr: phi2 - x - theta1}     # not phi2 - x: the row before, differentiated (dropped)
"""


@pytest.fixture(scope="module")
def odd_spec(tmp_path_factory):
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive

    path = tmp_path_factory.mktemp("latex") / "odd_names_1.yaml"
    path.write_text(SYMBOLS_SPEC, encoding="utf-8")
    return derive(load_model(path))


def test_symbol_map(odd_spec):
    m = odd_spec.model
    printer = latex_printer(odd_spec)
    theta1, x, phi2 = m.q
    expected = {
        theta1: r"\theta_{1}", m.qd[0]: r"\dot{\theta}_{1}", m.qdd[0]: r"\ddot{\theta}_{1}",
        x: "x", m.qd[1]: r"\dot{x}", m.qdd[1]: r"\ddot{x}",
        phi2: r"\varphi_2", m.qd[2]: r"\dot{\varphi}_2", m.qdd[2]: r"\ddot{\varphi}_2",
        m.symbol("k"): r"\kappa", m.symbol("m"): "m",
    }
    for symbol, tex in expected.items():
        assert printer.doprint(symbol) == tex, symbol
    multipliers = [printer.doprint(c.multiplier) for c in odd_spec.constraints]
    assert multipliers == [r"\lambda_{\mathrm{rolling}}", r"\lambda_{2}", r"\lambda_{\mathrm{roll\_x}}"]
    assert printer.doprint(m.qd[0] ** 2) == r"\dot{\theta}_{1}^{2}"


def test_latex_text():
    assert latex_text("a_b%c&d#e$f{g}h") == r"a\_b\%c\&d\#e\$f\{g\}h"
    assert latex_text("~^\\") == r"\textasciitilde{}\textasciicircum{}\textbackslash{}"
    assert latex_text("line\nbreak\x00") == "line break"


@needs_pdflatex
def test_spec_text_with_specials_compiles(odd_spec, tmp_path):
    document = latex_document(odd_spec)
    assert r"odd\_names\_1" in document and r"100\% of k\_0 \& more" in document
    compile_pdf(document, tmp_path)


def _chain_spec(n: int) -> str:
    """n coupled oscillators: n > 10 coordinates, more than a pmatrix can hold."""
    coords = ", ".join(f"q{i}" for i in range(1, n + 1))
    kinetic = " + ".join(f"q{i}_dot**2" for i in range(1, n + 1))
    springs = " + ".join(f"(q{i} - q{i + 1})**2" for i in range(1, n))
    return (f"name: chain{n}\ncoordinates: [{coords}]\nparameters: {{m: 1.0, k: 1.0}}\n"
            f"kinetic: m*({kinetic})/2 + m*q1_dot*q2_dot\npotential: k*({springs})/2\n")


@needs_pdflatex
def test_many_coordinates(tmp_path):
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive

    path = tmp_path / "chain12.yaml"
    path.write_text(_chain_spec(12), encoding="utf-8")
    document = latex_document(derive(load_model(path)))
    assert r"M_{1,2} &=" in document and r"egin{pmatrix}" not in document
    assert overfull(compile_pdf(document, tmp_path)) == []


# -- line breaking keeps the expression --------------------------------------------------

class SpecLanguageBreaker(LatexPrinter):
    """The same breaking, printing the spec language, so the lines parse back."""

    paren = ("(", ")")
    delimiters = (("(", ")"),)
    times = "*"

    def _print(self, expr, **kwargs):
        return spec_str(expr)


def _rejoin(lines: list[str], d) -> sp.Expr:
    m = d.model
    names = {s.name: s for s in (m.t, *m.q, *m.qd, *m.qdd, *m.parameter_symbols, *d.multipliers)}
    names.update(min=sp.Min, max=sp.Max, abs=sp.Abs)
    return parse_expr(" ".join(lines), local_dict=names,
                      transformations=standard_transformations + (implicit_multiplication,))


def _same_value(a: sp.Expr, b: sp.Expr, rng) -> bool:
    symbols = sorted(a.free_symbols | b.free_symbols, key=sp.default_sort_key)
    for _ in range(3):
        values = {s: sp.Float(rng.uniform(0.3, 1.3)) for s in symbols}
        va, vb = complex(a.xreplace(values).evalf()), complex(b.xreplace(values).evalf())
        if abs(va - vb) > 1e-9 * max(1.0, abs(vb)):
            return False
    return True


@pytest.mark.parametrize("name", ["ex18_slider_compound_pendulum", "ex20_spinning_disk_double_pendulum",
                                  "rolling_disc", "heavy_symmetric_top"])
def test_broken_lines_are_the_expression(name, derived):
    d = derived(name)
    breaker = SpecLanguageBreaker(d.model)
    rng = np.random.default_rng(11)
    exprs = [d.T, d.L, *d.forcing, *(eq.lhs for eq in d.equations)]
    broken = 0
    for expr in exprs:
        for width in (12.0, 30.0):
            lines = breaker.lines(sp.sympify(expr), width)
            broken += len(lines) > 1
            assert _same_value(_rejoin(lines, d), expr, rng), "\n".join(lines)
    assert broken


def test_long_sum_is_broken_into_align_lines(derived):
    fragment = latex_fragment(derived("ex20_spinning_disk_double_pendulum"))
    assert r"&\quad +" in fragment or r"&\quad -" in fragment


# -- golden files, determinism, CLI --------------------------------------------------------

@pytest.mark.parametrize("name", GOLDEN_SPECS)
def test_golden_document(name, derived):
    text = latex_document(derived(name))
    path = GOLDEN / f"{name}.tex"
    if os.environ.get("LAGCLI_UPDATE_GOLDEN") == "1":
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        return
    assert path.exists(), f"missing {path}: run with LAGCLI_UPDATE_GOLDEN=1 to create it"
    expected = path.read_text(encoding="utf-8")
    if text != expected:
        diff = "".join(difflib.unified_diff(expected.splitlines(True), text.splitlines(True),
                                            str(path), "latex_document()"))
        pytest.fail(f"{name}: LaTeX differs from the golden file "
                    f"(LAGCLI_UPDATE_GOLDEN=1 rewrites it):\n{diff}")


def test_header_names_spec_and_version(derived):
    import lagcli

    document = latex_document(derived("double_pendulum"))
    first = document.splitlines()[0]
    assert first.startswith("%") and "double_pendulum.yaml" in first and lagcli.__version__ in first
    assert re.search(r"20\d\d-\d\d-\d\d", document) is None


def test_same_spec_same_bytes(derived):
    d = derived("ex6_9_two_wheels_axle")
    assert latex_document(d) == latex_document(d)
    assert latex_fragment(d) == latex_fragment(d)


def test_same_bytes_across_processes(tmp_path):
    spec = str(ROOT / "specs" / "ex6_9_two_wheels_axle.yaml")
    outputs = []
    for seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": str(ROOT)}
        out = tmp_path / f"doc{seed}.tex"
        subprocess.run([sys.executable, "-m", "lagcli", "generate", spec, "--lang", "latex", "-o", str(out)],
                       check=True, env=env, cwd=tmp_path, timeout=300)
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1]


def test_cli_latex(derived, tmp_path):
    from lagcli.cli import cli

    spec = str(ROOT / "specs" / "ex6_9_two_wheels_axle.yaml")
    d = derived("ex6_9_two_wheels_axle")
    runner = CliRunner()
    fragment = runner.invoke(cli, ["derive", spec, "--latex"])
    assert fragment.exit_code == 0, fragment.output
    assert fragment.output == latex_fragment(d)
    standalone = runner.invoke(cli, ["derive", spec, "--latex", "--standalone"])
    assert standalone.exit_code == 0 and standalone.output == latex_document(d)
    out = tmp_path / "axle.tex"
    generated = runner.invoke(cli, ["generate", spec, "--lang", "latex", "-o", str(out)])
    assert generated.exit_code == 0, generated.output
    assert out.read_text(encoding="utf-8") == latex_document(d)
