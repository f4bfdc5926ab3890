"""Text, JSON and LaTeX of the analyses (linear models, sweeps, equilibria).

Content first (`*_content`: plain dicts of numbers and strings, which is also the
JSON), then one printer per format. Numbers: JSON carries full precision
(repr of floats; complex numbers as [re, im]); text and LaTeX use 10 significant
digits, critical values 15.
"""
from __future__ import annotations

import json

import numpy as np
import sympy as sp

from lagcli.analysis.wording import (complex_text, drift_sentence, modes_content, modes_text,
                                     motion_lines, number, pair)
from lagcli.render.escape import latex_text
from lagcli.report.display import signed_sum
from lagcli.report.notation import analysis_letters, linear_equations


ROUND_OFF = 1000 * float(np.finfo(float).eps)   # relative size below which an entry is round-off
ROUND_OFF_RULE = ("text and LaTeX show an entry as 0 when |entry| <= round_off x max|entry| of its matrix "
                  "(of G: of C); the JSON keeps every float as computed")

POINT_ROUND_OFF = 1e-10     # relative size below which a coordinate of a solved point is 0 (the solve's accuracy)
POINT_ROUND_OFF_RULE = ("text shows a coordinate as 0 when |value| <= round_off x max(1, max|value|) of its "
                        "point (a point is solved to residuals of 1e-10); the JSON keeps every float as computed")


def shown(a, scale: float | None = None) -> np.ndarray:
    """`a` as text, LaTeX and the notebook show it: entries within round-off of 0 relative
    to their matrix (or to `scale`) are 0, so 7e-17 next to 0.49 is not read as data."""
    a = np.asarray(a, dtype=float)
    size = np.max(np.abs(a), initial=0.0) if scale is None else scale
    return np.where(np.abs(a) <= ROUND_OFF * size, 0.0, a)


def shown_point(point: dict) -> np.ndarray:
    """The values of a point {coordinate: value} as text shows them: what the solve cannot
    tell from 0 (relative to the largest value, or to 1) is 0, so 7e-13 is not read as a position."""
    values = np.array(list(point.values()), dtype=float)
    scale = max(1.0, float(np.max(np.abs(values), initial=0.0)))
    return np.where(np.abs(values) <= POINT_ROUND_OFF * scale, 0.0, values)


def _matrix(a: np.ndarray) -> list[list[float]]:
    return [[float(x) for x in row] for row in np.asarray(a)]


# -- content ------------------------------------------------------------------

def linear_content(lin) -> dict:
    """The JSON of a `results.Linearization`."""
    point = lin.point
    return {
        "name": lin.name,
        "operating_point": point.state,
        "t": point.t,
        "parameters": point.parameters,
        "input_values": point.inputs,
        "notes": list(point.notes),
        "states": list(lin.states), "inputs": list(lin.inputs), "dependent": list(lin.dependent),
        "A": _matrix(lin.A), "B": _matrix(lin.B),
        "second_order": {"coordinates": list(lin.coordinates), "speeds": list(lin.speeds),
                         "M": _matrix(lin.M), "C": _matrix(lin.C), "K": _matrix(lin.K), "B": _matrix(lin.B_second),
                         "gyroscopic": _matrix(lin.gyroscopic), "damping": _matrix(lin.damping)},
        "speed_rates": [float(x) for x in lin.speed_rates],
        "eigenvalues": [pair(s) for s in lin.eigenvalues],
        "modes": modes_content(lin.modes),
        "neutral_states": list(lin.neutral),
        "drift": list(lin.drift),
        "defective": [pair(s) for s in lin.defective],
        "negative_stiffness": lin.negative_stiffness,
        "verdict": lin.verdict,
        "evidence": lin.evidence,
        "round_off": {"relative": ROUND_OFF, "rule": ROUND_OFF_RULE},
        "notation": lin.letters,
    }


def sweep_content(result) -> dict:
    """The JSON of a `sweep.LinearizationSweep`."""
    return {
        "variable": result.variable,
        "points": [{"value": p.value, "verdict": p.stability.verdict,
                    "eigenvalues": [pair(s) for s in p.stability.eigenvalues]} for p in result.points],
        "critical": [{"value": c.value, "unstable_below": c.unstable_below,
                      "unstable_above": c.unstable_above} for c in result.critical],
    }


