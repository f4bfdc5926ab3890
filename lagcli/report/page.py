"""A page to share: `lagcli report SPEC -o page.html` / `System.page()`.

One self-contained HTML file (no network, no JavaScript needed to read it):

    header          the spec's name and description
    System          coordinates, parameters (value, unit, description), inputs, the counts
    Equations       the report's content (`report_content`, named quantities for big
                    expressions) printed as MathML (`lagcli.report.mathml`): T, V, L, the
                    mass matrix, the equations of motion, the constraints, what is conserved
    Linearization   at the spec's initial state, when it gives one (`System.linearize`)
    Simulation      the spec's own run drawn as `simulate --plot` draws it, inline SVG
    Animation       the motion as an animated GIF (a data: URI)
    Spec            the spec's text

Every piece of spec text goes through `html_text` (the page's one escaping function);
pictures need matplotlib (the `plot` extra) and are left out with a note without it.
Each part that cannot be made (a run that fails, a singular linearization) is replaced
by a sentence saying why: the page is still written.
"""
from __future__ import annotations

import base64
import os
import tempfile

import sympy as sp

from lagcli.render.escape import html_text
from lagcli.report.mathml import math_block, mathml, mathml_terms, mi, model_names
from lagcli.report.notation import notation_of, spoken_list

STYLE = """
body { font-family: system-ui, sans-serif; max-width: 60rem; margin: 2rem auto; padding: 0 1rem;
       line-height: 1.45; color: #222; }
h1 { margin-bottom: 0.2rem; } h2 { border-bottom: 1px solid #ddd; margin-top: 2rem; }
.eq { overflow-x: auto; overflow-y: hidden; padding: 0.2rem 0; }
math { font-family: "STIX Two Math", "STIX Math", "Cambria Math", "Latin Modern Math", math; }
math[display="block"] { margin: 0.4rem 0; }
table { border-collapse: collapse; margin: 0.5rem 0; }
td, th { border: 1px solid #ddd; padding: 0.2rem 0.6rem; text-align: left; }
pre { background: #f6f6f6; padding: 0.8rem; overflow-x: auto; }
figure { margin: 1rem 0; } figure svg, figure img { max-width: 100%; height: auto; }
.note { color: #666; font-style: italic; }
.wide { overflow-x: auto; }
"""
ANIMATION_FPS = 10.0


def page_html(system, pictures: bool = True) -> str:
    """The page of `system` (a `lagcli.System`) as HTML text."""
    d, content = system.derivation, _content(system)
    sections = [_system_section(system, content), _equations_section(d, content),
                _linearization_section(system)]
    if pictures:
        sections.append(_pictures_section(system))
    sections.append(_spec_section(system))
    title = html_text(system.name)
    description = html_text(system.model.description or "")
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<title>{title}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
            f"<h1>{title}</h1>\n<p>{description}</p>\n" + "\n".join(sections)
            + f"\n<p class=\"note\">Made by lagcli {html_text(_version())} from "
              f"{html_text(os.path.basename(system.model.source or system.name))}.</p>\n</body>\n</html>\n")


def _version() -> str:
    from lagcli.version import __version__

    return __version__


def _content(system) -> dict:
    from lagcli.report.content import ReportPrinter, report_content

    names = model_names(system.model)
    printer = ReportPrinter(lambda e: mathml(e, names), lambda terms: mathml_terms(terms, names))
    content = report_content(system.derivation, printer, named=True)
    return {**content, "names": names}


# -- sections ---------------------------------------------------------------------------

