"""LaTeX output: `lagcli derive --latex [--standalone]` and `lagcli generate --lang latex`.

The content is the text report's (`report_content`), printed with lagcli's
`LatexPrinter`; this module only lays it out as rows of `align*` environments
(pre-printed strings) for `templates/latex/fragment.tex.jinja`:

    latex_fragment(derivation, simplify=True, parts=PARTS) -> str   # body text, needs amsmath
    latex_document(derivation, simplify=True, parts=PARTS) -> str   # article + geometry + amsmath

`parts`: the report's sections to include (`lagcli.report.content.PARTS`, `--part`).

Every row has a label column and a content column (`label & content`); a long
expression continues on `&\\quad` lines, a wide matrix is listed entry by entry.
The output depends only on the spec (its file name, not its path) and the
lagcli version: no dates, so the same spec gives the same bytes.
"""
from __future__ import annotations

import re
from pathlib import Path

import sympy as sp

from lagcli.version import __version__
from lagcli.derive.result import Derivation
from lagcli.render.escape import latex_comment, latex_text
from lagcli.report.latex_printer import CONTENT_WIDTH, LatexPrinter, Tex, tex_width
from lagcli.report.content import PARTS, ReportPrinter, report_content
from lagcli.report.notation import Notation, notation_of, spoken_list
from lagcli.render.templates import render

PLANAR_AXES = ("x", "y", "z")
MAX_MATRIX_COLS = 10          # amsmath's MaxMatrixCols
LIST_SEP = r", \allowbreak "   # inline lists of symbols may break after a comma


def latex_printer(derivation: Derivation) -> LatexPrinter:
    """The printer for one derivation's symbols (coordinates, parameters, multipliers)."""
    return LatexPrinter(derivation.model, multipliers=[(c.multiplier, c.label) for c in derivation.constraints])


def latex_fragment(derivation: Derivation, simplify: bool = True, parts=PARTS) -> str:
    return _body(dict(_context(derivation, simplify), parts=parts))


def latex_document(derivation: Derivation, simplify: bool = True, parts=PARTS) -> str:
    context = dict(_context(derivation, simplify), parts=parts, in_document=True)   # description = title
    return render("latex/document.tex.jinja", body=_body(context), **context)


def latex_files(d: Derivation, layout=None, initial=None, initial_notes=()) -> dict[str, str]:
    """`lagcli generate --lang latex` (lagcli.targets.LANGUAGES): the standalone document."""
    return {f"{d.model.name}.tex": latex_document(d)}


def _body(context: dict) -> str:
    """The fragment, its "Named quantities" holding the definitions that the selected
    parts use (directly or through a later definition that uses them)."""
    body = render("latex/fragment.tex.jinja", **context, named_rows=[])
    named_rows = named_rows_used(context["named"], body)
    if not named_rows:
        return body
    return render("latex/fragment.tex.jinja", **context, named_rows=named_rows)


def named_rows_used(named: list, shown: str) -> list[str]:
    """The rows defining the named quantities that `shown` uses, directly or through a
    later definition that uses them, in definition order."""
    needed = []
    for symbol, expr in reversed(named):
        if re.search(re.escape(symbol) + r"(?![\w{])", shown):
            needed.append((symbol, expr))
            shown += f" {expr}"
    return [row for symbol, expr in reversed(needed) for row in rows(symbol, expr)]


# -- rows of align* -----------------------------------------------------------------

def rows(label: str, tex: Tex, via: str | None = None) -> list[str]:
    """`label = expression` (or `label = via = expression`), continued on `\\quad` lines."""
    first, *rest = tex.lines
    if via is None:
        return [f"{label} &= {first}", *(rf"&\quad {line}" for line in rest)]
    if not rest and tex_width(via) + 2.4 + tex.width <= CONTENT_WIDTH:
        return [f"{label} &= {via} = {first}"]
    return [f"{label} &= {via}", f"&= {first}", *(rf"&\quad {line}" for line in rest)]


def equation_rows(label: str, lhs: Tex, rhs: Tex) -> list[str]:
    """`label: lhs = rhs` with the relation inside the content column (whose lines have
    the room of the "= " and "\\quad" that `CONTENT_WIDTH` keeps for other rows)."""
    if lhs.width + rhs.width + 2.4 <= CONTENT_WIDTH + 4.0:
        return [f"{label} & {lhs} = {rhs}"]
    lines = list(lhs.lines)
    room = CONTENT_WIDTH + (4.0 if len(lines) == 1 else 2.0)
    if tex_width(lines[-1]) + rhs.width + 2.4 <= room and len(rhs.lines) == 1:
        lines[-1] = f"{lines[-1]} = {rhs}"
    else:
        lines.append(f"= {rhs.lines[0]}")
        lines.extend(rhs.lines[1:])
    return [f"{label} & {lines[0]}", *(rf"&\quad {line}" for line in lines[1:])]


