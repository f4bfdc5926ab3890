"""The report's derivatives of its tidied parts: d M_ij / d q_k for the velocity terms,
dV/dq_i for the forces, da_i/dq_j for the gyroscopic matrix (`Display.differentiate`
takes each once).

They are the derivation's derivatives (`lagcli.model.calculus.derivative`, taken almost
everywhere as the derivation takes them), with one shortcut for the mass matrix's
entries: a product in which one factor varies (`one_factor_derivative`).
"""
from __future__ import annotations

import sympy as sp

from lagcli.model import calculus
from lagcli.model.calculus import almost_everywhere
from lagcli.model.products import product


def derivative(expr: sp.Expr, var, memo: dict) -> sp.Expr:
    """d expr/d var, taken almost everywhere as the derivation does (no Heaviside, DiracDelta);
    `memo`: free symbols of the subexpressions seen (`lagcli.model.calculus.free_symbols`)."""
    found = one_factor_derivative(expr, var, memo)
    return almost_everywhere(calculus.derivative(expr, var, memo) if found is None else found)


def one_factor_derivative(expr, var, memo: dict) -> sp.Expr | None:
    """`calculus.derivative` of a product in which one factor f varies (l3 l6 (m6 + ... + m40)
    cos(q3 - q6), an entry of a chain's M): the other factors times f', one product of them
    all, where calculus.derivative forms it factor by factor (each product sorting the sum
    of masses again). The same expression when no factor is a rational number and f' is
    not one (a rational times a sum would be distributed in the factor-by-factor product);
    None otherwise. tests/test_report_shared_terms.py compares both."""
    if not expr.is_Mul or any(a.is_Rational for a in expr.args):
        return None
    moving = [k for k, a in enumerate(expr.args) if var in calculus.free_symbols(a, memo)]
    if len(moving) != 1:
        return None
    k = moving[0]
    rate = calculus.derivative(expr.args[k], var, memo)
    if rate.is_Rational:
        return None
    return product(*expr.args[:k], rate, *expr.args[k + 1:])
