"""Small calculus tools shared by the model and the derivation.

Derivations use plain symbols for q, q' and q'' and an explicit total time
derivative, which is much faster than sympy's `Function`/`Derivative` objects:

    D f(t, q, q') = df/dt + sum_k (df/dq_k q'_k + df/dq'_k q''_k)
"""
from __future__ import annotations

import functools
import random
from collections.abc import Iterable, Sequence
from functools import reduce

import sympy as sp
from sympy.core.function import ArgumentIndexError

from lagcli.model.angle_calls import TRIG, trig_call
from lagcli.model.constants import ConstantError, value_at, value_from_arguments
from lagcli.model.products import product
from lagcli.model.sums import total


class TimeDerivative:
    """The total time derivative along the coordinates' motion."""

    def __init__(self, t: sp.Symbol, q: Sequence[sp.Symbol], qd: Sequence[sp.Symbol],
                 qdd: Sequence[sp.Symbol]):
        self.t = t
        self.chain = list(zip(q, qd)) + list(zip(qd, qdd))
        self.position_chain = self.chain[:len(q)]
        self.accelerations = frozenset(qdd)
        self.order = {var: k for k, (var, _) in enumerate(self.chain)}
        self.free: dict = {}      # free symbols of every subexpression seen (see `derivative`)
        self.partials: dict = {}  # (term, variable) -> derivative, for the terms `gradient` meets
        self.rated: dict = {}     # (partial, rate) -> their product: one object for equal terms

    def __call__(self, expr: sp.Expr, accelerations: bool = True) -> sp.Expr:
        """D expr; with `accelerations=False`, D expr at q'' = 0 (the q'' terms are never
        formed, which is much cheaper than substituting 0 for them afterwards)."""
        expr = sp.sympify(expr)
        free = free_symbols(expr, self.free)
        if free & self.accelerations:
            raise ValueError("cannot differentiate an expression containing accelerations")
        last = len(self.chain) if accelerations else len(self.position_chain)
        # the chain's variables that expr mentions, in the chain's order (not all 2n of them),
        # differentiated for in one pass over a sum's terms, summed once (adding term by
        # term rebuilt the growing sum: a chain's positions made both quadratic)
        chain = [self.chain[k] for k in sorted(k for k in map(self.order.get, free) if k is not None and k < last)]
        partials = gradient(expr, [var for var, _ in chain], self.free, self.partials)
        terms = [self._rated(partial, rate) for partial, (_, rate) in zip(partials, chain)]
        return total([derivative(expr, self.t, self.free) if self.t in free else sp.S.Zero, *terms])

    def _rated(self, partial: sp.Expr, rate: sp.Symbol) -> sp.Expr:
        """partial * rate, the same object each time (a chain's velocities share their terms, so
        differentiating them again finds them in the memos at once, not by comparing copies)."""
        key = (partial, rate)
        found = self.rated.get(key)
        if found is None:
            found = self.rated[key] = product(partial, rate)
        return found

    def matrix(self, m: sp.MatrixBase, accelerations: bool = True) -> sp.ImmutableMatrix:
        return sp.ImmutableMatrix(m.shape[0], m.shape[1], [self(e, accelerations) for e in m])


def free_symbols(expr: sp.Basic, memo: dict) -> frozenset:
    """expr.free_symbols, remembered in `memo` for every subexpression (sympy recomputes
    them from the leaves at every call, which made differentiating big trees quadratic)."""
    found = memo.get(expr)
    if found is None:
        if expr.is_Symbol:
            found = frozenset((expr,))
        elif not expr.args or not isinstance(expr, sp.Expr):
            found = frozenset(expr.free_symbols)
        else:
            found = frozenset().union(*(free_symbols(a, memo) for a in expr.args))
        memo[expr] = found
    return found


