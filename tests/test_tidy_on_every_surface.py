"""No untidied trigonometry on any surface of any bundled spec (issue 21, acceptance: "no
`sin(x)**2 + cos(x)**2`, `sqrt(1 - sin(x)**2)` or `x/Abs(x)` left in any bundled spec's
report, notebook display or page").

Every bundled spec (`specs/` and `specs/hybrid/`, as `lagcli examples` lists them) and every
surface a user reads: the text report, the LaTeX report, the JSON report, the notebook
(`System._repr_latex_`, each part's text and LaTeX) and the page's MathML.

Two independent looks:

- the JSON report's expressions are parsed back into sympy and searched structurally: an
  `Abs`; a square root whose radicand `sympy.trigsimp` + `sympy.factor` turn into a perfect
  square (sqrt(1 - sin(x)**2) = sqrt(cos(x)**2)); a sum holding both a term with sin(a)**2
  and the same term with cos(a)**2 in its place (c sin^2 + c cos^2 = c);
- the printed surfaces are searched for the three forms as each printer writes them
  (text, LaTeX, MathML read back into a linear form). The searches are first shown to find
  the forms in what sympy's and lagcli's own printers make of a known untidy expression, so
  a search that can never match is a failure here, not a silent pass.
"""
from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import pytest
import sympy as sp

import lagcli
from lagcli.errors import LagcliError
from conftest import SPECS

SLOW = {"benchmark_bicycle", "benchmark_bicycle_frames"}          # seconds per surface
BUNDLED = sorted([*SPECS.glob("*.yaml"), *SPECS.glob("hybrid/*.yaml")], key=lambda p: p.stem)
CASES = [pytest.param(p, id=p.stem, marks=[pytest.mark.slow] if p.stem in SLOW else []) for p in BUNDLED]

# A Pythagorean pair c*sin(a)**2 + c*cos(a)**2: c is a whole term's leading factors (the
# search starts where a term starts) and the second square ends its term.
_TERM = r"(?:^|(?<=[-+=(&{\u2212]))\s*"
TEXT = [re.compile(r"sqrt\(1 - (sin|cos)\("), re.compile(r"Abs\("),
        *(re.compile(rf"(?:^|(?<=[-+=( ]))(?P<c>[\w*]*){f}\((?P<a>[^()]+)\)\*\*2 \+ (?P=c){g}\((?P=a)\)\*\*2(?![*\w])")
          for f, g in (("sin", "cos"), ("cos", "sin")))]
LATEX = [re.compile(r"\\sqrt\{1 - \\(sin|cos)\^\{2\}"), re.compile(r"\\left\|"),
         *(re.compile(rf"{_TERM}(?P<c>[^-+=&]*?)\\{f}\^\{{2\}}\{{\\left\((?P<a>[^)]*?) \\right\)\}} \+ "
                      rf"(?P=c)\\{g}\^\{{2\}}\{{\\left\((?P=a) \\right\)\}}(?=\s*(?:[-+=)&}}]|\\right|\\\\|$))")
           for f, g in (("sin", "cos"), ("cos", "sin")))]
MATHML = [re.compile(r"sqrt\(1[-\u2212]\((sin|cos)\("), re.compile(r"\|"),
          *(re.compile(rf"{_TERM}(?P<c>[^-+\u2212=]*?)\({f}\((?P<a>[^()]*)\)\)\^\(2\)\+(?P=c)\({g}\((?P=a)\)\)\^\(2\)"
                       r"(?=[-+\u2212=)]|$)")
            for f, g in (("sin", "cos"), ("cos", "sin")))]


def linear(node: ET.Element) -> str:
    """Presentation MathML as one line: msup -> (a)^(b), msqrt -> sqrt(...), mfrac -> (a)/(b)."""
    inner = [linear(child) for child in node]
    tag = node.tag.split("}")[-1]
    if tag == "msup":
        return f"({inner[0]})^({inner[1]})"
    if tag == "mfrac":
        return f"({inner[0]})/({inner[1]})"
    if tag in ("msqrt", "mroot"):
        return f"sqrt({''.join(inner)})"
    return (node.text or "").strip() + "".join(inner)


def page_lines(html: str) -> list[str]:
    """Each <math> element of a page as one line."""
    found = re.findall(r"<math\b.*?</math>", html, flags=re.S)
    return [linear(ET.fromstring(re.sub(r"&\w+;", " ", block))) for block in found]


def untidy_in(texts, patterns) -> list[str]:
    return [f"{pattern.pattern!r} in: ...{text[max(0, m.start() - 60):m.end() + 60]}..."
            for text in texts for pattern in patterns for m in [pattern.search(text)] if m]


