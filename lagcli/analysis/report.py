"""Text, JSON and LaTeX of the analyses (linear models, sweeps, equilibria).

Content first (`*_content`: plain dicts of numbers and strings, which is also the
JSON), then one printer per format. Numbers: JSON carries full precision
(repr of floats; complex numbers as [re, im]); text and LaTeX use 10 significant
digits, critical values 15.
"""
from __future__ import annotations

import json

import numpy as np


def number(x: float, digits: int = 10) -> str:
    x = float(x)
    return "0" if x == 0 else f"{x:.{digits}g}"


def complex_text(s: complex, digits: int = 10) -> str:
    if s.imag == 0:
        return number(s.real, digits)
    sign = "-" if s.imag < 0 else "+"
    return f"{number(s.real, digits)} {sign} {number(abs(s.imag), digits)}i"


def _matrix(a: np.ndarray) -> list[list[float]]:
    return [[float(x) for x in row] for row in np.asarray(a)]


def _pair(s: complex) -> list[float]:
    return [float(s.real), float(s.imag)]


# -- content ------------------------------------------------------------------

def linear_content(d, lm, st) -> dict:
    point = lm.point
    return {
        "name": d.model.name,
        "operating_point": {s.name: float(v) for s, v in zip(d.model.q + d.model.qd, [*point.q, *point.qd])},
        "t": point.t,
        "parameters": {p.symbol.name: point.parameters[p.symbol.name] for p in d.model.parameters},
        "input_values": {u.symbol.name: point.parameters[u.symbol.name] for u in d.model.inputs},
        "notes": list(point.notes),
        "states": list(lm.states), "inputs": list(lm.inputs), "dependent": list(lm.dependent),
        "A": _matrix(lm.A), "B": _matrix(lm.B),
        "second_order": {"coordinates": list(lm.coordinates), "speeds": list(lm.speeds),
                         "M": _matrix(lm.M), "C": _matrix(lm.C), "K": _matrix(lm.K), "B": _matrix(lm.B2),
                         "gyroscopic": _matrix(lm.gyroscopic), "damping": _matrix(lm.damping)},
        "speed_rates": [float(x) for x in lm.speed_rates],
        "eigenvalues": [_pair(s) for s in st.eigenvalues],
        "modes": [{"eigenvalue": _pair(m.eigenvalue), "natural_frequency": m.natural_frequency,
                   "damping_ratio": m.damping_ratio} for m in st.modes],
        "neutral_states": list(st.neutral),
        "negative_stiffness": st.negative_stiffness,
        "verdict": st.verdict,
    }


def sweep_content(name: str, points, critical) -> dict:
    return {
        "variable": name,
        "points": [{"value": p.value, "verdict": p.stability.verdict,
                    "eigenvalues": [_pair(s) for s in p.stability.eigenvalues]} for p in points],
        "critical": [{"value": c.value, "unstable_below": c.unstable_below,
                      "unstable_above": c.unstable_above} for c in critical],
    }


def to_json(content: dict) -> str:
    return json.dumps(content, indent=2) + "\n"


# -- text ---------------------------------------------------------------------

def _matrix_text(label: str, rows_named, cols_named, a: np.ndarray) -> list[str]:
    if a.size == 0:
        return [f"{label} = (empty)"]
    cells = [[number(x) for x in row] for row in a]
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
    lines.append("x' = A x + B u,  x = (" + ", ".join(c["states"]) + ")"
                 + (", u = (" + ", ".join(c["inputs"]) + ")" if c["inputs"] else ""))
    lines += _matrix_text("A", c["states"], c["states"], np.array(c["A"]))
    if c["inputs"]:
        lines += _matrix_text("B", c["states"], c["inputs"], np.array(c["B"]))
    s = c["second_order"]
    lines.append("")
    lines.append("second-order form  M u' + C u + K q = B u_in,  u = (" + ", ".join(s["speeds"])
                 + "), q = (" + ", ".join(s["coordinates"]) + ")")
    lines += _matrix_text("M", s["speeds"], s["speeds"], np.array(s["M"]))
    lines += _matrix_text("C", s["speeds"], s["speeds"], np.array(s["C"]))
    if np.any(np.array(s["gyroscopic"])):
        lines += _matrix_text("G = (C - C^T)/2 (gyroscopic)", s["speeds"], s["speeds"], np.array(s["gyroscopic"]))
    lines += _matrix_text("K", s["speeds"], s["coordinates"], np.array(s["K"]))
    if c["inputs"]:
        lines += _matrix_text("B", s["speeds"], c["inputs"], np.array(s["B"]))
    lines.append("")
    lines += _modes_text(c)
    return "\n".join(lines) + "\n"