def to_json(content: dict) -> str:
    return json.dumps(content, indent=2) + "\n"


# -- text ---------------------------------------------------------------------

def _matrix_text(label: str, rows_named, cols_named, a: np.ndarray) -> list[str]:
    if a.size == 0:
        return [f"{label} = (empty)"]
    cells = [[number(x) for x in row] for row in shown(a)]
    width = max(len(c) for row in cells for c in row + list(cols_named))
    head = max(len(r) for r in rows_named)
    out = [f"{label} =", " " * (head + 4) + " ".join(c.rjust(width) for c in cols_named)]
    for name, row in zip(rows_named, cells):
        out.append(f"  {name.rjust(head)}  " + " ".join(c.rjust(width) for c in row))
    return out


def linear_text(c: dict) -> str:
    state = ", ".join(f"{k} = {number(v)}" for k, v in c["operating_point"].items())
    lines = [f"linearization of {c['name']} about {state}" + (f" (t = {number(c['t'])})" if c["t"] else "")]
    lines += [f"  {note}" for note in c["notes"]]
    lines.append("parameters: " + ", ".join(f"{k} = {number(v)}" for k, v in c["parameters"].items()))
    if c["inputs"]:
        held = c["input_values"]
        lines.append("inputs: " + ", ".join(f"{k} = {number(held[k])}" if k in held else k for k in c["inputs"]))
    if c["dependent"]:
        lines.append("dependent (eliminated): " + ", ".join(c["dependent"]))
    rates = c["speed_rates"]
    if any(abs(r) > 1e-9 for r in rates):
        lines.append("warning: not an equilibrium or steady motion: "
                     + ", ".join(f"{s}' = {number(r)}" for s, r in zip(c["second_order"]["speeds"], rates)))
    lines.append("")
    n, s = c["notation"], c["second_order"]
    lines.append(first_order_line(n, c["states"], c["inputs"]))
    lines += _matrix_text(n["A"], c["states"], c["states"], np.array(c["A"]))
    if c["inputs"]:
        lines += _matrix_text(n["B"], c["states"], c["inputs"], np.array(c["B"]))
    lines.append("")
    lines.append(f"second-order form  {linear_equations(n, bool(c['inputs']))[1]},  {n['v']} = (" + ", ".join(s["speeds"]) + f"), {n['q']} = (" + ", ".join(s["coordinates"]) + ")")
    lines += _matrix_text(n["M"], s["speeds"], s["speeds"], np.array(s["M"]))
    lines += _matrix_text(n["C"], s["speeds"], s["speeds"], np.array(s["C"]))
    gyroscopic = shown(s["gyroscopic"], np.max(np.abs(np.array(s["C"])), initial=0.0))
    if np.any(gyroscopic):       # not round-off of a symmetric C printed as a physical effect
        lines += _matrix_text(f"{n['G']} = ({n['C']} - {n['C']}^T)/2 (gyroscopic)", s["speeds"], s["speeds"],
                              gyroscopic)
    lines += _matrix_text(n["K"], s["speeds"], s["coordinates"], np.array(s["K"]))
    if c["inputs"]:
        lines += _matrix_text(n["F"], s["speeds"], c["inputs"], np.array(s["B"]))
    lines.append("")
    lines += modes_text(c)
    return "\n".join(lines) + "\n"


def first_order_line(n: dict, states, inputs) -> str:
    """`x' = A x + B u,  x = (...), u = (...)` in the output's letters `n` (`linear_letters`)."""
    return (linear_equations(n, bool(inputs))[0] + f",  {n['x']} = (" + ", ".join(states) + ")"
            + (f", {n['u']} = (" + ", ".join(inputs) + ")" if inputs else ""))


def sweep_text(c: dict) -> str:
    lines = [f"{c['variable']:>14}  {'verdict':<26}  eigenvalues"]
    for p in c["points"]:
        values = ", ".join(complex_text(complex(*s), 8) for s in p["eigenvalues"])
        lines.append(f"{number(p['value']):>14}  {p['verdict']:<26}  {values}")
    for crit in c["critical"]:
        lines.append(f"critical {c['variable']} = {number(crit['value'], 15)}: unstable eigenvalues "
                     f"{crit['unstable_below']} -> {crit['unstable_above']}")
    return "\n".join(lines) + "\n"


