"""What `derive` reports, as pre-printed strings, shared by text, JSON and LaTeX.

`report_content(derivation, printer)` returns a plain dict (the JSON keys of
docs/derive.md plus a few extensions) whose expressions are strings made by a
`ReportPrinter`: `expr` prints one expression, `terms` an ordered sum. Every
expression is assembled from small parts tidied once (`lagcli.report.display`), so
the same spec gives the same report on any machine, fast: nothing large is ever
simplified.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import sympy as sp

from lagcli.derive.result import Derivation
from lagcli.report.display import Display, signed_sum
from lagcli.report.naming import Namer
from lagcli.report.notation import notation_of, spoken_list
from lagcli.report.hybrid_report import check_lines, hybrid_content


PARTS = ("system", "energies", "forces", "equations", "constraints", "explicit", "conservation", "events")


def report_parts(selection: str | None) -> tuple[str, ...]:
    """The sections of a text or LaTeX report named in `selection` ("equations,energies"),
    in report order; every section for None."""
    from lagcli.errors import UsageError

    if selection is None:
        return PARTS
    chosen = {name.strip() for name in selection.split(",") if name.strip()}
    unknown = sorted(chosen - set(PARTS))
    if unknown or not chosen:
        raise UsageError(f"--part {selection}: unknown part {', '.join(unknown) or '(none given)'}; "
                         f"choose from {', '.join(PARTS)}")
    return tuple(name for name in PARTS if name in chosen)


@dataclass(frozen=True)
class ReportPrinter:
    expr: Callable[[sp.Expr], str]                 # one expression
    terms: Callable[[Sequence[sp.Expr]], str]      # an ordered sum, signs pulled out


def spec_printer() -> ReportPrinter:
    """The spec language (text report and JSON): every string parses back with lagcli's parser."""
    from lagcli.render.spec_printer import remembering_spec_str

    spec_str = remembering_spec_str()
    pieces: dict = {}      # each term printed once with its sign (`signed_sum`)
    return ReportPrinter(spec_str, lambda terms: signed_sum(terms, spec_str, pieces))


def report_content(d: Derivation, printer: ReportPrinter, simplify: bool = True,
                   named: bool = False) -> dict:
    """The report of `d`. `named` (text, LaTeX): big expressions are shown with named
    intermediate quantities, listed under "named_quantities" (`lagcli.report.naming`);
    without it (JSON) every expression is complete."""
    m = d.model
    shown = Display(d, simplify)
    taken = (m.t, *m.q, *m.qd, *m.qdd, *m.parameter_symbols, *m.input_symbols, *d.multipliers)
    namer = Namer(s.name for s in taken) if named else None

    def p(expr) -> str:
        return printer.expr(namer(expr) if namer else expr)

    def terms(items) -> str:
        return printer.terms(namer.terms(items) if namer else items)

    content = _content(d, shown, p, terms)
    content.update(hybrid_content(d, p))
    content["parameters"] = {pi.symbol.name: pi.value for pi in m.parameters}
    content["renamed_parameters"] = {}       # kept for old readers: the user's names are never renamed
    content["named_quantities"] = [] if namer is None else [
        {"name": symbol.name, "expr": printer.expr(value)} for symbol, value in namer.definitions]
    return content


def text_report(d: Derivation, simplify: bool = True, parts=PARTS) -> str:
    """`lagcli derive --text`: the content in the spec language, the report's own letters
    yielding to the spec's names (`lagcli.report.notation`)."""
    from lagcli.render.templates import render

    content = report_content(d, spec_printer(), simplify, named=True)
    n = notation_of(d)
    legend = n.legend(n.text)
    line = ", ".join(f"{shown} = {meaning}" for _, shown, meaning in legend)
    if legend:
        line += f" ({spoken_list([letter for letter, _, _ in legend])} the spec's own)"
    return render("report/derive.txt.jinja", r=content, parts=parts, n=n.texts, legend=legend,
                  legend_line=line, no_jacobi_reason=n.sentence(content["no_jacobi_reason"] or ""))