def vector_rows(labels: list[str], entries: list[Tex], name: str) -> list[str]:
    """One row per component, or `name = 0` when every component is zero."""
    if all(e == "0" for e in entries):
        return [f"{name} &= 0"]
    return [row for label, e in zip(labels, entries) for row in rows(label, e)]


def matrix_block(name: str, entries: list[list[Tex]], kind: str) -> dict:
    """A matrix as a pmatrix when it fits, else its entries (`kind`: symmetric, skew, general)."""
    n_rows = len(entries)
    n_cols = len(entries[0]) if entries else 0
    if all(e == "0" for row in entries for e in row):
        return {"matrix": f"{name} = 0", "rows": []}
    col_widths = [max(entries[i][j].width for i in range(n_rows)) for j in range(n_cols)]
    single = all(len(e.lines) == 1 for row in entries for e in row)
    if single and n_cols <= MAX_MATRIX_COLS and sum(col_widths) + 2.0 * n_cols + 3.0 <= CONTENT_WIDTH:
        if any(r"\frac" in e for row in entries for e in row):    # fractions at full size, rows apart
            entries = [[rf"\displaystyle {e}" if r"\frac" in e else e for e in row] for row in entries]
            body = r" \\[1ex] ".join(" & ".join(row) for row in entries)
        else:
            body = r" \\ ".join(" & ".join(row) for row in entries)
        return {"matrix": rf"{name} = \begin{{pmatrix}} {body} \end{{pmatrix}}", "rows": []}
    sep = "," if max(n_rows, n_cols) > 9 else ""
    out = []
    for i in range(n_rows):
        for j in range(n_cols):
            shown = j >= i if kind == "symmetric" else (j > i if kind == "skew" else True)
            if shown and entries[i][j] != "0":
                out.extend(rows(f"{name}_{{{i + 1}{sep}{j + 1}}}", entries[i][j]))
    return {"matrix": None, "rows": out}


# -- the template context -------------------------------------------------------------

def latex_content(d: Derivation, simplify: bool = True) -> dict:
    """The report's content (`report_content`) printed in LaTeX (`Tex` strings, named
    quantities for big expressions): what every LaTeX surface shows."""
    printer = latex_printer(d)
    return report_content(d, ReportPrinter(printer.tex, printer.tex_terms), simplify, named=True)


def _context(d: Derivation, simplify: bool) -> dict:
    return latex_context(d, latex_content(d, simplify))