def _modes_text(c: dict) -> list[str]:
    lines = ["eigenvalues" + (f" (neutral modes by structure, left out: {', '.join(c['neutral_states'])})"
                              if c["neutral_states"] else "") + ":"]
    lines.append(f"  {'eigenvalue':>34}  {'frequency (rad/s)':>18}  {'damping ratio':>14}")
    for m in c["modes"]:
        zeta = "-" if m["damping_ratio"] is None else number(m["damping_ratio"], 6)
        lines.append(f"  {complex_text(complex(*m['eigenvalue'])):>34}  {number(m['natural_frequency']):>18}  {zeta:>14}")
    verdict = c["verdict"]
    if verdict == "gyroscopically stabilized":
        verdict += " (the stiffness K alone has a negative eigenvalue; the linear model is marginally stable)"
    elif verdict == "stable":
        verdict += " (at rest on a strict minimum of the conserved h = T2 - T0 + V: Lagrange-Dirichlet)"
    elif verdict == "marginally stable":
        verdict += " (all eigenvalues on the imaginary axis: the linear model does not decide)"
    lines.append(f"verdict: {verdict}")
    return lines


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

def _bmatrix(a: np.ndarray) -> str:
    if a.size == 0:
        return r"\varnothing"
    rows = [" & ".join(number(x, 6) for x in row) for row in a]
    return r"\begin{bmatrix}" + r" \\ ".join(rows) + r"\end{bmatrix}"


def linear_latex(c: dict, printer) -> str:
    """A LaTeX fragment (amsmath): A, B, M, C, K and the eigenvalues; state names by `printer`."""
    def vec(names):
        return r"\begin{bmatrix}" + r" \\ ".join(printer(n) for n in names) + r"\end{bmatrix}"

    s = c["second_order"]
    out = [r"\begin{align*}",
           rf"x &= {vec(c['states'])}, & A &= {_bmatrix(np.array(c['A']))}"
           + (rf", & B &= {_bmatrix(np.array(c['B']))}" if c["inputs"] else "") + r" \\",
           rf"M &= {_bmatrix(np.array(s['M']))}, & C &= {_bmatrix(np.array(s['C']))}, "
           rf"& K &= {_bmatrix(np.array(s['K']))}",
           r"\end{align*}",
           "Eigenvalues: $" + ", ".join(complex_text(complex(*e), 6).replace("i", r"\,i")
                                         for e in c["eigenvalues"]) + "$; verdict: "
           + c["verdict"] + ".", ""]
    return "\n".join(out)


def equilibria_content(d, found, printer) -> dict:
    def one(e) -> dict:
        st = e.stability
        return {
            "coordinates": e.coordinates,
            "closed_form": {k: printer(v) for k, v in e.symbolic.items()} if e.symbolic else None,
            "eigenvalues": [_pair(s) for s in st.eigenvalues] if st else None,
            "frequencies": sorted({round(m.natural_frequency, 12) for m in st.modes if m.eigenvalue.imag > 0})
            if st else [],
            "verdict": st.verdict if st else "not linearizable here (singular mass matrix)",
        }

    return {"name": d.model.name, "equilibria": [one(e) for e in found]}


def equilibria_text(c: dict) -> str:
    if not c["equilibria"]:
        return f"{c['name']}: no equilibrium found\n  hint: give a starting point with --guess NAME=VALUE,...\n"
    lines = [f"equilibria of {c['name']} (q' = 0):"]
    for k, e in enumerate(c["equilibria"], 1):
        where = ", ".join(f"{q} = {number(v, 12)}" for q, v in e["coordinates"].items())
        lines.append(f"{k}. {where}: {e['verdict']}")
        if e["closed_form"]:
            lines.append("   closed form: " + ", ".join(f"{q} = {v}" for q, v in e["closed_form"].items()))
        if e["eigenvalues"] is not None:
            values = ", ".join(complex_text(complex(*s), 8) for s in e["eigenvalues"])
            lines.append(f"   eigenvalues: {values or '(none)'}")
        if e["frequencies"]:
            lines.append("   small-oscillation frequencies (rad/s): " + ", ".join(number(w) for w in e["frequencies"]))
    return "\n".join(lines) + "\n"


