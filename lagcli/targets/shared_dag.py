"""The CSE of a big system: one pass over the distinct subexpressions, no sympy arithmetic.

sympy's `cse` (lagcli/targets/cse.py) rebuilds every subexpression through sympy's
constructors several times (the 'basic' preprocessing, `opt_cse`'s sign and sub-sum
searches, `tree_cse`'s canonical sort), which cost ~12 s of CPU for the 40-link chain,
growing faster than its code. Above a size budget (`cse.LINEAR_CSE_MIN_NODES`, counted in
distinct subexpressions: no bundled spec reaches it) the outputs go through this module
instead:

    Dag.add_expr      each distinct sympy subexpression becomes one node of a hash-consed
                      graph of plain tuples: ("atom", expr), ("add", terms),
                      ("mul", coefficient, ((base, integer exponent), ...)),
                      ("call", func, args); terms and factors sorted by node id
    _sum              like terms merged, then the common factors of the terms pulled out
                      (content and shared powers, as `tidy.factored` does: a weighted sum
                      m1*X + ... + mn*X becomes X*(m1 + ... + mn)), then the terms that
                      are a weight times a product other terms share grouped (`_grouped`)
    nest_sums         a sum that is another sum plus one term becomes that sum plus the term
    reduce_dag        a node with two or more parents (or an output that is also a part)
                      becomes a temporary; the rest is rebuilt in place with sympy's
                      unevaluated constructors (`_from_args`), children in node order

Node ids are given in the order of a walk of the outputs in their order along sympy's
`args` (a deterministic order: sympy sorts the arguments of a sum or product by
`Basic.compare`), so the code is the same in every process. The printer is told to keep
that order (`Reduced.ordered` False: no `as_ordered_terms` sort while printing).
"""
from __future__ import annotations

import sympy as sp

from lagcli.render.tidy import common_exponent, numeric_content

ONE = sp.S.One