def _system_section(system, r: dict) -> str:
    d, units, names = system.derivation, r.get("units", {}), r["names"]
    rows = "".join(f"<tr><td>{_math(mathml(p.symbol, names))}</td><td>{p.value:g}</td>"
                   f"<td>{html_text(units.get(p.symbol.name, ''))}</td>"
                   f"<td>{html_text(p.description or '')}</td></tr>" for p in d.model.parameters)
    inputs = "".join(f"<tr><td>{_math(mathml(u.symbol, names))}</td><td>{u.value:g}</td>"
                     f"<td>{html_text(units.get(u.symbol.name, ''))}</td>"
                     f"<td>{html_text(u.description or '')}</td></tr>" for u in d.model.inputs)
    counts = r["counts"]
    n, h, g = counts["coordinates"], counts["holonomic"], counts["nonholonomic"]
    parts = [f"<h2>System</h2>\n<p>Coordinates {_math(_list(d.model.q, names))}; "
             f"{n} coordinate{'s' * (n != 1)}, {h} holonomic and {g} nonholonomic "
             f"constraint{'s' * (h + g != 1)}: {d.dof} degree{'s' * (d.dof != 1)} of freedom. "
             f"The system is {'scleronomic' if r['scleronomic'] else 'rheonomic'}.</p>"]
    if rows:
        parts.append("<table><tr><th>parameter</th><th>value</th><th>unit</th><th></th></tr>"
                     f"{rows}</table>")
    if inputs:
        parts.append("<table><tr><th>input</th><th>default</th><th>unit</th><th></th></tr>"
                     f"{inputs}</table>")
    return "\n".join(parts)


def _equations_section(d, r: dict) -> str:
    n = notation_of(d)
    T, L, Q, a = (html_text(n.unicode(letter)) for letter in "TLQa")
    out = ["<h2>Energies</h2>", *_legend(n), _eq(n.mathml("T"), r["kinetic_energy"]["T"]),
           _eq(n.mathml("V"), r["potential_energy"]), _eq(n.mathml("L"), r["lagrangian"]),
           f"<p>Mass matrix (the bold M: {T}<sub>2</sub> = ½ q̇ᵀ 𝐌 q̇):</p>",
           _eq(mi("\U0001d40c"), _matrix(r["mass_matrix"]))]
    out.append(f"<h2>Equations of motion</h2>\n<p>d/dt(∂{L}/∂q̇<sub>i</sub>) − ∂{L}/∂q<sub>i</sub> − "
               f"{Q}′<sub>i</sub> = Σ<sub>j</sub> λ<sub>j</sub> {a}<sub>ji</sub>, one per coordinate:</p>")
    out += [_block(eq["lhs"], "<mo>=</mo>", eq["rhs"]) for eq in r["equations"]]
    if r["constraints"]:
        out.append("<h2>Constraints</h2>")
        out += [_block(c["expr"], "<mo>=</mo><mn>0</mn>") for c in r["constraints"]]
    conserved = r["conserved_quantities"]
    if conserved:
        out.append("<h2>Conserved quantities</h2>")
        out += [_eq(_name(c["name"], n), c["expr"]) for c in conserved]
    if r["named_quantities"]:
        out.append("<h2>Named quantities</h2>\n<p>Expressions too large to print whole use these:</p>")
        out += [_eq(_name(q["name"]), q["expr"]) for q in r["named_quantities"]]
    return "\n".join(out)


def _linearization_section(system) -> str:
    """The linear model about the spec's `initial:` state, the point and the command that
    gives it named: what `initial:` gives, the rest as `lagcli linearize` takes it (0, or
    solved from the constraints), so the page and `lagcli linearize --at ...` agree."""
    given = dict(system.model.initial)
    if not given:
        return ""
    from lagcli.errors import LagcliError

    try:
        result = system.linearize(at=given)
    except LagcliError as exc:
        return f"<h2>Linearization</h2>\n<p class=\"note\">{html_text(str(exc).splitlines()[0])}</p>"
    return (f"<h2>Linearization at the initial state</h2>\n{_linearization_point(system, given, result)}"
            f"<div class=\"wide\">{result._repr_html_()}</div>")