def latex_context(d: Derivation, r: dict) -> dict:
    """The template context of the LaTeX report made from its content `r`: pre-printed
    rows, also shown one part at a time in notebooks (`lagcli.report.parts`)."""
    m = d.model
    printer = latex_printer(d)
    notation = notation_of(d)
    n = notation.latexes
    qtex = {q.name: printer.doprint(q) for q in m.q}
    qs = [qtex[name] for name in r["coordinates"]]

    def per_q(template: str) -> list[str]:
        return [template.replace("@", qtex[name]) for name in r["coordinates"]]

    def column(values: dict, template: str, name: str) -> list[str]:
        return vector_rows(per_q(template), [values[q] for q in r["coordinates"]], name)

    return {
        "n": n,
        "legend": _legend(notation, printer, m),
        "version": __version__,
        "in_document": False,          # a standalone document prints the description as its title
        "spec_file": latex_comment(Path(m.source).name if m.source else ""),   # in % comments only
        "spec_name": latex_comment(r["name"]),
        "spec_title": latex_text(r["name"]),
        "title": latex_text(r["description"]) if r["description"] else latex_text(r["name"]),
        "description": _sentence(latex_text(r["description"] or "")),
        "coordinates": LIST_SEP.join(qs),
        "velocities": LIST_SEP.join(printer.doprint(v) for v in m.qd),
        "parameters": [{"symbol": printer.doprint(info.symbol), "value": _number(info.value),
                        "unit": latex_text(m.units.get(info.symbol.name, (None,))[0] or ""),
                        "description": latex_text(info.description or "")}
                       for info in m.parameters],
        "inputs": [{"symbol": printer.doprint(info.symbol), "value": _number(info.value),
                    "description": latex_text(info.description or "")}
                   for info in m.inputs],
        "known": [row for name, e in r["known"].items()
                  for row in rows(f"{printer.symbol(name)}(t)", e)],
        "counts": {"n": r["counts"]["coordinates"], "d": r["counts"]["holonomic"],
                   "g": r["counts"]["nonholonomic"], "dof": r["dof"]},
        "scleronomic": r["scleronomic"],
        "energy_rows": _energy_rows(r, n["T"]),
        "mass_matrix": matrix_block(n["M"], r["mass_matrix"], "symmetric"),
        "potential_rows": [*rows(n["V"], r["potential_energy"]),
                           *rows(n["L"], r["lagrangian"], f"{n['T']} - {n['V']}")],
        "force_rows": column(r["generalized_forces"], n["Q"] + "_{@}", n["Q"]),
        "nonconservative_rows": column(r["nonconservative_forces"], n["Q"] + "'_{@}", n["Q"] + "'"),
        "nonconservative_vanish": all(e == "0" for e in r["nonconservative_forces"].values()),
        "forces_conservative": r["forces_conservative"],
        "force_potential_rows": [] if r["force_potential"] is None else rows(n["V"] + "'", r["force_potential"]),
        "constrained": bool(r["constraints"]),
        "equations": [row for name, eq in zip(r["coordinates"], r["equations"])
                      for row in equation_rows(rf"{qtex[name]}\colon", eq["lhs"], eq["rhs"])],
        "constraints": [_constraint(j, c, row, printer, qs, n) for j, (c, row)
                        in enumerate(zip(r["constraints"], d.constraints), start=1)],
        "multipliers": LIST_SEP.join(printer.doprint(c.multiplier) for c in d.constraints),
        "constraint_force_rows": _constraint_forces(r, per_q, n),
        "particle_forces": bool(r["constraint_forces"]["particles"]),
        "explicit_rows": [
            *column(r["explicit_form"]["velocity_terms"], n["c"] + "_{@}", n["c"]),
            *column(r["explicit_form"]["mass_rate_terms"], rf"(\partial_t {n['M']}\,\dot q)_{{@}}",
                    rf"\partial_t {n['M']}\,\dot q"),
            *column(r["explicit_form"]["t1_rate_terms"], rf"\partial_t {n['a']}_{{@}}", rf"\partial_t {n['a']}"),
            *column(r["explicit_form"]["position_terms"], rf"\partial_{{@}}({n['V']} - {n['T']}_0)",
                    rf"\partial_q ({n['V']} - {n['T']}_0)"),
            *column(r["explicit_form"]["forcing"], n["F"] + "_{@}", n["F"]),
        ],
        "gyroscopic": matrix_block(n["G"], r["gyroscopic_matrix"], "skew"),
        "ignorable": LIST_SEP.join(qtex[name] for name in r["ignorable_coordinates"]),
        "conserved_rows": _conserved(r, qtex, r["energy_is_jacobi"], n),
        "named": [(printer.doprint(sp.Symbol(named["name"])), named["expr"])
                  for named in r["named_quantities"]],
        "jacobi": r["jacobi_integral"] is not None,
        "energy_is_jacobi": r["energy_is_jacobi"],
        "no_jacobi_reason": _math_words(r["no_jacobi_reason"] or "", n),
        "law_rows": [row for name, e in r.get("input_laws", {}).items()
                     for row in rows(printer.doprint(m.symbol(name)), e)],
        "events": [_event(e, printer, m, n) for e in r.get("events", [])],
    }


def _legend(notation: Notation, printer: LatexPrinter, m) -> str:
    """The sentence saying what the report's yielded letters are ("" when none)."""
    legend = notation.legend(notation.latex)
    if not legend:
        return ""
    said = ", ".join(f"${shown}$ denotes {meaning}" for _, shown, meaning in legend)
    mine = spoken_list([f"${_user_latex(letter, printer, m)}$" for letter, _, _ in legend])
    return f"Notation: {said} ({mine} the spec's own)."


def _user_latex(letter: str, printer: LatexPrinter, m) -> str:
    """The spec's symbol named `letter` as the report prints it (the letter itself else)."""
    try:
        return printer.doprint(m.symbol(letter))
    except KeyError:
        return letter