def residues(expr: sp.Expr) -> list[str]:
    """The untidy forms inside one expression, found on its sympy tree."""
    found = [str(a) for a in expr.atoms(sp.Abs)]
    for power in expr.atoms(sp.Pow):
        if power.exp in (sp.S.Half, -sp.S.Half) and power.base.has(sp.sin, sp.cos):
            square = sp.factor(sp.trigsimp(power.base))
            if square.is_Pow and square.exp.is_even or (square.is_Mul and all(
                    f.is_Pow and f.exp.is_even or f.is_number and f > 0 for f in square.args)):
                found.append(str(power))
    for node in sp.preorder_traversal(expr):
        if node.is_Add:
            terms = set(node.args)
            for term in node.args:
                for s in (f for f in term.atoms(sp.sin) if term.has(f ** 2)):
                    partner = sp.expand(term / s ** 2 * sp.cos(s.args[0]) ** 2)
                    if partner in terms:
                        found.append(f"{term} + {partner}")
    return found


def json_expressions(report, model) -> list[tuple[str, sp.Expr]]:
    """(key, parsed expression) of every expression string the JSON report holds."""
    from lagcli.render.spec_printer import parse_output

    multipliers = [sp.Symbol(m if isinstance(m, str) else m["name"]) for m in report.get("multipliers", [])]
    out = []

    def walk(key, value):
        if isinstance(value, dict):
            for k, v in value.items():
                walk(f"{key}.{k}", v)
        elif isinstance(value, list):
            for k, v in enumerate(value):
                walk(f"{key}[{k}]", v)
        elif isinstance(value, str) and ("sin(" in value or "cos(" in value or "Abs(" in value or "sqrt(" in value):
            try:
                out.append((key, parse_output(value, model, multipliers)))
            except LagcliError:
                pass                                   # a sentence, not an expression
    walk("", report)
    return out


def test_the_searches_find_the_untidy_forms():
    from lagcli.report.mathml import mathml

    x, l, m = sp.symbols("theta l m")
    bad = [m * (l ** 2 * sp.sin(x) ** 2 + l ** 2 * sp.cos(x) ** 2), sp.sqrt(1 - sp.sin(x) ** 2) * l,
           x / sp.Abs(x)]
    for expr in bad:
        assert untidy_in([str(expr)], TEXT), str(expr)
        assert untidy_in([sp.latex(expr)], LATEX), sp.latex(expr)
        assert untidy_in(page_lines(f"<math>{mathml(expr)}</math>"), MATHML), mathml(expr)
        assert residues(expr), expr
    tidy = l * sp.cos(x) + sp.sqrt(l ** 2 + 1) * sp.sin(x) ** 2 + m * sp.cos(x) ** 2     # no pair: m != sqrt(l**2 + 1)
    assert not residues(tidy)
    assert not untidy_in([str(tidy)], TEXT) and not untidy_in([sp.latex(tidy)], LATEX)
    assert not untidy_in(page_lines(f"<math>{mathml(tidy)}</math>"), MATHML)


@pytest.fixture(scope="module")
def loaded():
    return {}


@pytest.mark.core_specs
@pytest.mark.parametrize("path", CASES)
def test_no_untidy_form_in_the_reports_notebook_and_page(path, loaded):
    system = lagcli.load(path)
    parts = [getattr(system.parts, name) for name in dir(system.parts) if not name.startswith("_")]
    found = untidy_in([system.report("text"), *(p.text for p in parts)], TEXT)
    found += untidy_in([system.report("latex"), system._repr_latex_(), *(p.latex for p in parts)], LATEX)
    found += untidy_in(page_lines(system.page(pictures=False)), MATHML)
    assert not found, f"{path.stem}:\n" + "\n".join(found[:5])


@pytest.mark.parametrize("path", CASES)
def test_no_untidy_form_in_the_json_report_expressions(path):
    system = lagcli.load(path)
    report = system.report("dict")
    found = [(key, r) for key, expr in json_expressions(report, system.model) for r in residues(expr)]
    assert not found, f"{path.stem}: {found[:5]}"


UNCONSTRAINED_SMALL = [p for p in BUNDLED if p.stem not in SLOW and "constraints" not in p.read_text()
                       and "rolling" not in p.read_text()]