def _linearization_point(system, given: dict, result) -> str:
    """Which values of the point come from the spec's `initial:`, which not, and the command."""
    state = result.point.state
    rest = [name for name in state if name not in given]

    def values(names) -> str:
        return ", ".join(f"{name} = {state[name] + 0.0:.10g}" for name in names)

    command = " ".join(["lagcli linearize", os.path.basename(system.model.source),
                        *(f"--at {name}={float(value) + 0.0!r}" for name, value in given.items())])
    parts = [f"The point: {html_text(values([n for n in state if n in given]))} from the spec's "
             "<code>initial:</code>"]
    if rest:
        parts.append(f"; {html_text(values(rest))} as <code>lagcli linearize</code> takes what "
                     "<code>--at</code> does not give (0, or solved from the constraints)")
    notes = "".join(f"<br/>{html_text(note)}" for note in result.point.notes)
    return f"<p>{''.join(parts)}.{notes}<br/>The same: <code>{html_text(command)}</code></p>\n"


def _pictures_section(system) -> str:
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return ("<h2>Simulation</h2>\n<p class=\"note\">Plots need matplotlib: "
                "pip install \"lagcli[plot]\".</p>")
    from lagcli.errors import LagcliError

    try:
        trajectory = system.simulate()
    except LagcliError as exc:
        return f"<h2>Simulation</h2>\n<p class=\"note\">{html_text(str(exc).splitlines()[0])}</p>"
    out = ["<h2>Simulation</h2>", f"<figure>{_svg(trajectory.plot())}</figure>"]
    gif = _animation(system, trajectory)
    if gif:
        out += ["<h2>Animation</h2>", f"<figure><img alt=\"the motion of {html_text(system.name)}\" "
                f"src=\"data:image/gif;base64,{gif}\"></figure>"]
    return "\n".join(out)


def _spec_section(system) -> str:
    text = system.spec_bytes.decode("utf-8", errors="replace")
    return f"<h2>Spec</h2>\n<pre>{html_text(text)}</pre>"


# -- pieces -----------------------------------------------------------------------------

def _svg(figure) -> str:
    """The figure as inline SVG, the same bytes every run (`figure_bytes`: no date, fixed ids)."""
    from lagcli.viz.plot import figure_bytes

    svg = figure_bytes(figure, "svg").decode("utf-8")
    return svg[svg.index("<svg"):]


def _animation(system, trajectory) -> str | None:
    """The motion as a base64 GIF (ANIMATION_FPS frames per simulated second)."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "motion.gif")
        system.animate(path, trajectory=trajectory, fps=ANIMATION_FPS)
        with open(path, "rb") as f:
            return base64.b64encode(f.read()).decode("ascii")


def _legend(n) -> list[str]:
    """The paragraph saying what the page's yielded letters are (none when nothing yields)."""
    legend = n.legend(n.unicode)
    if not legend:
        return []
    said = ", ".join(f"{html_text(shown)} denotes {html_text(meaning)}" for _, shown, meaning in legend)
    mine = spoken_list([html_text(letter) for letter, _, _ in legend])
    return [f"<p>Notation: {said} ({mine} the spec's own).</p>"]


def _math(body: str) -> str:
    return f"<math>{body}</math>"


def _eq(label: str, body: str) -> str:
    return _block(label, "<mo>=</mo>", body)


def _block(*pieces: str) -> str:
    return f"<div class=\"eq\">{math_block(*pieces)}</div>"


def _list(symbols, names: dict) -> str:
    return "<mo>,</mo>".join(mathml(s, names) for s in symbols)


def _name(name: str, n=None) -> str:
    """A quantity's name as the printer shows a symbol of that name (p_phi -> p with φ,
    the p bold when the spec names something p: `lagcli.report.notation`)."""
    if n is not None and name.startswith("p_"):
        name = n.unicode("p") + name[1:]
    return mathml(sp.Symbol(name))


def _matrix(entries: list[list[str]]) -> str:
    body = "".join("<mtr>" + "".join(f"<mtd>{e}</mtd>" for e in row) + "</mtr>" for row in entries)
    return f"<mrow><mo>(</mo><mtable>{body}</mtable><mo>)</mo></mrow>"
