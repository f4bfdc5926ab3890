"""Big expressions shown with named intermediate quantities (text and LaTeX reports).

A hand derivation of a large system does not print thousands of terms: it names
the recurring sums once ("where X1 = ...") and writes the equations with the
names. `Namer` does that for the reports. A report whose expressions all have at
most SHOW_MAX_NODES tree nodes has no names. From its first expression over that
budget on, the report is a big one: every expression over BIG_SHOW_MAX_NODES is shown
with each sum inside it of more than NAME_MIN_NODES nodes replaced by a name X1, X2, ...
(for a sum given as terms, T or an equation, the size of the whole sum decides). So
the small sums that recur all over a big system (the bicycle's direction cosines
sin(delta) sin(phi) - sin(lambda + theta_B) cos(delta) cos(phi), ...) are written once,
and so are the entries of M, F and the constraints made from them. The same sum gets
the same name wherever it occurs (in M, F, the constraints, T...), so each is defined
once; definitions use earlier names (children are named before their parents). The
budgets count tree nodes and the report's order of expressions is fixed, so the same
spec always gives the same names. The JSON report never uses names: its expressions
are complete and parse back.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.products import product
from lagcli.model.sums import total
from lagcli.render.tidy import small

SHOW_MAX_NODES = 400       # a report with an expression bigger than this is a big one
BIG_SHOW_MAX_NODES = 80    # in a big report, an expression bigger than this is shown with names
NAME_MIN_NODES = 12        # the sums inside it bigger than this get a name


class Namer:
    """Replaces the big sums of big expressions by names, remembering the definitions."""

    def __init__(self, taken_names, prefix: str = "X"):
        taken = set(taken_names)
        while any(name.startswith(prefix) and name[len(prefix):].isdigit() for name in taken):
            prefix += prefix[-1]
        self.prefix = prefix
        self.definitions: list[tuple[sp.Symbol, sp.Expr]] = []
        self._shown: dict = {}
        self._budget = SHOW_MAX_NODES      # BIG_SHOW_MAX_NODES once an expression exceeded it

    def _small(self, expr) -> bool:
        if small(expr, self._budget):
            return True
        self._budget = BIG_SHOW_MAX_NODES
        return small(expr, self._budget)

    def __call__(self, expr: sp.Expr) -> sp.Expr:
        """expr as shown: itself when small, else with its big sums named."""
        expr = sp.sympify(expr)
        if self._small(expr):
            return expr
        return self._rebuilt(expr)

    def terms(self, terms) -> list:
        """A sum given as terms (T, L, h, an equation) as shown: when the whole sum is big,
        the big sums inside every term are named, however small the term itself."""
        terms = [sp.sympify(term) for term in terms]
        if self._small(total(terms)):       # sympy's Add, summed faster (sums.total)
            return terms
        return [self._rebuilt(term) for term in terms]

    def _rebuilt(self, expr: sp.Expr) -> sp.Expr:
        if expr.is_Atom or small(expr, NAME_MIN_NODES):
            return expr
        if expr not in self._shown:
            args = [self._named(a) for a in expr.args]
            self._shown[expr] = product(*args) if expr.is_Mul else expr.func(*args)   # product: sympy's Mul, faster
        return self._shown[expr]

    def _named(self, expr: sp.Expr) -> sp.Expr:
        """A big sum inside a big expression: its name (defined on first use)."""
        rebuilt = self._rebuilt(expr)
        if not expr.is_Add or small(expr, NAME_MIN_NODES):
            return rebuilt
        key = ("name", expr)
        if key not in self._shown:
            symbol = sp.Symbol(f"{self.prefix}{len(self.definitions) + 1}", real=True)
            self.definitions.append((symbol, rebuilt))
            self._shown[key] = symbol
        return self._shown[key]