# -- LaTeX --------------------------------------------------------------------

def bmatrix(a: np.ndarray) -> str:
    if a.size == 0:
        return r"\varnothing"
    rows = [" & ".join(number(x, 6) for x in row) for row in shown(a)]
    return r"\begin{bmatrix}" + r" \\ ".join(rows) + r"\end{bmatrix}"


def linear_latex(c: dict, printer) -> str:
    """A LaTeX fragment (amsmath): x' = A x + B u, M v' + C v + K q = F u with their
    matrices, and the eigenvalues; state names by `printer`, letters `c["notation"]`."""
    from lagcli.report.notation import linear_latex_letters

    def vec(names):
        return r"\begin{bmatrix}" + r" \\ ".join(printer(n) for n in names) + r"\end{bmatrix}"

    s, n, inputs = c["second_order"], linear_latex_letters(c["notation"]), c["inputs"]
    first, second = (e.replace(" = ", " &= ") for e in linear_equations(n, bool(inputs), r"\,"))
    out = [r"\begin{align*}",
           first + rf", & {n['x']} &= {vec(c['states'])}" + (rf", & {n['u']} &= {vec(inputs)}" if inputs else "") + r" \\",
           rf"{n['A']} &= {bmatrix(np.array(c['A']))}"
           + (rf", & {n['B']} &= {bmatrix(np.array(c['B']))}" if inputs else "") + r" \\",
           second + rf", & {n['v']} &= {vec(s['speeds'])}, & {n['q']} &= {vec(s['coordinates'])} \\",
           rf"{n['M']} &= {bmatrix(np.array(s['M']))}, & {n['C']} &= {bmatrix(np.array(s['C']))}, "
           rf"& {n['K']} &= {bmatrix(np.array(s['K']))}"
           + (rf", & {n['F']} &= {bmatrix(np.array(s['B']))}" if inputs else ""),
           r"\end{align*}",
           "Eigenvalues: $" + ", ".join(complex_text(complex(*e), 6).replace("i", r"\,i")
                                         for e in c["eigenvalues"]) + "$; "
           + (latex_text("drift: " + drift_sentence(c["drift"])) + "; " if c["drift"] else "")
           + "verdict: " + latex_text(f"{c['verdict']} ({c['evidence']})") + ".", ""]
    return "\n".join(out)


def equilibria_content(found, printer) -> dict:
    """The JSON of `results.Equilibria`; closed forms printed by `printer`."""
    def one(e) -> dict:
        return {
            "coordinates": e.point,
            "closed_form": {k: printer(v) for k, v in e.closed_form.items()} if e.closed_form else None,
            "eigenvalues": [pair(s) for s in e.eigenvalues] if e.linearization or e.eigenvalues.size else None,
            "frequencies": list(e.frequencies),
            "modes": modes_content(e.modes),
            "drift": list(e.drift),
            "verdict": e.verdict,
            "evidence": e.evidence,
            "free": list(e.free),
            "coordinate_singularity": list(e.singular.notes) if e.singular is not None else [],
        }

    return {"name": found.name, "equilibria": [one(e) for e in found], "proved_none": found.proved_none,
            "round_off": {"relative": POINT_ROUND_OFF, "rule": POINT_ROUND_OFF_RULE}}


