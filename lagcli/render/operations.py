"""`count_ops`: sympy's `count_ops(expr)` (visual=False), the same number, faster.

The tidying steps compare operation counts of candidate forms of every expression they
touch, and sympy's `count_ops` builds a symbolic sum of operation names and splits
every product into numerator and denominator (`fraction`) to get there: a third of a
40-link chain's report. This walk follows sympy's rules node by node for what
mechanical systems are made of (sums, products with an integer or float coefficient,
positive integer powers, sin/cos and the other plain functions) and hands any other
node (a division, exp, Min, Piecewise...) to sympy itself: sympy's count is a sum over
the nodes it visits, so a subtree it counts alone contributes what it contributes
inside the whole (tests/test_fast_sympy_rules.py compares both on every bundled spec).
"""
from __future__ import annotations

import sympy as sp

PLAIN_FUNCTIONS = (sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.sinh, sp.cosh, sp.tanh,
                   sp.log, sp.Abs, sp.sign)


def count_ops(expr) -> int:
    """The number of operations in expr, as `sympy.count_ops(expr)` counts them."""
    expr = sp.sympify(expr)
    total, stack = 0, [expr]
    while stack:
        node = stack.pop()
        if node.is_Symbol:
            continue
        if isinstance(node, _Product):
            total += _count_product(node.number, node.factors, stack)
        elif node.is_Rational:
            total += (node.p < 0) + (node.q != 1)
        elif node.is_Add:
            total += _count_add(node, stack)
        elif node.is_Mul and _plain_product(node):
            total += _count_product(*_coefficient_and_factors(node), stack)
        elif node.is_Mul and len(node.args) == 2 and node.args[0] is sp.S.NegativeOne and node.args[1].is_Add:
            total += 1      # -(x + y) unevaluated: sympy counts its NEG, then each term alone (no ADD)
            stack.extend(node.args[1].args)
        elif node.is_Pow and node.exp.is_Integer and node.exp > 0 and node.base is not sp.E:
            total += 1                         # the power; its positive integer exponent counts 0
            stack.append(node.base)
        elif isinstance(node, PLAIN_FUNCTIONS):
            total += 1
            stack.extend(node.args)
        else:
            total += int(sp.count_ops(node))
    return total


def _count_add(add, stack) -> int:
    """n - 1 additions or subtractions, and a negation when every term is negative; each
    negative term is counted as its negation (sympy counts -x*y as the SUB before it)."""
    negative = 0
    for term in add.args:
        number, rest = _coefficient_and_factors(term) if term.is_Mul else (None, None)
        if term.is_Number and term.is_extended_negative:
            negative += 1
            stack.append(-term)
        elif number is not None and number.is_extended_negative:
            negative += 1
            if _plain_product(term):
                stack.append(_Product(-number, rest))
            else:
                stack.append(-term)
        else:
            stack.append(term)
    return len(add.args) - 1 + (negative == len(add.args))


class _Product:
    """A product `number * factors` not built (the negation of a sum's term), counted as
    sympy counts the Mul it stands for."""
    is_Symbol = is_Rational = is_Add = is_Mul = is_Pow = False

    def __init__(self, number, factors):
        self.number, self.factors = number, factors


def _coefficient_and_factors(mul):
    args = mul.args
    return (args[0], args[1:]) if args[0].is_Number else (sp.S.One, args)


def _plain_product(mul) -> bool:
    """A product sympy's `fraction` leaves whole: a float or integer coefficient and factors
    that are symbols, sums, plain function calls or positive integer powers."""
    number, factors = _coefficient_and_factors(mul)
    if not (number.is_Integer or number.is_Float):
        return False
    if number == -1 and len(factors) == 1:
        return False       # -(x + y) unevaluated: sympy counts its NEG and not the sum's ADD
    for factor in factors:
        if factor.is_Pow:
            if not (factor.exp.is_Integer and factor.exp > 0):
                return False
        elif not (factor.is_Symbol or factor.is_Add or isinstance(factor, PLAIN_FUNCTIONS)):
            return False
    return True


def _count_product(number, factors, stack) -> int:
    """A negation for a negative coefficient, then len(args) - 1 multiplications of the
    product without it (a single factor is counted as itself)."""
    count = 0
    if number.is_extended_negative:
        count, number = 1, -number
    args = factors if number == 1 else (number, *factors)
    if len(args) == 1:
        stack.append(args[0])
        return count
    stack.extend(args)
    return count + len(args) - 1
