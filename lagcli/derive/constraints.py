"""Constraint rows in velocity form, classification and integrability.

Each constraint is used exactly as written (no normalisation):

    holonomic     phi(q, t) = 0      a_jk = dphi/dq_k,  d_j = dphi/dt
    nonholonomic  a(q,t).q' + d = 0  a_jk = coefficient of q'_k, d_j = the rest

The multiplier of row j is lambda_<j> (1-based) or lambda_<name>.
"""
from __future__ import annotations

import itertools

import sympy as sp

from lagcli.model.calculus import TimeDerivative, almost_everywhere, derivative, numerically_zero
from lagcli.derive.result import ConstraintRow
from lagcli.errors import Loc, Problem, SpecError
from lagcli.interface import multiplier_name
from lagcli.model.model_types import ConstraintSpec, Model


def constraint_rows(model: Model) -> tuple[ConstraintRow, ...]:
    problems, rows = [], []
    for j, spec in enumerate(model.constraints, start=1):
        try:
            rows.append(_row(model, j, spec))
        except SpecError as exc:
            problems.extend(exc.problems)
    if problems:
        raise SpecError(problems)
    return tuple(rows)


def _row(model: Model, j: int, spec: ConstraintSpec) -> ConstraintRow:
    multiplier = sp.Symbol(multiplier_name(j, spec.label), real=True)
    expr, qd = spec.expr, model.qd
    memo: dict = {}
    if not expr.free_symbols & set(qd):
        a = tuple(almost_everywhere(derivative(expr, qk, memo)) for qk in model.q)
        return ConstraintRow(spec.label, multiplier, "holonomic", expr, a,
                             almost_everywhere(derivative(expr, model.t, memo)), None, spec.loc)
    a = tuple(almost_everywhere(derivative(expr, v, memo)) for v in qd)
    rest = {v: 0 for v in qd}
    d = expr.xreplace(rest)
    _require_linear(expr, a, qd, spec.loc or Loc(model.source, path=f"constraints[{j - 1}]"))
    a = tuple(ak.xreplace(rest) for ak in a)  # drop velocity terms that cancel
    integrable = is_integrable(model, a, d)
    return ConstraintRow(spec.label, multiplier, "nonholonomic", expr, a, d, integrable, spec.loc)


NON_SMOOTH = (sp.sign, sp.Abs, sp.Min, sp.Max, sp.Heaviside, sp.DiracDelta)


def _require_linear(expr: sp.Expr, a, qd, loc: Loc) -> None:
    """Linear in q' means every coefficient a_k is free of velocities (up to cancellation,
    checked numerically) and no non-smooth function of a velocity hides a kink."""
    velocities = set(qd)
    tangled = [ak for ak in a if ak.free_symbols & velocities]
    non_smooth = any(f.free_symbols & velocities for f in expr.atoms(*NON_SMOOTH))
    if non_smooth or not numerically_zero([ak.diff(v) for ak in tangled for v in qd]):
        raise SpecError(Problem(loc, f"velocity constraint {sp.sstr(expr)!r} is not linear in the "
                                "velocities", "a kinematic constraint must have the Pfaffian form "
                                "a_1(q,t) q1_dot + ... + a_n(q,t) qn_dot + d(q,t) = 0"))


def is_integrable(model: Model, a, d) -> bool:
    """Frobenius test for one Pfaffian form w = sum a_k dq_k + d dt (t as a coordinate):
    w is integrable (holonomic in disguise, up to an integrating factor) iff
    w ^ dw = 0, i.e. for every triple i < j < k of (q..., t):
        a_i (d_j a_k - d_k a_j) + a_j (d_k a_i - d_i a_k) + a_k (d_i a_j - d_j a_i) = 0.
    With only two variables every form is integrable."""
    coords = list(model.q) + [model.t]
    coeff = list(a) + [d]
    memo, partials = {}, {}

    def D(k, j):     # d coeff_k / d coords_j, each formed once
        if (k, j) not in partials:
            partials[k, j] = derivative(coeff[k], coords[j], memo)
        return partials[k, j]

    triples = []
    for i, j, k in itertools.combinations(range(len(coords)), 3):
        ai, aj, ak = coeff[i], coeff[j], coeff[k]
        triples.append(ai * (D(k, j) - D(j, k)) + aj * (D(i, k) - D(k, i)) + ak * (D(j, i) - D(i, j)))
    return numerically_zero(triples)


def constraint_matrix(model: Model, rows) -> sp.ImmutableMatrix:
    return sp.ImmutableMatrix(len(rows), len(model.q), [e for r in rows for e in r.a])


def constraint_bias(model: Model, rows, D: TimeDerivative) -> sp.ImmutableMatrix:
    """-(A' q' + d') for each row: the time derivative of a.q' + d with q'' set to 0."""
    bias = []
    for row in rows:
        velocity_form = sum((ak * v for ak, v in zip(row.a, model.qd)), row.d)
        bias.append(almost_everywhere(-D(velocity_form, accelerations=False)))
    return sp.ImmutableMatrix(len(rows), 1, bias)