def derivative(expr: sp.Expr, var: sp.Symbol, memo: dict | None = None,
               partials: dict | None = None) -> sp.Expr:
    """d expr / d var, the same expression as sympy's `expr.diff(var)`, much faster on big
    trees: subtrees free of `var` are skipped without visiting them (`free_symbols`), and
    sums, products, constant powers and smooth functions are differentiated here with
    sympy's own rules (Add, Mul and Pow `_eval_derivative`, Function's chain rule) rather
    than through a `Derivative` object per node. Anything else (Abs, sign, Piecewise, a
    power with a varying exponent...) is left to sympy. `partials`: the derivatives of the
    sums' terms met, (term, var) -> derivative (`gradient`'s): a chain's potential holds
    g m_k (-l_1 cos(q_1) - ... - l_k cos(q_k)) for every k, and the derivative of each
    -l_i cos(q_i) was formed again for each k."""
    memo = {} if memo is None else memo
    if not isinstance(expr, sp.Basic) or var not in free_symbols(expr, memo):   # a plain 0 or number
        return sp.S.Zero
    if expr.is_Symbol:          # one whose free symbols hold var: var itself
        return sp.S.One
    if expr.is_Add:
        return total([_term_derivative(a, var, memo, partials) for a in _terms_mentioning(expr, var, memo)])
    if expr.is_Mul:
        args, terms = list(expr.args), []
        for i, a in enumerate(args):
            d = derivative(a, var, memo, partials)
            if d:
                terms.append(reduce(product, args[:i] + [d] + args[i + 1:]))    # x * y, in turn
        return total(terms)
    if expr.is_Pow and var not in free_symbols(expr.exp, memo):
        base, exponent = expr.args
        return expr * (derivative(base, var, memo, partials) * exponent / base)
    if isinstance(expr, TRIG):     # sympy's fdiff, its new call built directly (`trig_call`)
        arg = expr.args[0]
        rate = trig_call(sp.cos, arg) if isinstance(expr, sp.sin) else -trig_call(sp.sin, arg)
        return product(rate, derivative(arg, var, memo, partials))
    if isinstance(expr, sp.Function) and type(expr)._eval_derivative is sp.Function._eval_derivative:
        terms = []
        for i, a in enumerate(expr.args, start=1):
            d = derivative(a, var, memo, partials)
            if not d.is_zero:
                try:
                    terms.append(expr.fdiff(i) * d)
                except ArgumentIndexError:
                    return expr.diff(var)
        return sp.Add(*terms)
    return expr.diff(var)


def _term_derivative(term: sp.Expr, var: sp.Symbol, memo: dict, partials: dict | None) -> sp.Expr:
    """`derivative(term, var)` of a sum's term, remembered in `partials` when given."""
    if partials is None:
        return derivative(term, var, memo)
    key = (term, var)
    found = partials.get(key)
    if found is None:
        found = partials[key] = derivative(term, var, memo, partials)
    return found


_BIG_SUM = 8     # sums of more terms than this are indexed by symbol (`_terms_mentioning`)
_SUM_INDEXES: dict = {}     # big sum -> {symbol: its terms mentioning the symbol}, oldest first
_MAX_SUM_INDEXES = 1 << 12  # the sums indexed at once (the 100-link chain's V holds 100)


def _terms_mentioning(expr: sp.Add, var: sp.Symbol, memo: dict) -> tuple:
    """The terms of the sum `expr` that mention `var`, in order (the others differentiate to
    0, which `total` drops). A big sum's terms are indexed by symbol once, in a memo of its
    own (the index depends on the sum only): a chain's potential holds
    g m_k (l_1 cos(q_1) + ... + l_k cos(q_k)) for every k, and differentiating it for each
    q_i walked the whole sum each time (n^3)."""
    if len(expr.args) <= _BIG_SUM:
        return expr.args
    index = _SUM_INDEXES.get(expr)
    if index is None:
        if len(_SUM_INDEXES) >= _MAX_SUM_INDEXES:
            del _SUM_INDEXES[next(iter(_SUM_INDEXES))]
        index = _SUM_INDEXES[expr] = {}
        for term in expr.args:
            for symbol in free_symbols(term, memo):
                index.setdefault(symbol, []).append(term)
    return index.get(var, ())


