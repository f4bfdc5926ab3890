"""ONE `sympy.cse` over every group of expressions (`eliminate`), so a temporary is
shared by every function that needs it; each function then computes only the
temporaries its outputs depend on (`Reduced.block`).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp
from sympy.simplify.cse_opts import sub_post

from lagcli.targets.expressions import Outputs
from lagcli.targets.minus_sign import could_extract_minus_sign
from lagcli.targets.shared_dag import Dag, reduce_dag
from lagcli.model.calculus import distinct_nodes
from lagcli.render.operations import count_ops
from lagcli.render.tidy import factored


def basic_optimizations() -> list:
    """sympy.cse's 'basic' optimizations (signs normalised, common factors pulled out
    first: fewer operations for N = 2 and 8 links, docs/codegen.md) with `tidy.factored`,
    linear in the distinct subexpressions, in place of sympy's factor_terms, which took
    30 s of CPU on a bicycle-sized system (1.5 s with factored)."""
    memo: dict = {}          # shared by all expressions: they share subexpressions
    if len(_EXTRACTS) > _EXTRACTS_KEPT:
        _EXTRACTS.clear()
    return [(signs_normalised(_EXTRACTS), sub_post), (lambda expr: factored(expr, memo), None)]


# sum -> could_extract_minus_sign(sum), for every CSE of a run: the model's functions (the
# tidied and the derived candidates) and the variational ones share M's and F's sums
_EXTRACTS: dict = {}
_EXTRACTS_KEPT = 1 << 17


def signs_normalised(memo: dict):
    """sympy's `cse_opts.sub_pre` (y - x -> -(x - y) where a minus sign can be pulled
    out), giving the same expressions, with its per-sum test remembered across
    expressions in `memo` and without its sort of the sums (it only orders a dict,
    which `xreplace` reads by key): the test and the sort were 80% of `generate` of
    the 20-link chain (bench/README.md). Its `atoms` and `xreplace` visit each distinct
    subexpression once (`sums`, `xreplaced`): a big system's trees share subtrees, which
    sympy's walk once per occurrence (a third of `generate` of the 40-link chain); a
    tie of signs is broken by the sum's leading term (`minus_sign`), not by the sort
    keys of the whole sum. Each distinct expression is normalised once (`done`: the
    variational functions repeat M's mirrored entries), each sum negated once."""
    negations: dict = {}
    done: dict = {}

    def extracts(add) -> bool:
        if add not in memo:
            memo[add] = could_extract_minus_sign(add)
        return memo[add]

    def negation(add):
        if add not in negations:
            negations[add] = -add
        return negations[add]

    def normalise(expr):
        if expr not in done:
            done[expr] = normalised(expr)
        return done[expr]

    def normalised(expr):
        reps, ignore = {}, set()
        for add in sums(expr):
            if not extracts(add):
                continue
            negated = negation(add)
            if negated.is_Mul:
                ignore.add(add)
            else:
                reps[add] = sp.Mul._from_args([sp.S.NegativeOne, negated])
        if not reps:          # nothing replaced: the second pass below finds nothing to mark
            return expr
        expr = xreplaced(expr, reps)
        if not isinstance(expr, sp.Basic):
            return expr
        negs = {}
        for add in sums(expr):          # sums still there: mark them 1*-1*(x - y)
            if add in ignore:
                continue
            if add in reps:
                negs[add] = reps[add]
            elif extracts(add):
                negs[add] = sp.Mul._from_args([sp.S.One, sp.S.NegativeOne, negation(add)])
        return xreplaced(expr, negs)

    return normalise


def sums(expr) -> set:
    """`expr.atoms(sp.Add)`, each distinct subexpression visited once."""
    return {node for node in distinct_nodes(expr) if isinstance(node, sp.Add)}


def xreplaced(expr, rule: dict):
    """`expr.xreplace(rule)`, each distinct subexpression rebuilt once (sympy's
    `Basic._xreplace` with a memo: a node is rebuilt, `func(*args)`, when a replacement
    happened below it, as there)."""
    memo: dict = {}

    def walk(node):
        if node in rule:
            return rule[node], True
        if not rule or not node.args:
            return node, False
        done = memo.get(node)
        if done is None:
            args, changed = [], False
            for arg in node.args:
                new, below = walk(arg) if isinstance(arg, sp.Basic) else (arg, False)
                args.append(new)
                changed |= below
            done = memo[node] = (node.func(*args), True) if changed else (node, False)
        return done

    return walk(expr)[0] if isinstance(expr, sp.Basic) else expr.xreplace(rule)


CSE_OPTIMIZATIONS = "basic"   # `basic_optimizations`; None: no preprocessing
LINEAR_CSE_MIN_NODES = 4000   # distinct subexpressions from which `linear_cse` replaces sympy.cse


@dataclass(frozen=True)
class Reduced:
    """The result of one CSE over all groups: temporaries in dependency order and the
    reduced expressions of every group."""

    temporaries: tuple[tuple[sp.Symbol, sp.Expr], ...]
    groups: dict
    ordered: bool = True      # False: print sums and products in the order they have (`linear_cse`)

    def block(self, names, exclude=frozenset()) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """The temporaries (in order) that the groups `names` need, minus `exclude`."""
        needed = set()
        for name in names:
            for expr in self.groups[name]:
                needed |= self.free_symbols(expr)
        chosen = []
        for symbol, value in reversed(self.temporaries):
            if symbol in needed:
                chosen.append((symbol, value))
                needed |= self.free_symbols(value)
        return tuple(pair for pair in reversed(chosen) if pair[0] not in exclude)

    def free_symbols(self, expr) -> frozenset:
        """`expr.free_symbols` of a temporary's value or an output, each found once (every
        function body asks again: a tenth of `generate` of the 40-link chain)."""
        found = self._free.get(expr)
        if found is None:
            found = self._free[expr] = frozenset(sp.sympify(expr).free_symbols)
        return found

    @cached_property
    def _free(self) -> dict:
        return {}

    def operation_count(self, names) -> int:
        """Operations (sympy.count_ops, the same number by `operations.count_ops`) to evaluate
        the groups `names`, temporaries included."""
        temps = self.block(names)
        exprs = [value for _, value in temps] + [e for name in names for e in self.groups[name]]
        return sum(count_ops(e) for e in exprs)


def eliminate(outputs: Outputs, optimizations=CSE_OPTIMIZATIONS) -> Reduced:
    """ONE `sympy.cse` over every group of `outputs` (or of any object whose `groups()`
    is {name: expressions}, e.g. the Hamiltonian module's, lagcli/targets/hamilton.py);
    `optimizations`: "basic" (`basic_optimizations`), None or a list for sympy.cse."""
    groups = outputs.groups()
    flat = [sp.sympify(e) for name in groups for e in groups[name]]
    symbols = sp.numbered_symbols("x", cls=sp.Dummy)
    linear = optimizations is not None and not few_nodes(flat, LINEAR_CSE_MIN_NODES)
    if linear:
        temporaries, reduced = linear_cse(flat, symbols)
    else:
        if optimizations == "basic":
            optimizations = basic_optimizations()
        temporaries, reduced = sp.cse(flat, symbols=symbols, optimizations=optimizations, order="canonical")
    result, start = {}, 0
    for name in groups:
        size = len(groups[name])
        result[name] = tuple(reduced[start:start + size])
        start += size
    return Reduced(tuple(temporaries), result, ordered=not linear)


def few_nodes(exprs, budget: int) -> bool:
    """True when `exprs` have at most `budget` distinct subexpressions together (stops
    counting past it)."""
    seen, stack = set(), list(exprs)
    while stack:
        node = stack.pop()
        if node not in seen:
            seen.add(node)
            if len(seen) > budget:
                return False
            stack.extend(node.args)
    return True


def linear_cse(exprs, symbols) -> tuple[list, list]:
    """The CSE of a big system (lagcli/targets/shared_dag.py): common factors of sums
    pulled out and every subexpression used twice made a temporary, in one pass over the
    distinct subexpressions; printed in the order it gives (`Reduced.ordered`)."""
    dag = Dag()
    return reduce_dag(dag, [dag.add_expr(e) for e in exprs], symbols)