@pytest.mark.core_specs
@pytest.mark.parametrize("path", UNCONSTRAINED_SMALL, ids=[p.stem for p in UNCONSTRAINED_SMALL])
def test_no_untidy_form_in_hamiltons_equations(path):
    """`lagcli hamiltonian` (text and the notebook's LaTeX) of every bundled unconstrained
    spec: the momenta, H and Hamilton's equations carry none of the untidy forms (the
    double pendulum's used to be sums of l2 p1 cos^2(theta2) + l2 p1 sin^2(theta2)), and
    they are still Hamilton's equations: at seeded random states q' from them equals the
    solution of M q' = p - a with the derivation's M and a (numpy), and H equals
    T2 - T0 + V there."""
    import numpy as np

    from lagcli.analysis.report import hamilton_content, hamilton_text
    from lagcli.render.spec_printer import spec_str

    system = lagcli.load(path)
    h = system.hamiltonian()
    if h.H is None:
        pytest.skip("M is full and larger than 2 x 2: the solved form")
    text = hamilton_text(hamilton_content(h, spec_str))
    found = untidy_in([text], TEXT) + untidy_in([h._repr_latex_()], LATEX)
    exprs = [h.H, *h.momenta.values(), *h.equations.values()]
    found += [r for e in exprs for r in residues(sp.sympify(e))]
    assert not found, f"{path.stem}:\n" + "\n".join(map(str, found[:5]))

    d, model = system.derivation, system.model
    values = {p.symbol: sp.Float(p.value) for p in (*model.parameters, *model.inputs)}
    rng = np.random.default_rng(3)
    momenta = [sp.Symbol(f"p_{q.name}", real=True) for q in model.q]
    for _ in range(3):
        state = {s: sp.Float(rng.uniform(-1.0, 1.0)) for s in (*model.q, *model.qd)} | {model.t: sp.Float(0.3)}
        at = lambda e: complex(sp.sympify(e).xreplace(values).xreplace(state)).real
        M = np.array([[at(e) for e in row] for row in sp.Matrix(d.mass_matrix).tolist()])
        a = np.array([at(e) for e in d.t1_coefficients])
        qd = np.array([float(state[v]) for v in model.qd])
        p = M @ qd + a
        state |= {s: sp.Float(v) for s, v in zip(momenta, p)}
        assert [at(h.momenta[name]) for name in h.momenta] == pytest.approx(list(p), rel=1e-9, abs=1e-12)
        solved = [at(h.equations[f"{q.name}_dot"]) for q in model.q]
        assert solved == pytest.approx(list(np.linalg.solve(M, p - a)), rel=1e-9, abs=1e-12)
        assert at(h.H) == pytest.approx(at(d.T2 - d.T0 + d.V), rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("path", UNCONSTRAINED_SMALL, ids=[p.stem for p in UNCONSTRAINED_SMALL])
def test_no_untidy_form_in_the_routhian(path):
    """`lagcli routh` (text and the notebook's LaTeX) of every bundled unconstrained spec
    with a cyclic coordinate: R, V_eff, the cyclic velocities and the reduced equations
    carry none of the untidy forms (the top's R had A + m (h^2 cos^2 + h^2 sin^2)), and at
    seeded random states they are still the reduction: q'_s from numpy's solve of
    M_ss q'_s = p_s - M_sr q'_r - a_s, R = L - p_s q'_s there, V_eff = -R at q'_r = 0."""
    import numpy as np

    from lagcli.analysis.report import routh_content, routh_text
    from lagcli.render.spec_printer import spec_str

    system = lagcli.load(path)
    if not system.derivation.ignorable:
        pytest.skip("no cyclic coordinate")
    r = system.routh()
    text = routh_text(routh_content(r, spec_str))
    found = untidy_in([text], TEXT) + untidy_in([r._repr_latex_()], LATEX)
    exprs = [r.R, r.effective_potential, *r.cyclic_velocities.values(), *r.reduced_equations]
    found += [x for e in exprs for x in residues(sp.sympify(e))]
    assert not found, f"{path.stem}:\n" + "\n".join(map(str, found[:5]))

    d, model = system.derivation, system.model
    s = [model.q.index(model.symbol(c)) for c in r.cyclic]
    rest = [k for k in range(len(model.q)) if k not in s]
    values = {p.symbol: sp.Float(p.value) for p in (*model.parameters, *model.inputs)}
    rng = np.random.default_rng(5)
    for _ in range(3):
        state = {x: sp.Float(rng.uniform(0.2, 1.2)) for x in (*model.q, *model.qd)} | {model.t: sp.Float(0.3)}
        momenta = {sp.Symbol(name, real=True): sp.Float(rng.uniform(-1.0, 1.0)) for name in r.momenta}
        at = lambda e, extra={}: float(sp.sympify(e).xreplace(values).xreplace({**state, **momenta, **extra}))
        M = np.array([[at(e) for e in row] for row in sp.Matrix(d.mass_matrix).tolist()])
        a = np.array([at(e) for e in d.t1_coefficients])
        qd_r = np.array([float(state[model.qd[k]]) for k in rest])
        qd_s = np.linalg.solve(M[np.ix_(s, s)], np.array([float(v) for v in momenta.values()])
                               - M[np.ix_(s, rest)] @ qd_r - a[s])
        assert [at(r.cyclic_velocities[f"{model.q[k].name}_dot"]) for k in s] == pytest.approx(list(qd_s), rel=1e-9)
        solved = {model.qd[k]: sp.Float(v) for k, v in zip(s, qd_s)}
        R = at(d.L, solved) - sum(float(p) * v for p, v in zip(momenta.values(), qd_s))
        assert at(r.R) == pytest.approx(R, rel=1e-9, abs=1e-12)
        still = {model.qd[k]: sp.S.Zero for k in rest}
        assert at(r.effective_potential) == pytest.approx(-at(r.R, still), rel=1e-9, abs=1e-12)