def jacobian(exprs, variables, memo: dict | None = None) -> sp.ImmutableMatrix:
    """d exprs_i / d variables_j (a column of expressions), by `derivative`."""
    memo = {} if memo is None else memo
    exprs = list(exprs)
    return sp.ImmutableMatrix(len(exprs), len(variables),
                              [derivative(e, v, memo) for e in exprs for v in variables])


def gradient(expr: sp.Expr, variables, memo: dict, partials: dict | None = None) -> list[sp.Expr]:
    """[derivative(expr, v) for v in variables], in one pass over a sum's terms: each term
    is differentiated for the variables it mentions only (n coordinates of a sum of n
    uncoupled terms cost n, not n^2). The same expressions as `derivative`'s. `partials`
    remembers each term's derivatives: a chain's positions are sums sharing their terms
    (the k-th point's holds the k - 1 terms of the one before it)."""
    index = {v: k for k, v in enumerate(variables)}
    parts: list[list] = [[] for _ in variables]
    partials = {} if partials is None else partials
    for term in (expr.args if expr.is_Add else (expr,)):
        for v in free_symbols(term, memo):
            place = index.get(v)        # each lookup hashes the expressions anew, in Python
            if place is not None:
                key = (term, v)
                found = partials.get(key)
                if found is None:
                    found = partials[key] = derivative(term, v, memo, partials)
                parts[place].append(found)
    return [total(p) if expr.is_Add else (p[0] if p else sp.S.Zero) for p in parts]


_PLACES: list = []      # (variables, {variable: its place}) of the last few variable tuples


def _places(variables) -> dict:
    """{variable: its index} of a tuple of variables, formed once per tuple (a point that
    moves with one of 1 000 coordinates looked at all 1 000 to find it: n^2 for n points)."""
    for known, places in _PLACES:
        if known is variables:
            return places
    places = {v: j for j, v in enumerate(variables)}
    if isinstance(variables, tuple):        # immutable: its places stay true
        _PLACES[:] = [(variables, places), *_PLACES[:3]]
    return places


def jacobian_columns(exprs, variables, memo: dict,
                     partials: dict | None = None) -> list[tuple[int, tuple[sp.Expr, ...]]]:
    """The nonzero columns of `jacobian(exprs, variables)` as (index, column) pairs, in order:
    only the variables the expressions mention are differentiated for, so a point that
    moves with a few of n coordinates costs what those few do, not n."""
    exprs = [sp.sympify(e) for e in exprs]
    mentioned = frozenset().union(*(free_symbols(e, memo) for e in exprs))
    places = _places(variables)
    used = sorted((places[v], v) for v in mentioned if v in places)
    rows = [gradient(e, [v for _, v in used], memo, partials) for e in exprs]    # one pass over each sum's terms
    columns = []
    for k, (j, _) in enumerate(used):
        column = tuple(row[k] for row in rows)
        if any(column):
            columns.append((j, column))
    return columns


def shared_terms(vector: sp.ImmutableMatrix, seen: dict) -> sp.ImmutableMatrix:
    """`vector` with each term of its sums replaced by the first equal term in `seen` (which
    learns the new ones): a chain's positions repeat the terms of the point before, parsed
    anew, and the derivation's memos (`free`, `partials`) compared equal copies node by node
    (Basic.__eq__) where the same object is found at once. The same expressions."""
    def share(expr):
        if not expr.is_Add:
            return expr
        args = tuple(seen.setdefault(term, term) for term in expr.args)
        same = all(a is b for a, b in zip(args, expr.args))
        return expr if same else sp.Add._from_args(args, expr.is_commutative)
    return sp.ImmutableMatrix(vector.shape[0], vector.shape[1], [share(e) for e in vector])