def _event(e: dict, printer, m, n: dict) -> dict:
    """One event of the report: what happens where g crosses zero, and its rows."""
    g = n["g"]
    out = [*rows(g, e["when"])]
    if e["action"] == "impact":
        out += [rf"G = \partial {g}/\partial q &= \begin{{pmatrix}} {' & '.join(e['G'])} \end{{pmatrix}}",
                *rows(rf"\partial_t {g}", e["g_t"]), *rows(n["e"], e["restitution"])]
    for name, value in e.get("reset", {}).items():
        out += rows(f"{printer.doprint(m.symbol(name))}^{{+}}", value)
    return {"name": latex_text(e["name"]), "action": e["action"], "direction": e["direction"], "rows": out}


# The symbols in lagcli's own sentences (invariants.jacobi_obstacle), set as math, the
# report's letters as the notation shows them.
_MATH_WORDS = {"Q'": "${Q}'$", "row a": "row ${a}$", "term d": "term ${d}$", "L depends": "${L}$ depends",
               "on t": "on $t$"}


def _math_words(sentence: str, n: dict) -> str:
    for word, tex in _MATH_WORDS.items():
        sentence = sentence.replace(word, tex.format(**n))
    return sentence


def _energy_rows(r: dict, T: str) -> list[str]:
    """T and its parts; one row `T = T_2` when T1 and T0 vanish (nothing printed twice)."""
    kinetic = r["kinetic_energy"]
    if r["T_is_T2"]:
        return [*rows(T, kinetic["T"], f"{T}_2"), f"{T}_1 &= {T}_0 = 0"]
    return [*rows(T, kinetic["T"]),
            *(row for k in ("T2", "T1", "T0") for row in rows(f"{T}_{k[1]}", kinetic[k]))]


def _constraint(j: int, c: dict, row, printer: LatexPrinter, qs: list[str], n: dict) -> dict:
    a, a_name = c["a"], n["a"]
    a_rows = ([rf"({a_name}_{{{j}k}})_k &= \left({', '.join(a)}\right)"]
              if all(len(e.lines) == 1 for e in a) and sum(e.width + 1 for e in a) + 4 <= CONTENT_WIDTH
              else [r for q, e in zip(qs, a) for r in rows(f"{a_name}_{{{j},{q}}}", e)])
    return {
        "index": j,
        "kind": c["kind"],
        "integrable": c["integrable"],
        "multiplier": printer.doprint(row.multiplier),
        "name": latex_text(c["name"] or ""),
        "rows": [*equation_rows(rf"{printer.doprint(row.multiplier)}\colon", c["expr"], Tex("0")),
                 *a_rows, *rows(f"{n['d']}_{{{j}}}", c["d"])],
    }


def _constraint_forces(r: dict, per_q, n: dict) -> list[str]:
    generalized = r["constraint_forces"]["generalized"]
    out = [row for label, q in zip(per_q(n["C"] + "_{@}"), r["coordinates"]) if q in generalized
           for row in rows(label, generalized[q])]
    for name, vector in r["constraint_forces"]["particles"].items():
        for axis, e in zip(PLANAR_AXES, vector):
            out.extend(rows(rf"{n['R']}_{{\mathrm{{{latex_text(name)}}},{axis}}}", e))
    return out


def _conserved(r: dict, qtex: dict, energy_is_jacobi: bool, n: dict) -> list[str]:
    """Conserved momenta, h and E (one row `h = T_2 - T_0 + V = T + V` when they are equal)."""
    momenta = {f"p_{name}": tex for name, tex in qtex.items()}
    kinds = {c["kind"] for c in r["conserved_quantities"]}
    merged = energy_is_jacobi and {"jacobi", "energy"} <= kinds
    out = []
    T, V, E = n["T"], n["V"], n["E"]
    for c in r["conserved_quantities"]:
        if c["kind"] == "momentum":
            out.extend(rows(f"{n['p']}_{{{momenta.get(c['name'], latex_text(c['name']))}}}", c["expr"]))
        elif c["kind"] == "jacobi":
            h_is = f"{T}_2 - {T}_0 + {V}"
            out.extend(rows(n["h"], c["expr"], f"{h_is} = {T} + {V} = {E}" if merged else h_is))
        elif not merged:
            out.extend(rows(E, c["expr"], f"{T} + {V}"))
    return out


def _number(value: float) -> str:
    """A parameter's default value in LaTeX (1e-09 -> 1 \\times 10^{-9})."""
    text = repr(float(value))
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    return rf"{mantissa} \times 10^{{{int(exponent)}}}"


def _sentence(text: str) -> str:
    text = text.strip()
    return text + "." if text and text[-1] not in ".!?" else text