def _content(d: Derivation, shown: Display, p, terms) -> dict:
    m = d.model
    qs = range(len(m.q))

    def column(values) -> dict:
        return {q.name: v for q, v in zip(m.q, values)}

    def rows(matrix) -> list:
        return [[p(e) for e in row] for row in matrix]

    def part(names) -> dict:
        return column(terms(shown.part_terms(i, names)) for i in qs)

    energy_is_jacobi = d.energy_is_jacobi
    return {
        "name": m.name,
        "description": m.description,
        "coordinates": [q.name for q in m.q],
        "velocities": [v.name for v in m.qd],
        "parameters": {pi.symbol.name: pi.value for pi in m.parameters},
        "units": {name: text for name, (text, _) in m.units.items()},
        "inputs": {u.symbol.name: u.value for u in m.inputs},     # name -> default
        "known": {name: p(shown.tidy(expr)) for name, expr in m.known},
        "counts": {"coordinates": len(m.q), "holonomic": d.n_holonomic,
                   "nonholonomic": d.n_nonholonomic},
        "dof": d.dof,
        "scleronomic": d.scleronomic,
        "kinetic_energy": {"T": terms(shown.T), "T2": terms(shown.T2), "T1": terms(shown.T1),
                           "T0": p(shown.T0)},
        "T_is_T2": shown.T_is_T2,
        "mass_matrix": rows(shown.M),
        "potential_energy": p(shown.V),
        "lagrangian": terms(shown.lagrangian),
        "generalized_forces": column(p(shown.generalized_force(i)) for i in qs),
        "nonconservative_forces": column(p(e) for e in shown.Qp),
        "forces_conservative": d.forces_conservative,
        "force_potential": None if d.force_potential is None else p(shown.tidy(d.force_potential)),
        "equations": [{"coordinate": q.name, "lhs": terms(shown.equation(i)),
                       "rhs": terms(shown.constraint_force(i))} for i, q in enumerate(m.q)],
        "explicit_form": {
            "velocity_terms": part(["velocity"]),
            "mass_rate_terms": part(["mass_rate"]),
            "t1_rate_terms": part(["t1_rate"]),
            "position_terms": part(["position"]),
            "forcing": column(terms(shown.forcing(i)) for i in qs),
        },
        "constraints": [{"kind": r.kind, "name": r.label, "multiplier": r.multiplier.name,
                         "expr": p(shown.tidy(r.expr)), "a": [p(e) for e in a], "d": p(shown.tidy(r.d)),
                         "integrable": r.integrable} for r, a in zip(d.constraints, shown.A)],
        "multipliers": [lam.name for lam in d.multipliers],
        "constraint_forces": {
            "generalized": column(terms(shown.constraint_force(i)) for i in qs) if d.constraints else {},
            "particles": {name: [p(shown.tidy(e)) for e in vec[: m.dimension]]
                          for name, vec in d.particle_constraint_forces.items()},
        },
        "gyroscopic_matrix": rows(shown.gyroscopic),
        "ignorable_coordinates": [q.name for q in d.ignorable],
        "conserved_quantities": [{"name": c.name, "kind": c.kind, "expr": terms(shown.conserved(c.kind, c.name))}
                                 for c in d.conserved],
        "jacobi_integral": None if d.jacobi_integral is None else terms(shown.jacobi),
        "energy_is_jacobi": energy_is_jacobi,
        "no_jacobi_reason": d.no_jacobi_reason,
    }


def check_content(d: Derivation) -> dict:
    """The one-screen summary of `lagcli check`, as plain strings and numbers."""
    m = d.model
    if d.jacobi_integral is None:
        jacobi = f"does not exist ({d.no_jacobi_reason})"
    else:
        jacobi = "exists (= total energy)" if d.energy_is_jacobi else "exists (differs from the total energy)"
    return {
        "source": m.source, "name": m.name, "description": m.description,
        "coordinates": ", ".join(q.name for q in m.q), "n": len(m.q),
        "parameters": ", ".join(f"{p.symbol.name} = {p.value:g}" + (f" {m.units[p.symbol.name][0]}"
                                if p.symbol.name in m.units else "") for p in m.parameters) or "none",
        "inputs": ", ".join(f"{u.symbol.name} (default {u.value:g})" for u in m.inputs),
        "particles": ", ".join(p.name for p in m.particles) or "none",
        "bodies": ", ".join(b.name for b in m.bodies) or "none",
        "holonomic": d.n_holonomic, "nonholonomic": d.n_nonholonomic,
        "integrable": [c.multiplier.name for c in d.constraints if c.integrable],
        "dof": d.dof,
        "time": "scleronomic" if d.scleronomic else "rheonomic",
        "ignorable": ", ".join(q.name for q in d.ignorable) or "none",
        "jacobi": jacobi,
        "hybrid": check_lines(d),
    }