def depends_on(expr: sp.Expr, symbols: Iterable[sp.Symbol], memo: dict | None = None) -> bool:
    """Structural dependence (cheap; may say True for a dependence that cancels); with a
    `free_symbols` memo, the subexpressions already seen are not walked again."""
    expr = sp.sympify(expr)
    found = expr.free_symbols if memo is None else free_symbols(expr, memo)
    return bool(found & set(symbols))


def numerically_zero(exprs: Iterable[sp.Expr], trials: int = 3, seed: int = 20261121) -> bool:
    """True when every expression vanishes at `trials` random points.

    Used to decide identities such as "L has no explicit t" robustly when a
    dependence cancels only after trigonometric simplification (a bead on a
    spinning hoop has cos(W t)**2 + sin(W t)**2 in its T). Random values lie in
    [0.3, 1.3] so square roots and logs of parameters stay real. A point where an
    expression is not finite or not real is skipped (another is drawn).
    """
    exprs = [sp.sympify(e) for e in exprs]
    exprs = [e for e in exprs if e != 0]
    if not exprs:
        return True
    names = set().union(*(e.free_symbols for e in exprs))
    rng = random.Random(seed)
    done = attempts = 0
    while done < trials and attempts < 10 * trials:
        attempts += 1
        point = {s: rng.uniform(0.3, 1.3) for s in sorted(names, key=str)}
        memo: dict = {}      # subexpressions shared between the expressions are evaluated once
        values = [_evaluate(e, point, memo) for e in exprs]
        if any(v is None for v in values):
            continue
        done += 1
        if any(abs(value) > 1e-9 * (1 + scale) for value, scale in values):
            return False
    return done > 0  # no point could be evaluated: undecided, so not "zero"


def _evaluate(expr: sp.Expr, point: dict, memo: dict) -> tuple[float, float] | None:
    """(value, scale) of expr at point, scale = sum of |terms| for a relative tolerance.

    Evaluated in double precision node by node (`constants.value_at`), never by
    substituting Floats and `evalf`: sympy would evaluate sin(exp(exp(exp(exp(x)))))
    at a point with mpmath to millions of digits."""
    terms = expr.args if expr.is_Add else (expr,)
    total, scale = 0.0, 0.0
    for term in terms:
        try:
            number = value_at(term, point, memo)
        except ConstantError:
            return None
        total += number
        scale += abs(number)
    return total, scale