def equilibria_text(c: dict) -> str:
    if c["proved_none"]:
        return f"{c['name']}: there is no equilibrium: the equations at rest have no solution (solved in closed form)\n"
    if not c["equilibria"]:
        return f"{c['name']}: no equilibrium found\n  hint: give a starting point with --guess NAME=VALUE,...\n"
    lines = [f"equilibria of {c['name']} (q' = 0):"]
    for k, e in enumerate(c["equilibria"], 1):
        where = ", ".join(f"{q} = {number(v, 12)}" for q, v in zip(e["coordinates"], shown_point(e["coordinates"])))
        lines.append(f"{k}. {where}: {e['verdict']}")
        if e["free"]:
            lines.append(f"   one of a family along {', '.join(e['free'])} (shown: the member nearest the first guess)")
        lines += [f"   {note}" for note in e["coordinate_singularity"]]
        if e["closed_form"]:
            lines.append("   closed form: " + ", ".join(f"{q} = {v}" for q, v in e["closed_form"].items()))
        if e["evidence"]:
            lines.append(f"   because: {e['evidence']}")
        if e["eigenvalues"] is not None:
            values = ", ".join(complex_text(complex(*s), 8) for s in e["eigenvalues"])
            lines.append(f"   eigenvalues: {values or '(none)'}")
            lines += [f"   {line}" for line in motion_lines(e["modes"], e["verdict"])]
        if e["drift"]:
            lines.append(f"   drift: {drift_sentence(e['drift'])}")
    return "\n".join(lines) + "\n"


def routh_content(r, printer) -> dict:
    """The JSON of a `results.Routh`; expressions printed by `printer`."""
    return {
        "name": r.name,
        "cyclic": list(r.cyclic),
        "momenta": list(r.momenta),
        "routhian": printer(r.R),
        "effective_potential": printer(r.effective_potential),
        "cyclic_velocities": {name: printer(e) for name, e in r.cyclic_velocities.items()},
        "reduced_equations": [signed_sum(terms, printer) for terms in r.reduced_terms],
        "steady_motions": [{"coordinates": m.coordinates, "cyclic_rates": m.cyclic_rates,
                            "eigenvalues": [pair(s) for s in m.eigenvalues],
                            "frequencies": list(m.frequencies)} for m in r.steady_motions],
        "notation": analysis_letters(r.derivation)["text"],
    }


def routh_rows(r, d) -> list[str]:
    """`lhs &= rhs` LaTeX rows of a `results.Routh` (the notebook's display)."""
    from lagcli.report.latex import latex_printer

    printer = latex_printer(d)
    model = d.model
    printer._settings["symbol_names"].update({sp.Symbol(p, real=True): f"p_{{{printer.doprint(model.symbol(c))}}}"
                                              for p, c in zip(r.momenta, r.cyclic)})
    R = analysis_letters(d)["latex"]["R"]
    rows = [rf"{R} &= {printer.doprint(r.R)}", rf"V_{{\mathrm{{eff}}}} &= {printer.doprint(r.effective_potential)}"]
    rows += [rf"{printer.doprint(model.symbol(name))} &= {printer.doprint(e)}"
             for name, e in r.cyclic_velocities.items()]
    return rows + [rf"0 &= {printer.tex_terms(terms)}" for terms in r.reduced_terms]


def routh_text(c: dict) -> str:
    lines = [f"Routh reduction of {c['name']} over {', '.join(c['cyclic'])} "
             f"(momenta {', '.join(c['momenta'])} held constant)",
             f"{c['notation']['R']} = {c['routhian']}", f"V_eff = {c['effective_potential']}"]
    lines += [f"{name} = {expr}" for name, expr in c["cyclic_velocities"].items()]
    lines += ["reduced equations (= 0):"] + [f"  {e}" for e in c["reduced_equations"]]
    if not c["steady_motions"]:
        lines.append("no steady motion found at these momenta\n  hint: give a starting point with --guess")
    for k, m in enumerate(c["steady_motions"], 1):
        where = ", ".join(f"{q} = {number(v, 12)}" for q, v in {**m["coordinates"], **m["cyclic_rates"]}.items())
        lines.append(f"steady motion {k}: {where}")
        lines.append("   eigenvalues: " + ", ".join(complex_text(complex(*s), 8) for s in m["eigenvalues"]))
        if m["frequencies"]:
            lines.append("   small-oscillation frequencies (rad/s): " + ", ".join(number(w) for w in m["frequencies"]))
    return "\n".join(lines) + "\n"


def hamilton_content(h, printer) -> dict:
    """The JSON of a `results.Hamiltonian`; expressions printed by `printer`."""
    return {
        "name": h.name,
        "momenta": {name: printer(e) for name, e in h.momenta.items()},
        "hamiltonian": printer(h.H) if h.H is not None else None,
        "equations": {name: printer(e) for name, e in h.equations.items()} if h.H is not None else None,
        "solved_form": h.H is None,
        "notation": analysis_letters(h.derivation)["text"],
    }


