"""Routh reduction over the cyclic coordinates (lecture notes, the Routhian).

For cyclic coordinates s (ignorable and absent from every constraint row) with momenta p_s = dL/dq'_s = M_ss q'_s + M_sr q'_r + a_s
held at given values, the cyclic velocities are eliminated,

    q'_s = M_ss^-1 (p_s - M_sr q'_r - a_s),

and the Routhian R(q_r, q'_r) = L - p_s . q'_s is the Lagrangian of the reduced
coordinates r: d/dt(dR/dq'_r) - dR/dq_r = Q'_r. Its velocity-free part gives the
effective potential

    V_eff(q_r) = -R(q_r, 0) = V - T0 + 1/2 (p_s - a_s)^T M_ss^-1 (p_s - a_s),

whose stationary points are the steady motions (q_r constant, q'_s constant),
and small oscillations about one follow from M_red q_r'' + G q_r' + K q_r = 0
with M_red = d2R/dq'_r^2, K the Hessian of V_eff and G the gyroscopic matrix of
R's part linear in q'_r. M_ss is inverted symbolically: it is as small as the
number of cyclic coordinates.

A constrained system reduces the same way when its cyclic coordinates appear nowhere
in the constraints (neither q_s nor q'_s in any row): column s of A is zero, so the
q_s equation is p_s' = 0 with no multiplier, and the reduced equations keep their
multipliers, d/dt(dR/dq'_r) - dR/dq_r - Q'_r = sum_j lambda_j a_jr, with the
constraint rows unchanged. An ignorable coordinate that a constraint contains (as
sin(phi) in the notes' Ex. 6-9: p_phi is conserved all the same) is refused, since
the reduced system would still depend on it. Steady motions (`steady_motions`) are
found for unconstrained systems only.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagcli.derive.hamilton_form import tidy_fraction, tidy_split
from lagcli.errors import UsageError
from lagcli.render.tidy import display_form, pull_signs


@dataclass(frozen=True)
class Routhian:
    cyclic: tuple[sp.Symbol, ...]
    momenta: tuple[sp.Symbol, ...]          # p_<q> symbols
    reduced: tuple[sp.Symbol, ...]          # q_r
    R: sp.Expr                              # R(q_r, q'_r, p)
    effective_potential: sp.Expr            # V_eff(q_r, p)
    cyclic_velocities: tuple[sp.Expr, ...]  # q'_s(q_r, q'_r, p)
    equations: tuple[sp.Expr, ...]          # d/dt(dR/dq'_r) - dR/dq_r - Q'_r = 0
    equation_terms: tuple[tuple[sp.Expr, ...], ...] = ()   # each equation's terms as printed: q'' first


def routhian(d) -> Routhian:
    model = d.model
    cyclic = tuple(d.ignorable)
    if not cyclic:
        raise UsageError(f"{model.source}: no ignorable coordinate, nothing to reduce\n"
                         "  hint: `lagcli derive` lists the ignorable coordinates")
    _require_absent_from_constraints(d, cyclic)
    s = [model.q.index(c) for c in cyclic]
    r = [k for k in range(len(model.q)) if k not in s]
    # L does not depend on a cyclic coordinate, but may still hold it in a form that cancels
    # (sin(phi)**2 + cos(phi)**2 where the tidying gave up): any value of it is exact, and 0
    # leaves no cyclic coordinate in R (it would be an unknown name at the numbers)
    # M, a and T0 - V as the reports print them (sin^2 + cos^2 = 1, angle sums folded), so
    # the solved forms start from tidy entries; each result is one fraction tidied as
    # Hamilton's form is (`tidy_fraction`), V_eff = V - T0 + the momenta's part, and
    # R = its velocity part - V_eff, as a textbook writes them
    absent = {c: sp.S.Zero for c in cyclic}
    M = sp.Matrix(d.mass_matrix).xreplace(absent).applyfunc(display_form)
    a = sp.Matrix(d.t1_coefficients).xreplace(absent).applyfunc(display_form)
    p = sp.Matrix([sp.Symbol(f"p_{c.name}", real=True) for c in cyclic])
    M_ss, M_sr = M.extract(s, s), M.extract(s, r)
    qd_r = sp.Matrix([model.qd[k] for k in r])
    qd_s = M_ss.LUsolve(p - M_sr * qd_r - a.extract(s, [0])).applyfunc(tidy_fraction)
    eliminate = {model.qd[k]: e for k, e in zip(s, qd_s)}
    qd = sp.Matrix(model.qd)
    potential = display_form((d.V - d.T0).xreplace(absent))            # V - T0
    L = (qd.T * M * qd)[0] / 2 + (a.T * qd)[0] - potential
    R_full = (L - sum(pi * model.qd[k] for pi, k in zip(p, s))).xreplace(eliminate)
    at_rest = {model.qd[k]: 0 for k in r}
    w = p - a.extract(s, [0]).xreplace(at_rest)
    V_eff = tidy_fraction((w.T * M_ss.LUsolve(w))[0] / 2) + potential
    R = tidy_fraction(R_full - R_full.xreplace(at_rest)) - V_eff
    forces = sp.Matrix(d.nonconservative_forces).xreplace(absent).xreplace(eliminate)
    if d.constraints:      # the multipliers' generalized forces sum_j lambda_j a_jr stay
        forces += sp.Matrix(d.constraint_matrix).T * sp.Matrix(d.multipliers)
    terms = _reduced_equations(model, R, r, forces)
    return Routhian(cyclic, tuple(p), tuple(model.q[k] for k in r), R, V_eff,
                    tuple(qd_s), tuple(sp.Add(*t) for t in terms), terms)


def _require_absent_from_constraints(d, cyclic) -> None:
    """Refuse (with the constraint that says why) an ignorable coordinate that a constraint row contains."""
    model = d.model
    for row_index, (row, spec) in enumerate(zip(d.constraints, model.constraints)):
        used = [c for c in cyclic if row.expr.has(c) or row.d.has(c) or any(a.has(c) for a in row.a)]
        if used:
            name = used[0].name
            where = f"{spec.loc}: " if spec.loc is not None else f"{model.source}: constraints[{row_index}]: "
            raise UsageError(
                f"{where}Routh reduction over '{name}' is not possible: "
                f"'{name}' is ignorable (p_{name} is conserved) but this constraint contains it, so "
                f"the reduced equations would still depend on '{name}'\n"
                "  hint: Routh reduction needs coordinates that appear in no constraint; "
                f"`lagcli derive` reports the conserved p_{name} and `simulate` its column")


def _reduced_equations(model, R, r, Q) -> tuple[tuple[sp.Expr, ...], ...]:
    """The terms of d/dt(dR/dq'_r) - dR/dq_r - Q'_r for each reduced coordinate, in the
    derive report's order (`lagcli.report.display.ordered_terms`): the q_r'' terms, then
    the velocity monomials by degree, then the rest. R is quadratic in q'_r (the cyclic
    velocities it eliminated are linear in them), so Lagrange's operator on it is linear
    in q_r'' and quadratic in q'_r, and its coefficients are its derivatives at q'_r = 0."""
    from lagcli.model.calculus import TimeDerivative
    from lagcli.report.display import ordered_terms, split

    qd_r, qdd_r = [model.qd[k] for k in r], [model.qdd[k] for k in r]
    D = TimeDerivative(model.t, [model.q[k] for k in r], qd_r, qdd_r)
    moving = {model.t, *model.q, *model.qd}

    def tidy(expr):
        return tidy_split(expr, moving)

    out = []
    for k in r:
        lagrange = D(R.diff(model.qd[k])) - R.diff(model.q[k])
        accelerations = [pull_signs(tidy(lagrange.diff(a)) * a) for a in qdd_r]
        buckets = _velocity_coefficients(lagrange.xreplace({a: 0 for a in qdd_r}), qd_r)
        for term in split(display_form(Q[k])):
            coefficient, monomial = term.as_independent(*qd_r, as_Add=False)
            buckets[monomial] = buckets.get(monomial, sp.S.Zero) - coefficient
        out.append(tuple(a for a in accelerations if a != 0)
                   + tuple(ordered_terms(buckets, qd_r, tidy)))
    return tuple(out)


def _velocity_coefficients(expr, qd) -> dict:
    """{1, q'_j, q'_j q'_l: coefficient} of expr, a polynomial of degree <= 2 in qd."""
    rest = {v: 0 for v in qd}
    buckets = {sp.S.One: expr.xreplace(rest)}
    for j, v in enumerate(qd):
        slope = expr.diff(v)
        buckets[v] = slope.xreplace(rest)
        for w in qd[j:]:
            curvature = slope.diff(w).xreplace(rest)
            buckets[v * w] = curvature / 2 if w == v else curvature
    return buckets


@dataclass(frozen=True)
class SteadyMotion:
    coordinates: dict                 # reduced coordinate -> value
    cyclic_rates: dict                # cyclic velocity name -> value
    eigenvalues: np.ndarray           # of the reduced linearization
    frequencies: tuple[float, ...]    # small-oscillation frequencies (rad/s): of oscillations only, no spiral


def steady_motions(d, routh: Routhian, momenta: dict, parameters: dict, guesses) -> list[SteadyMotion]:
    """Stationary points of V_eff at the given momenta, each with its small oscillations."""
    from lagcli.analysis.equilibria import solve_stationary
    from lagcli.analysis.stability import modes_of, sorted_eigenvalues

    model = d.model
    if d.constraints:
        raise UsageError(f"{model.source}: steady motions of a constrained reduced system are not "
                         "computed (its V_eff is stationary only together with the multipliers)\n"
                         "  hint: `lagcli routh` without --momentum prints the reduced equations; "
                         "`lagcli linearize --at ...` analyses a steady motion you know")
    values = {p.symbol: parameters[p.symbol.name] for p in (*model.parameters, *model.inputs)}
    values.update({p: momenta[p.name] for p in routh.momenta})
    values[model.t] = 0.0
    q_r = list(routh.reduced)
    gradient = [routh.effective_potential.diff(q) for q in q_r]
    starts = [[g.get(q.name, 0.0) for q in q_r] for g in guesses]
    out = []
    for found in solve_stationary(gradient, q_r, values, starts):
        here = {**values, **dict(zip(q_r, found.values))}
        A = _reduced_linear(model, routh, here)
        eig = sorted_eigenvalues(A)
        rates = {model.qd[model.q.index(c)].name: _number(e, here, model, q_r) for c, e in
                 zip(routh.cyclic, routh.cyclic_velocities)}
        out.append(SteadyMotion(dict(zip((q.name for q in q_r), found.values)), rates, eig,
                                tuple(sorted({float(abs(m.eigenvalue)) for m in modes_of(eig)
                                              if m.kind == "oscillation" and m.eigenvalue.imag > 0}))))
    return out


def _number(expr, here, model, q_r) -> float:
    rest = {model.qd[model.q.index(q)]: 0 for q in q_r}
    return float(sp.sympify(expr).xreplace(rest).xreplace({k: sp.Float(v, 30) for k, v in here.items()}).evalf(30))


def _reduced_linear(model, routh: Routhian, here: dict) -> np.ndarray:
    """A of x = (q_r, q'_r) for M_red q'' + G q' + K q = 0 at the steady motion."""
    q_r = list(routh.reduced)
    qd_r = [model.qd[model.q.index(q)] for q in q_r]
    rest = {v: 0 for v in qd_r}
    R = routh.R
    numbers = {k: sp.Float(v, 30) for k, v in here.items()}

    def num(matrix) -> np.ndarray:
        return np.array(sp.Matrix(matrix).xreplace(rest).xreplace(numbers).evalf(30), dtype=float)

    M_red = num(sp.hessian(R, qd_r))
    K = num(sp.hessian(routh.effective_potential, q_r))
    b = sp.Matrix([R.diff(v) for v in qd_r]).xreplace(rest)       # R1 = b . q'_r
    G = num(sp.Matrix(len(q_r), len(q_r), lambda i, j: b[i].diff(q_r[j]) - b[j].diff(q_r[i])))
    n = len(q_r)
    # Lagrange's operator on R1 = b . q'_r gives sum_j G_ij q'_j: M q'' + G q' + K q = 0 (Q'_r left out)
    return np.block([[np.zeros((n, n)), np.eye(n)],
                     [-np.linalg.solve(M_red, K), -np.linalg.solve(M_red, G)]])