class DependenceProbe:
    """Decides numerically whether expressions depend on a symbol.

    The expressions are evaluated at random points, then again with only the symbol in
    question changed. Any change beyond rounding means dependence. Used where structural
    dependence is misleading: cos(W t)**2 + sin(W t)**2. The random points and the values
    there are drawn and computed once for all the symbols asked about (asking about each of
    n coordinates would otherwise draw and evaluate n points of n symbols: quadratic in a
    system of many coordinates). Evaluated node by node in double precision
    (`constants.value_at`, as `numerically_zero`), each shared subexpression once; at a
    moved point only the nodes that mention the moved symbol are evaluated again, a sum
    from its terms' values at the base point with those that mention it replaced
    (`_Moved`): the same values as evaluating everything anew. (Compiling the expressions
    with sympy's lambdify printed them whole: most of the cost for a chain's V; evaluating
    all of V again for each coordinate was n^3.) `free`: a `free_symbols` memo.
    """

    def __init__(self, exprs: Sequence[sp.Expr], seed: int = 20261121, free: dict | None = None):
        self.exprs = [sp.sympify(e) for e in exprs]
        self.free = {} if free is None else free
        self.symbols = sorted(set().union(*(free_symbols(e, self.free) for e in self.exprs)), key=str)
        self.rng = random.Random(seed)
        self.points: list[tuple[dict, list[float] | None, dict]] = []   # (point, values, memo), in draw order
        self.mentions: dict = {}      # sum -> {symbol: the places of its terms that mention it}
        self.term_lists: dict = {}    # (id of a point's values, id of a sum) -> its terms' values there
        self.exprs_mentioning: dict | None = None    # symbol -> the places of the exprs that mention it

    def _point(self, k: int) -> tuple[dict, list[float] | None, dict]:
        while len(self.points) <= k:
            point, memo = {s: self.rng.uniform(0.3, 1.3) for s in self.symbols}, {}
            try:
                values = [value_at(e, point, memo) for e in self.exprs]
            except _UNDEFINED:
                values = None
            self.points.append((point, values, memo))
        return self.points[k]

    def depends_on(self, symbol: sp.Symbol, trials: int = 3) -> bool:
        if not self._mentioning(symbol):         # (a list's `in` compared every symbol: n^2)
            return False
        done = attempts = 0
        while done < trials and attempts < 10 * trials:
            base, first, memo = self._point(attempts)
            attempts += 1
            if first is None:
                continue
            moved = _Moved(self, memo, symbol, base[symbol] + self.rng.uniform(0.5, 1.5))
            places = self._mentioning(symbol)      # the others keep their values: not evaluated again
            try:
                second = [moved.value(self.exprs[k]) for k in places]
            except _UNDEFINED:
                continue
            done += 1
            scale = 1 + max(max(abs(v) for v in first), max(abs(v) for v in second))
            if any(abs(first[k] - b) > 1e-9 * scale for k, b in zip(places, second)):
                return True
        return done == 0  # no point could be evaluated: undecided, so assume dependence

    def _mentioning(self, symbol: sp.Symbol) -> list[int]:
        """The places of the expressions that mention `symbol` (indexed once: asking each of
        n coordinates about n diagonal entries of M was n^2)."""
        if self.exprs_mentioning is None:
            self.exprs_mentioning = {}
            for k, e in enumerate(self.exprs):
                for s in free_symbols(e, self.free):
                    self.exprs_mentioning.setdefault(s, []).append(k)
        return self.exprs_mentioning.get(symbol, [])

    def term_values(self, expr: sp.Add, base: dict) -> list[float]:
        """The values of the sum `expr`'s terms at a base point (`base`: the values of every
        node there), a new list of them, listed once per point and sum (looking each term up
        for each moved symbol was n^3 for a chain's V). Keyed by identity: the sums and the
        points' values stay alive in `exprs` and `points`."""
        key = (id(base), id(expr))
        found = self.term_lists.get(key)
        if found is None:
            found = self.term_lists[key] = [base[term] for term in expr.args]
        return list(found)

    def places(self, expr: sp.Add, symbol: sp.Symbol) -> list[int]:
        """The places of the terms of the sum `expr` that mention `symbol` (indexed once)."""
        index = self.mentions.get(expr)
        if index is None:
            index = self.mentions[expr] = {}
            for k, term in enumerate(expr.args):
                for s in free_symbols(term, self.free):
                    index.setdefault(s, []).append(k)
        return index.get(symbol, [])


_UNDEFINED = (ConstantError, TypeError, ValueError, ArithmeticError)   # complex, undefined, overflow


class _Moved:
    """Values at a point that differs from a base point (`base`: the values of every node
    there) in `symbol` only, which has the value `at`."""

    def __init__(self, probe: DependenceProbe, base: dict, symbol: sp.Symbol, at: float):
        self.probe, self.base, self.symbol, self.at = probe, base, symbol, at
        self.values: dict = {}

    def value(self, expr: sp.Expr) -> float:
        if self.symbol not in free_symbols(expr, self.probe.free):
            return self.base[expr]
        found = self.values.get(expr)
        if found is None:
            if not expr.args:        # a leaf that mentions the symbol: the symbol
                found = value_at(expr, {expr: self.at})
            elif expr.is_Add:
                args = self.probe.term_values(expr, self.base)
                for k in self.probe.places(expr, self.symbol):
                    args[k] = self.value(expr.args[k])
                found = value_from_arguments(expr, args)
            else:
                found = value_from_arguments(expr, [self.value(arg) for arg in expr.args])
            self.values[expr] = found
        return found