def hamilton_text(c: dict) -> str:
    n = c["notation"]
    H, M, a = n["H"], n["M"], n["a"]
    lines = [f"Hamilton's equations of {c['name']}", "momenta:"]
    lines += [f"  {p} = {e}" for p, e in c["momenta"].items()]
    if c["solved_form"]:
        lines += [f"{H} = 1/2 (p - {a})^T {M}^-1 (p - {a}) - {n['T']}0 + {n['V']}   "
                  f"({M} full and larger than 2 x 2: kept solved)",
                  f"q_dot = {M}^-1 (p - {a}),  p_dot = dL/dq + Q'  at that q_dot"]
    else:
        lines.append(f"{H} = {c['hamiltonian']}")
        lines += [f"  {k} = {e}" for k, e in c["equations"].items()]
    return "\n".join(lines) + "\n"


SOLVED_H = r"{H} &= \tfrac12 (p - {a})^\mathsf{{T}} {M}^{{-1}} (p - {a}) - {T}_0 + {V}"


def hamilton_rows(form, d) -> list[str]:
    """`lhs &= rhs` LaTeX rows: H and Hamilton's equations (H alone, solved, when M is large)."""
    from lagcli.report.latex_printer import LatexPrinter

    n = analysis_letters(d)["latex"]
    if form.H is None:
        return [SOLVED_H.format(**n)]
    model = d.model
    printer = LatexPrinter(model)
    printer._settings["symbol_names"].update({p: f"p_{{{printer.doprint(q)}}}" for p, q in zip(form.momenta, model.q)})
    rows = [rf"{n['H']} &= {printer.doprint(form.H)}"]
    for q, qd, pd in zip(model.q, form.qdot, form.pdot):
        rows.append(rf"\dot{{{printer.doprint(q)}}} &= {printer.doprint(qd)}")
        rows.append(rf"\dot p_{{{printer.doprint(q)}}} &= {printer.doprint(pd)}")
    return rows


def hamilton_latex(form, d) -> str:
    """The command's LaTeX fragment (amsmath align*)."""
    if form.H is None:
        return ("% M is full and larger than 2 x 2: H is kept in its solved form\n"
                r"\[ " + SOLVED_H.format(**analysis_letters(d)["latex"]).replace("&=", "=") + r" \]" + "\n")
    return "\\begin{align*}\n" + " \\\\\n".join(hamilton_rows(form, d)) + "\n\\end{align*}\n"


def symbolic_letters(d, lin) -> dict[str, str]:
    """The letters of a symbolic linearization: none a name of the spec (its entries are
    expressions of the parameters)."""
    from lagcli.report.notation import linear_letters, user_names

    return linear_letters((*user_names(d.model), *lin.states, *lin.inputs))


def symbolic_content(d, lin, printer) -> dict:
    return {"name": d.model.name, "states": list(lin.states), "inputs": list(lin.inputs),
            "A": [[printer(e) for e in lin.A.row(i)] for i in range(lin.A.rows)],
            "B": [[printer(e) for e in lin.B.row(i)] for i in range(lin.B.rows)],
            "notation": symbolic_letters(d, lin)}


def symbolic_text(c: dict) -> str:
    n = c["notation"]
    lines = [f"linearization of {c['name']} (symbolic)", first_order_line(n, c["states"], c["inputs"])]
    for label, rows in ((n["A"], c["A"]), (n["B"], c["B"])):
        if rows and rows[0]:
            lines.append(f"{label} =")
            lines += [f"  {state}: [" + ", ".join(row) + "]" for state, row in zip(c["states"], rows)]
    return "\n".join(lines) + "\n"


def symbolic_latex(d, lin, printer) -> str:
    from lagcli.report.notation import linear_latex_letters

    n = linear_latex_letters(symbolic_letters(d, lin))
    out = [r"\begin{align*}", rf"{n['A']} &= {printer.doprint(lin.A)}"]
    if lin.B.cols:
        out[-1] += r" \\"
        out.append(rf"{n['B']} &= {printer.doprint(lin.B)}")
    return "\n".join(out + [r"\end{align*}", ""])