def routh_content(d, routh, motions, printer) -> dict:
    return {
        "name": d.model.name,
        "cyclic": [c.name for c in routh.cyclic],
        "momenta": [p.name for p in routh.momenta],
        "routhian": printer(routh.R),
        "effective_potential": printer(routh.effective_potential),
        "cyclic_velocities": {d.model.qd[d.model.q.index(c)].name: printer(e)
                              for c, e in zip(routh.cyclic, routh.cyclic_velocities)},
        "reduced_equations": [printer(e) for e in routh.equations],
        "steady_motions": [{"coordinates": m.coordinates, "cyclic_rates": m.cyclic_rates,
                            "eigenvalues": [_pair(s) for s in m.eigenvalues],
                            "frequencies": list(m.frequencies)} for m in motions],
    }


def routh_text(c: dict) -> str:
    lines = [f"Routh reduction of {c['name']} over {', '.join(c['cyclic'])} "
             f"(momenta {', '.join(c['momenta'])} held constant)",
             f"R = {c['routhian']}", f"V_eff = {c['effective_potential']}"]
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


def hamilton_content(d, form, printer) -> dict:
    model = d.model
    return {
        "name": model.name,
        "momenta": {p.name: printer(e) for p, e in zip(form.momenta, form.momentum_exprs)},
        "hamiltonian": printer(form.H) if form.H is not None else None,
        "equations": ({**{q.name + "_dot": printer(e) for q, e in zip(model.q, form.qdot)},
                       **{p.name + "_dot": printer(e) for p, e in zip(form.momenta, form.pdot)}}
                      if form.H is not None else None),
        "solved_form": form.H is None,
    }


def hamilton_text(c: dict) -> str:
    lines = [f"Hamilton's equations of {c['name']}", "momenta:"]
    lines += [f"  {p} = {e}" for p, e in c["momenta"].items()]
    if c["solved_form"]:
        lines += ["H = 1/2 (p - a)^T M^-1 (p - a) - T0 + V   (M full and larger than 2 x 2: kept solved)",
                  "q_dot = M^-1 (p - a),  p_dot = dL/dq + Q'  at that q_dot"]
    else:
        lines.append(f"H = {c['hamiltonian']}")
        lines += [f"  {k} = {e}" for k, e in c["equations"].items()]
    return "\n".join(lines) + "\n"


def hamilton_latex(c_form, d, latex_printer) -> str:
    model = d.model
    if c_form.H is None:
        return ("% M is full and larger than 2 x 2: H is kept in its solved form\n"
                r"\[ H = \tfrac12 (p - a)^\mathsf{T} M^{-1} (p - a) - T_0 + V \]" + "\n")
    rows = [rf"H &= {latex_printer.doprint(c_form.H)}"]
    for q, p, qd, pd in zip(model.q, c_form.momenta, c_form.qdot, c_form.pdot):
        rows.append(rf"\dot{{{latex_printer.doprint(q)}}} &= {latex_printer.doprint(qd)}")
        rows.append(rf"\dot p_{{{latex_printer.doprint(q)}}} &= {latex_printer.doprint(pd)}")
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}\n"


def symbolic_content(d, lin, printer) -> dict:
    return {"name": d.model.name, "states": list(lin.states), "inputs": list(lin.inputs),
            "A": [[printer(e) for e in lin.A.row(i)] for i in range(lin.A.rows)],
            "B": [[printer(e) for e in lin.B.row(i)] for i in range(lin.B.rows)]}


def symbolic_text(c: dict) -> str:
    lines = [f"linearization of {c['name']} (symbolic)",
             "x' = A x + B u,  x = (" + ", ".join(c["states"]) + ")"
             + (", u = (" + ", ".join(c["inputs"]) + ")" if c["inputs"] else "")]
    for label, rows in (("A", c["A"]), ("B", c["B"])):
        if rows and rows[0]:
            lines.append(f"{label} =")
            lines += [f"  {state}: [" + ", ".join(row) + "]" for state, row in zip(c["states"], rows)]
    return "\n".join(lines) + "\n"


def symbolic_latex(lin, printer) -> str:
    out = [r"\begin{align*}", rf"A &= {printer.doprint(lin.A)}"]
    if lin.B.cols:
        out[-1] += r" \\"
        out.append(rf"B &= {printer.doprint(lin.B)}")
    return "\n".join(out + [r"\end{align*}", ""])