class Dag:
    """A hash-consed graph of the outputs (see the module docstring)."""

    def __init__(self):
        self.nodes: list[tuple] = []
        self._ids: dict = {}
        self._converted: dict = {}
        self._plain: list[bool] = []      # per node: neither a product nor a number (`product` keeps it whole)

    def add_expr(self, expr) -> int:
        """The node of a sympy expression, each distinct subexpression converted once."""
        found = self._converted.get(expr)
        if found is None:
            found = self._converted[expr] = self._convert(expr)
        return found

    def _convert(self, expr) -> int:
        if not expr.args:
            return self.atom(expr)
        if expr.is_Add:
            return self._sum([self.add_expr(a) for a in expr.args])
        if expr.is_Mul:
            coefficient, factors, add_expr = ONE, [], self.add_expr
            for arg in expr.args:
                if arg.is_Number:
                    coefficient = _times(coefficient, arg)
                elif arg.is_Pow and arg.exp.is_Integer:
                    factors.append((add_expr(arg.base), int(arg.exp)))
                else:
                    factors.append((add_expr(arg), 1))
            return self.product(coefficient, factors)
        if expr.is_Pow and expr.exp.is_Integer:
            return self.product(ONE, [self._power(expr)])
        return self._node(("call", expr.func, tuple(self.add_expr(a) for a in expr.args)))

    def _power(self, expr) -> tuple[int, int]:
        if expr.is_Pow and expr.exp.is_Integer:
            return self.add_expr(expr.base), int(expr.exp)
        return self.add_expr(expr), 1

    def _node(self, key: tuple) -> int:
        found = self._ids.get(key)
        if found is None:
            found = self._ids[key] = len(self.nodes)
            self.nodes.append(key)
            self._plain.append(key[0] != "mul" and not (key[0] == "atom" and key[1].is_Number))
        return found

    def atom(self, expr) -> int:
        return self._node(("atom", expr))

    def product(self, coefficient, factors) -> int:
        """coefficient * prod(base**exponent) (a sympy number, integer exponents), nested
        products flattened, equal bases merged."""
        if coefficient is ONE and len(factors) == 1 and factors[0][1] == 1:
            return factors[0][0]
        nodes, plain = self.nodes, self._plain
        powers: dict = {}
        for base, exponent in factors:
            if plain[base]:
                powers[base] = powers.get(base, 0) + exponent
                continue
            node = nodes[base]
            kind = node[0]
            if kind == "mul" and (exponent == 1 or node[1] is ONE):
                if exponent == 1:
                    coefficient = _times(coefficient, node[1])
                    for inner, e in node[2]:
                        powers[inner] = powers.get(inner, 0) + e
                else:
                    for inner, e in node[2]:
                        powers[inner] = powers.get(inner, 0) + e * exponent
            elif kind == "atom" and node[1].is_Number:
                coefficient = _times(coefficient, node[1] ** exponent)
            else:
                powers[base] = powers.get(base, 0) + exponent
        if 0 in powers.values():
            powers = {b: e for b, e in powers.items() if e}
        if not powers or not coefficient:
            return self.atom(coefficient)
        if coefficient is ONE and len(powers) == 1:
            (base, exponent), = powers.items()
            if exponent == 1:
                return base
        return self._node(("mul", coefficient, tuple(sorted(powers.items()))))

    def split(self, term: int) -> tuple:
        """(numeric coefficient, ((base, exponent), ...) sorted) of a term."""
        node = self.nodes[term]
        if node[0] == "mul":
            return node[1], node[2]
        if node[0] == "atom" and node[1].is_Number:
            return node[1], ()
        return ONE, ((term, 1),)

    def _sum(self, terms) -> int:
        """The sum of the terms: like terms merged, common factors pulled out (`_factored`).
        A term is worked on as [number, ((base, exponent), ...) sorted, its node or None
        once changed]."""
        nodes, split = self.nodes, self.split
        merged: dict = {}
        for term in terms:
            node = nodes[term]
            for t in node[1] if node[0] == "add" else (term,):
                number, key = split(t)
                found = merged.get(key)
                if found is None:
                    merged[key] = [number, key, t]
                else:
                    found[0], found[2] = found[0] + number, None
        kept = [term for term in merged.values() if term[0]]
        if not kept:
            return self.atom(sp.S.Zero)
        if len(kept) == 1:
            return self._term(kept[0])
        return self._factored(kept)

    def _term(self, term) -> int:
        number, powers, node = term
        return node if node is not None else self.product(number, powers)

    def _factored(self, split) -> int:
        common = dict(split[0][1])
        for _, powers, _ in split[1:]:
            if not common:
                break
            powers = dict(powers)
            common = {b: common_exponent(e, powers[b]) for b, e in common.items() if b in powers}
            common = {b: e for b, e in common.items() if e != 0}
        numbers = [number for number, _, _ in split]
        content = ONE if all(number is ONE for number in numbers) else numeric_content(numbers)
        if common:                 # exponents 0 stay: they count in `_grouped`
            split = [(number if content is ONE else number / content,
                      tuple([(b, e - common.get(b, 0)) for b, e in powers]), None) for number, powers, _ in split]
        elif content is not ONE:
            split = [(number / content, powers, None) for number, powers, _ in split]
        terms = self._grouped(split)
        inner = terms[0] if len(terms) == 1 else self._node(("add", tuple(sorted(terms))))
        if content is ONE and not common:
            return inner
        return self.product(content, [*common.items(), (inner, 1)])

    def _grouped(self, split) -> list[int]:
        """The terms of a sum, those that are one factor (the weight) times a product
        several terms share written as that product times the sum of their weights
        (g*l1*m1*sin(q1) + g*l1*m2*sin(q1) -> g*l1*sin(q1)*(m1 + m2)); each term
        joins the product most terms share."""
        if all(len(powers) < 2 for _, powers, _ in split):
            return [self._term(term) for term in split]
        keys = [_products_less_one(powers) if len(powers) > 1 else () for _, powers, _ in split]
        counts: dict = {}
        for options in keys:
            for key, _ in options:
                counts[key] = counts.get(key, 0) + 1
        groups: dict = {}
        for k, (term, options) in enumerate(zip(split, keys)):
            best = _most_shared(options, counts)
            key = best[0] if best is not None and counts[best[0]] > 1 else k
            groups.setdefault(key, []).append((term, best))
        terms = []
        for key, members in groups.items():
            if len(members) == 1:
                terms.append(self._term(members[0][0]))
            else:
                weights = self._sum([self.product(term[0], [(best[1], 1)]) for term, best in members])
                terms.append(self.product(ONE, [*key, (weights, 1)]))
        return terms

    def children(self, node_id: int) -> tuple:
        node = self.nodes[node_id]
        if node[0] == "add":
            return node[1]
        if node[0] == "mul":
            return tuple(b for b, _ in node[2])
        if node[0] == "call":
            return node[2]
        return ()