@functools.lru_cache(maxsize=1 << 16)
def _rough(expr: sp.Basic) -> bool:
    """expr.has(DiracDelta, Heaviside, Derivative), remembered for shared subexpressions
    (the entries of a chain's M and F share most of theirs: `has` walked each whole tree)."""
    return isinstance(expr, (sp.DiracDelta, sp.Heaviside, sp.Derivative)) or any(_rough(a) for a in expr.args)


def _any_rough(exprs) -> bool:
    """`_rough` of any of `exprs`, in one walk visiting each subtree object once (the
    100-link chain's mass matrix has 170 000 nodes: more than `_rough` remembers). Nodes
    are told apart by identity (`id`, kept alive in `seen`): an equal copy is walked
    again, but no node's Python-level `__hash__` is called (most of the walk's time)."""
    stack, seen = list(exprs), {}
    while stack:
        node = stack.pop()
        key = id(node)
        if key in seen:
            continue
        if isinstance(node, (sp.DiracDelta, sp.Heaviside, sp.Derivative)):
            return True
        seen[key] = node
        stack.extend(node.args)
    return False


def distinct_nodes(*exprs) -> set:
    """Every distinct subexpression of `exprs` (what `sympy.preorder_traversal` visits, each
    once: big expressions share their parts, which a tree walk visits at every occurrence).
    An object met again is recognised by identity first (`id`, kept alive in `met`):
    only the first meeting of each object calls its Python-level `__hash__`."""
    seen, met, stack = set(), {}, list(exprs)
    while stack:
        node = stack.pop()
        key = id(node)
        if key in met:
            continue
        met[key] = node
        if node not in seen:
            seen.add(node)
            stack.extend(node.args)
    return seen


def leaves(*exprs) -> set:
    """The atoms of `exprs` (the nodes without arguments, what `atoms()` finds), each node
    object visited once and told apart by identity (`id`, kept alive in `met`): only the
    leaves are hashed, not every distinct subexpression as in `distinct_nodes` (a chain's T
    holds n^2 new products q_i' M_ij). An equal copy of a subtree is walked again: never
    more nodes than there are objects."""
    found, met, stack = set(), {}, list(exprs)
    while stack:
        node = stack.pop()
        key = id(node)
        if key in met:
            continue
        met[key] = node
        args = node.args
        if args:
            stack.extend(args)
        else:
            found.add(node)
    return found


def matrix_of_entries(rows: int, columns: int, entries: dict, kind=sp.Matrix) -> sp.MatrixBase:
    """The `kind` (sp.Matrix or sp.ImmutableMatrix) matrix with the nonzero `entries`
    ((i, j) -> value). What `kind(sp.SparseMatrix(rows, columns, entries))` returns (sympy
    keeps the sparse storage inside the dense matrix), without its walk over all
    rows x columns places: 0.5 s for the 1 000 x 1 000 M of 1 000 uncoupled coordinates."""
    return kind._fromrep(sp.SparseMatrix(rows, columns, entries)._rep)


def almost_everywhere(value):
    """Derivatives of abs/sign/min/max taken almost everywhere: DiracDelta -> 0, d sign -> 0 and
    Heaviside(x) -> (1 + sign(x))/2, so every result prints in the spec language and in C."""
    if isinstance(value, sp.MatrixBase):    # its nonzero entries only: M of n uncoupled coordinates has n
        entries = value.todok()
        if not _any_rough(entries.values()):
            return value.as_immutable()
        entries = {key: almost_everywhere(e) for key, e in entries.items()}
        return matrix_of_entries(value.shape[0], value.shape[1], entries, sp.ImmutableMatrix)
    value = sp.sympify(value)
    if not _rough(value):
        return value
    # sympy leaves d/dx sign(u) unevaluated when it cannot prove u real (u = 1/x): it is 0 too
    value = value.replace(lambda e: isinstance(e, sp.Derivative) and isinstance(e.expr, sp.sign),
                          lambda e: sp.S.Zero)
    value = value.replace(sp.DiracDelta, lambda *args: sp.S.Zero)
    return value.replace(sp.Heaviside, lambda x, *rest: (1 + sp.sign(x)) / 2)