def _products_less_one(powers: tuple) -> list:
    """(the other factors, the factor) for each factor of exponent 1 of a term, whose
    ((base, exponent), ...) `powers` are sorted by base."""
    return [(powers[:i] + powers[i + 1:], b) for i, (b, e) in enumerate(powers) if e == 1]


def _most_shared(options, counts: dict):
    """The option (product, factor) whose product most terms share, the larger factor on a
    tie (factors differ: no two options tie); None when there is none."""
    best, best_key = None, None
    for option in options:
        key = (counts[option[0]], option[1])
        if best_key is None or key > best_key:
            best, best_key = option, key
    return best


def _times(a, b):
    """a * b of sympy numbers, without sympy's arithmetic when one is 1."""
    return b if a is ONE else a if b is ONE else a * b


def reduce_dag(dag: Dag, outputs: list[int], symbols) -> tuple[list, list]:
    """(temporaries [(symbol, value)], reduced outputs): a node used twice or more (an
    output counts as a use) becomes a temporary, unless it is a number times one factor."""
    nest_sums(dag, _uses(dag, outputs))
    uses = _uses(dag, outputs)
    built: dict = {}
    temporaries: list = []

    def build(node_id):
        done = built.get(node_id)
        if done is not None:
            return done
        stack = [(node_id, False)]
        while stack:
            current, ready = stack.pop()
            if current in built:
                continue
            if not ready:
                stack.append((current, True))
                stack.extend((c, False) for c in reversed(dag.children(current)) if c not in built)
                continue
            value = _rebuilt(dag.nodes[current], built)
            if uses.get(current, 0) > 1 and not _inline(dag.nodes[current]):
                symbol = next(symbols)
                temporaries.append((symbol, value))
                value = symbol
            built[current] = value
        return built[node_id]

    reduced = [build(o) for o in outputs]
    return temporaries, reduced


MASK = (1 << 64) - 1


def _mixed(node_id: int) -> int:
    """A deterministic 64-bit scramble of a node id: sets of terms are hashed by the XOR
    of their terms' scrambles, so a sum less one term is found in one look-up."""
    return ((node_id + 1) * 0x9E3779B97F4A7C15 >> 7) & MASK


def nest_sums(dag: Dag, nodes) -> None:
    """Each sum of `nodes` that is another sum of them plus one term is rewritten as that
    sum plus the term (x3 = x2 + m38, x4 = x3 + m37, ...: the n tails of the chain's
    masses cost n additions instead of n**2/2). Rewrites the graph in place: no node may be
    added to it afterwards."""
    sums = sorted((len(dag.nodes[i][1]), i) for i in nodes if dag.nodes[i][0] == "add")
    by_hash: dict = {}
    for _, i in sums:
        terms = frozenset(dag.nodes[i][1])
        whole = 0
        for t in terms:
            whole ^= _mixed(t)
        for t in sorted(terms) if len(terms) > 2 else ():
            j, inside = by_hash.get(whole ^ _mixed(t), (None, None))
            if j is not None and inside == terms - {t}:
                dag.nodes[i] = ("add", (j, t))
                break
        by_hash.setdefault(whole, (i, terms))


def _uses(dag: Dag, outputs) -> dict:
    uses: dict = {}
    stack = []
    for output in outputs:
        uses[output] = uses.get(output, 0) + 1
        if uses[output] == 1:
            stack.append(output)
    while stack:
        for child in dag.children(stack.pop()):
            uses[child] = uses.get(child, 0) + 1
            if uses[child] == 1:
                stack.append(child)
    return uses


def _inline(node) -> bool:
    """Atoms and a number times one factor are written where they are used."""
    return node[0] == "atom" or (node[0] == "mul" and len(node[2]) == 1 and node[2][0][1] == 1)


def _rebuilt(node, built):
    kind = node[0]
    if kind == "atom":
        return node[1]
    if kind == "add":
        return sp.Add._from_args([built[t] for t in node[1]])
    if kind == "call":
        return node[1](*(built[a] for a in node[2]))
    coefficient, powers = node[1], node[2]
    factors = [built[b] if e == 1 else sp.Pow(built[b], e) for b, e in powers]
    if coefficient is not ONE:
        factors.insert(0, coefficient)
    return sp.Mul._from_args(factors) if len(factors) > 1 else factors[0]
