"""The report's expressions, assembled from small parts tidied once (`Display`).

Simplifying a large expression is slow and misses identities hidden in products, so
nothing large is ever simplified here. The small parts are tidied once
(`lagcli.render.tidy.display_form`): the entries of the mass matrix M, the
coefficients a of T1 = a . q', T0, V, Q' and the constraint rows. Everything else is
assembled from them, exactly (the tests parse the JSON back and compare with the
derivation at random states):

    T2 = 1/2 sum_i M_ii q'_i^2 + sum_{i<j} M_ij q'_i q'_j        T = T2 + T1 + T0
    L = T - V,  E = T + V,  h = T2 - T0 + V,  p_s = (M q' + a)_s
    equation i:  sum_j M_ij q''_j  + velocity terms  + the rest  =  sum_j lambda_j a_ji

An expression is a list of terms in the order the lecture notes write them (q''
terms first, then velocity terms by degree, then terms free of q'); the printers
join them with signs pulled out (`signed_sum`); a term that is a tidied coefficient times
velocities has its signs pulled out without a walk when that is known to keep it
(`signed_product`). The velocity terms of equation i
are grouped by monomial q'_j q'_l, with coefficients from the derivatives of the
tidied M (the Christoffel symbols of the notes' explicit form):

    c_i = sum_{j<=l} C_ijl q'_j q'_l,  C_ijl = d_l M_ij + d_j M_il - d_i M_jl  (j < l)
                                        C_ijj = d_j M_ij - 1/2 d_i M_jj
"""
from __future__ import annotations

import functools
from collections.abc import Callable, Sequence

import sympy as sp

from lagcli.model import calculus
from lagcli.model.products import product
from lagcli.model.sums import negated_terms, negative, total
from lagcli.derive.result import Derivation
from lagcli.report.derivatives import angle_entry_rates, derivative
from lagcli.render.dot_products import folded_dot_product
from lagcli.render.shapes import Shapes
from lagcli.render.tidy import (DISPLAY_MAX_NODES, display_form, pull_signs, small, sum_of_symbols, tree_size,
                                weighted_expandable)
from lagcli.render.weighted import flat_weighted_sum, weighted_display_form, weighted_sum

TREE_MAX_NODES = 5000     # tidy the parts of expressions up to this size (tree nodes)

Terms = list   # of sympy expressions, none of them a sum


def signed_sum(terms: Sequence[sp.Expr], print_expr: Callable[[sp.Expr], str],
               pieces: dict | None = None) -> str:
    """`a + b - c`: the terms in order, each printed by `print_expr` with its sign pulled out.
    `pieces` remembers each term's sign and printed body, for a printer that prints the
    same terms in several sums (T, L, E and h share T2's terms)."""
    if not terms:
        return print_expr(sp.S.Zero)
    pieces = {} if pieces is None else pieces
    out = []
    for i, term in enumerate(terms):
        piece = pieces.get(term)
        if piece is None:
            piece = pieces[term] = _signed_piece(term, print_expr)
        negative, body = piece
        if i == 0:
            out.append(f"-{body}" if negative else body)
        else:
            out.append(f" - {body}" if negative else f" + {body}")
    return "".join(out)


def _signed_piece(term: sp.Expr, print_expr: Callable[[sp.Expr], str]) -> tuple[bool, str]:
    """(negative, the term's magnitude printed, in parentheses when a sum)."""
    if type(term) is sp.Mul:     # Mul.could_extract_minus_sign, its -term built once (it builds one to
        leading = term.args[0]   # compare), and only for a negative leading number (else: not negative)
        negated = -term if leading.is_Number and leading.is_extended_negative else term
        negative = negated is not term and term != negated
        shown = negated if negative else term
    else:
        negative = term.could_extract_minus_sign()
        shown = -term if negative else term
    body = print_expr(shown)
    return negative, f"({body})" if shown.is_Add else body


def _tidies_to_itself(expr, cache: dict) -> bool:
    """`Display.tidy(expr)` is known to be expr: neither a sum nor a product (`_tidy_tree`
    leaves those as they are: sin(q1 - q2), new in each derivative of M), or one tidied
    to itself before."""
    return not (expr.is_Add or expr.is_Mul) or cache.get(expr) is expr


def split(expr: sp.Expr) -> Terms:
    """The terms of a sum (none for 0)."""
    return [] if expr == 0 else list(sp.Add.make_args(expr))


class Display:
    """Tidied parts of one derivation and the report's expressions built from them."""

    def __init__(self, d: Derivation, simplify: bool = True):
        self.d = d
        m = d.model
        self.q, self.qd, self.qdd, self.t = m.q, m.qd, m.qdd, m.t
        self.n = len(m.q)
        self._cache: dict = {}
        self._flat_sums: dict = {}       # sum -> flat_weighted_sum(sum)
        self._parts: dict = {}
        self._signs: dict = {}
        self._free_symbols: dict = {}   # of M's entries and every subexpression differentiated (calculus.free_symbols)
        self._differentiated: dict = {}  # (expr, var) -> d expr / d var
        self._rates: dict = {}           # (expr, var) -> d expr / d var of their parts (`derivatives.rate`)
        self._merged: dict = {}          # (i, names) -> the terms of the parts `names` of equation i
        self._bucket_terms: dict = {}    # (monomial, coefficient, sign) -> its terms, moving or not (`ordered_terms`)
        self._places: dict = {}          # monomial -> its place among an equation's terms (`ordered_terms`)
        self._monomials: dict = {}       # (j, l) -> q'_j q'_l
        self._tidy_on = simplify
        self._outlines: set = set()      # (terms, tree size) of the sums met (`_outline_seen`)
        self._tidy_by_shape = Shapes(functools.partial(self._tidy_tree, sized=True))
        n = self.n
        upper = {(i, j): self.tidy(d.mass_matrix[i, j]) for i in range(n) for j in range(i, n)}
        self.M = [[upper[min(i, j), max(i, j)] for j in range(n)] for i in range(n)]
        self._free = {key: calculus.free_symbols(entry, self._free_symbols) for key, entry in upper.items()}
        self._derivatives: dict = {}     # (i, j, k), i <= j -> dM_ij/dq_k (`_dM`)
        self._angle_rates: dict = {}     # (i, j), i <= j -> {q: dM_ij/dq} built at once (`angle_entry_rates`)
        self.a = [self.tidy(e) for e in d.t1_coefficients]
        self.T0 = self.tidy(d.T0)
        self.V = self.tidy(d.V)
        self.Qp = [self.tidy(e) for e in d.nonconservative_forces]
        self.A = [[self.tidy(e) for e in row.a] for row in d.constraints]

    def differentiate(self, expr: sp.Expr, var) -> sp.Expr:
        """d expr / d var (`derivative`), each taken once (Q_i and the explicit form's
        position terms both need dV/dq_i)."""
        key = (expr, var)
        found = self._differentiated.get(key)
        if found is None:
            found = self._differentiated[key] = derivative(expr, var, self._free_symbols, self._rates)
        return found

    def tidy(self, expr, sized: bool = False) -> sp.Expr:
        """expr tidied (`_tidy_tree`); `sized`: expr is known to be within TREE_MAX_NODES."""
        if not isinstance(expr, sp.Basic):
            expr = sp.sympify(expr)
        if not self._tidy_on:
            return expr
        cache = self._cache
        found = cache.get(expr)
        if found is None:
            if expr.is_Mul and all(_tidies_to_itself(a, cache) for a in expr.args):
                found = expr       # what _tidy_tree finds for a product of tidy factors (a derivative of M_ij)
            elif expr.is_Add and (folded := folded_dot_product(expr)) is not None:
                found = folded     # what _tidy_tree finds for a chain's dot product, found directly
            elif expr.is_Add and self._by_shape(expr, sized):
                found = self._tidy_by_shape(expr)   # the steps of the last sum of its shape
            else:
                found = self._tidy_tree(expr, sized)
            cache[expr] = found
        return found

    def _flat_weighted(self, add):
        """`flat_weighted_sum(add)`, found once (`_by_shape` and `_tidy_tree` both ask)."""
        found = self._flat_sums.get(add, self._flat_sums)
        if found is self._flat_sums:
            found = self._flat_sums[add] = flat_weighted_sum(add)
        return found

    def _by_shape(self, add, sized: bool = False) -> bool:
        """Worth tidying by its shape (a whole sum, or one inside a product: the dot
        product X of a chain's M entry X (m_k + ... + m_n)): small, not a weighted sum (whose X is tidied by its
        shape instead: renaming the whole sum costs as much as tidying it; nor one written
        flat, dV/dq_i = -g l_i m_i sin(q_i) - ... of a chain), not a sum of symbols
        (display_form keeps it)."""
        return (sized or small(add, TREE_MAX_NODES)) and not sum_of_symbols(add) and weighted_sum(add) is None \
            and self._flat_weighted(add) is None and self._outline_seen(add)

    def _outline_seen(self, add) -> bool:
        """A sum with add's number of terms and tree size was met before: only then may add
        share a shape with another (renaming a sum of a shape met once, to remember its
        result, cost as much as tidying it: a chain's potential and its 39 sums
        l_1 cos(q_1) + ... + l_k cos(q_k), one shape each). The first sum of each outline
        is tidied directly: the result is the same either way (`lagcli.render.shapes`)."""
        outline = (len(add.args), tree_size(add, TREE_MAX_NODES))
        if outline in self._outlines:
            return True
        self._outlines.add(outline)
        return False

    def signs(self, expr) -> sp.Expr:
        """`pull_signs`, remembering every subexpression's result for this report."""
        return pull_signs(expr, self._signs)

    def signed(self, coefficient, *factors) -> sp.Expr:
        """`signs` of the product of a tidied coefficient and velocities (`signed_product`)."""
        return signed_product(coefficient, *factors, signs=self.signs)

    def tidy_assembled(self, expr) -> sp.Expr:
        """An expression assembled from tidied parts (a derivative, a sum of them): tidied
        again only when it is small (DISPLAY_MAX_NODES); a big one keeps the form of its
        parts, signs pulled out (re-tidying it was most of a big system's report)."""
        expr = sp.sympify(expr)
        return self.tidy(expr) if small(expr, DISPLAY_MAX_NODES) else self.signs(expr)

    def _tidy_tree(self, expr: sp.Expr, sized: bool) -> sp.Expr:
        """Children first (each distinct one once: the same dot product appears in every
        mass's term), then the sums that combine them. The size is checked once, at the top
        (the children of a small expression are small)."""
        if expr.is_Atom or not (expr.is_Add or expr.is_Mul) or not (sized or small(expr, TREE_MAX_NODES)):
            return expr      # a huge expression is shown with named quantities instead
        weighted = weighted_sum(expr)
        if weighted is not None:
            found = weighted_display_form(weighted[0], self.tidy(weighted[1]), self.signs)   # X by its shape
            if found is not None:
                return found
        args = [self.tidy(a, sized=True) for a in expr.args]
        if all(new is old for new, old in zip(args, expr.args)):
            rebuilt = expr
        else:       # sympy's Mul without its general flatten (M's entries: X' times the sum of masses)
            rebuilt = product(*args) if expr.is_Mul else total(args) if expr.is_Add else expr.func(*args)
        if not rebuilt.is_Add:
            return rebuilt
        flat = self._flat_weighted(rebuilt)
        if flat is not None and small(rebuilt) and weighted_expandable(len(flat[0]), flat[1]):   # display_form's own terms
            found = weighted_display_form(*flat, self.signs)
            if found is not None:
                return found
        return display_form(rebuilt)

    # -- energies and integrals ---------------------------------------------------------

    @functools.cached_property
    def T2(self) -> Terms:
        n, qd, M = self.n, self.qd, self.M
        terms = [self.signed(M[i][i], qd[i] ** 2, sp.S.Half) for i in range(n)]      # one product each: the
        terms += [self.signed(M[i][j], qd[i], qd[j]) for i in range(n) for j in range(i + 1, n)]   # same as two
        return [term for term in terms if nonzero(term)]

    @functools.cached_property
    def T1(self) -> Terms:
        return [self.signed(a, v) for a, v in zip(self.a, self.qd) if a != 0]

    @property
    def T(self) -> Terms:
        return self.T2 + self.T1 + split(self.T0)

    @property
    def T_is_T2(self) -> bool:
        return not self.T1 and self.T0 == 0

    @property
    def lagrangian(self) -> Terms:
        return self.T + [-v for v in split(self.V)]

    @property
    def energy(self) -> Terms:
        return self.T + split(self.V)

    @property
    def jacobi(self) -> Terms:
        return self.T2 + [-e for e in split(self.T0)] + split(self.V)

    def momentum(self, s: int) -> Terms:
        terms = [self.signed(M_sj, v) for M_sj, v in zip(self.M[s], self.qd) if nonzero(M_sj)]
        return terms + split(self.a[s])

    def conserved(self, kind: str, name: str) -> Terms:
        if kind == "momentum":
            return self.momentum([f"p_{q.name}" for q in self.q].index(name))
        return self.jacobi if kind == "jacobi" else self.energy

    # -- forces ----------------------------------------------------------------------------

    def generalized_force(self, i: int) -> sp.Expr:
        """Q_i = Q'_i - dV/dq_i."""
        return self.tidy_assembled(difference(self.Qp[i], self.differentiate(self.V, self.q[i])))

    @functools.cached_property
    def gyroscopic(self) -> list[list[sp.Expr]]:
        """gamma_ij = da_i/dq_j - da_j/dq_i (0 at once when a_i = a_j = 0: a system with no T1)."""
        q, a, n, d, zero = self.q, self.a, self.n, self.differentiate, sp.S.Zero
        return [[self.tidy_assembled(difference(d(a[i], q[j]), d(a[j], q[i])))
                 if i != j and (a[i] is not zero or a[j] is not zero) else zero
                 for j in range(n)] for i in range(n)]

    def constraint_force(self, i: int) -> Terms:
        """C_i = sum_j lambda_j a_ji."""
        return [self.signed(row[i], lam) for lam, row in zip(self.d.multipliers, self.A) if row[i] != 0]

    # -- equations of motion ---------------------------------------------------------------

    def _dM(self, i: int, j: int, k: int) -> sp.Expr:
        """dM_ij/dq_k, each computed once (the velocity terms ask for most of them n times),
        kept under the indices (a tuple of ints hashes in C, a symbol's hash is a Python call)."""
        key = (i, j, k) if i <= j else (j, i, k)
        found = self._derivatives.get(key)
        if found is None:
            found = sp.S.Zero
            if k in self._mentions[key[:2]]:
                found = self._entry_rates(key[:2]).get(self.q[k])
                if found is None:
                    found = self.differentiate(self.M[i][j], self.q[k])
            self._derivatives[key] = found
        return found

    def _entry_rates(self, entry: tuple) -> dict:
        """`angle_entry_rates` of M's entry (i, j), i <= j: the derivatives of a chain's
        l_i l_j (m_j + ... + m_n) cos(q_i - q_j), found without `differentiate`'s walk."""
        found = self._angle_rates.get(entry)
        if found is None:
            i, j = entry
            found = self._angle_rates[entry] = angle_entry_rates(self.M[i][j], self._free_symbols, self._rates)
        return found

    def _dM_dt(self, i: int, j: int) -> sp.Expr:
        """dM_ij/dt (0 when M_ij does not mention t: always, for a scleronomic system)."""
        entry = (i, j) if i <= j else (j, i)
        return self.differentiate(self.M[i][j], self.t) if self.t in self._free[entry] else sp.S.Zero

    def velocity_buckets(self, i: int) -> dict:
        """c_i grouped by monomial: {q'_j q'_l: C_ijl} (see the module docstring), over
        the pairs (j, l) where a derivative in C_ijl can be nonzero (`_velocity_pairs`)."""
        zero = sp.S.Zero
        out = {}
        for j, l in self._velocity_pairs(i):
            if j == l:
                parts = (self._dM(i, j, j), _negated(self._dM(j, j, i), half=True))
            else:
                parts = _cancelled(self._dM(i, j, l), self._dM(i, l, j), self._dM(j, l, i))
            kept = [part for part in parts if part is not zero]
            if kept:      # sympy's Add drops zeros and returns a single term itself
                coefficient = kept[0] if len(kept) == 1 else sp.Add(*kept)
                if nonzero(coefficient):
                    out[self._monomial(j, l)] = coefficient
        return out

    def _monomial(self, j: int, l: int) -> sp.Expr:
        """q'_j q'_l, one object for each pair (the buckets of every equation share them)."""
        key = (j, l)
        found = self._monomials.get(key)
        if found is None:
            found = self._monomials[key] = product(self.qd[j], self.qd[l])
        return found

    def _velocity_pairs(self, i: int) -> list[tuple[int, int]]:
        """The pairs j <= l, in order, for which d_l M_ij, d_j M_il or d_i M_jl may be nonzero
        (the entry mentions that coordinate): ~n pairs per equation of a chain, whose
        entries mention two coordinates each, instead of all n^2 / 2."""
        pairs = set(self._mentioning[i])                            # d_i M_jl
        for other in range(self.n):                                 # d_l M_ij and d_j M_il
            for k in self._mentions[min(i, other), max(i, other)]:
                pairs.add((min(other, k), max(other, k)))
        return sorted(pairs)

    @functools.cached_property
    def _mentions(self) -> dict:
        """(i, j), i <= j -> the indices of the coordinates M_ij mentions."""
        index = {qk: k for k, qk in enumerate(self.q)}
        return {key: frozenset(index[s] for s in free if s in index) for key, free in self._free.items()}

    @functools.cached_property
    def _mentioning(self) -> list:
        """k -> the entries (i, j), i <= j, that mention q_k."""
        mentioning = [[] for _ in range(self.n)]
        for key, ks in self._mentions.items():
            for k in ks:
                mentioning[k].append(key)
        return mentioning

    def parts(self, i: int) -> dict[str, dict]:
        if i not in self._parts:
            self._parts[i] = self._compute_parts(i)
        return self._parts[i]

    def _compute_parts(self, i: int) -> dict[str, dict]:
        """The explicit form's terms of equation i, each {velocity monomial (1 for none): coefficient}:
        c, M_t q', gamma q', a_t, dV/dq - dT0/dq and -Q'."""
        qd, t, q = self.qd, self.t, self.q
        mass_rate = {v: self._dM_dt(i, j) for j, v in enumerate(qd)}
        gyroscopic = {v: g for v, g in zip(qd, self.gyroscopic[i])}
        a_t = self.differentiate(self.a[i], t)
        position = difference(self.differentiate(self.V, q[i]), self.differentiate(self.T0, q[i]))
        forces: dict = {}
        for term in split(self.Qp[i]):
            coefficient, monomial = term.as_independent(*qd, as_Add=False)
            _add(forces, monomial, -coefficient)
        return {"velocity": self.velocity_buckets(i), "mass_rate": mass_rate, "gyroscopic": gyroscopic,
                "t1_rate": {sp.S.One: a_t}, "position": {sp.S.One: position}, "forces": forces}

    def part_terms(self, i: int, names: Sequence[str]) -> Terms:
        """The terms of the parts `names` of equation i, merged by monomial and ordered."""
        key = (i, tuple(names))
        found = self._merged.get(key)
        if found is None:       # the equation and F_i merge and order the same parts
            buckets: dict = {}
            for name in names:
                for monomial, coefficient in self.parts(i)[name].items():
                    _add(buckets, monomial, coefficient)
            found = self._merged[key] = self._ordered(buckets)
        return list(found)

    def acceleration_terms(self, i: int) -> Terms:
        return [self.signed(M_ij, a) for M_ij, a in zip(self.M[i], self.qdd) if nonzero(M_ij)]

    def equation(self, i: int) -> Terms:
        """sum_j M_ij q''_j + c_i + (M_t q')_i + (gamma q')_i + a_t,i + dV/dq_i - dT0/dq_i - Q'_i."""
        return self.acceleration_terms(i) + self.part_terms(i, PARTS)

    def forcing(self, i: int) -> Terms:
        """F_i = Q'_i - c_i - ...: the equation's terms without q'', negated term by term
        (tidying each negated coefficient anew gave the same terms for a fifth of a
        40-link report's content: tests/test_report_forcing.py)."""
        return [self.signs(_negated(term)) for term in self.part_terms(i, PARTS)]

    def _ordered(self, buckets: dict) -> Terms:
        """Terms of degree 2 in q', then 1, then others depending on q', then free of q' (`ordered_terms`)."""
        return ordered_terms(buckets, self.qd, self.tidy_assembled, self.signs, 1, self._free_symbols,
                             self._bucket_terms, self._places)


def ordered_terms(buckets: dict, velocities: Sequence, tidy: Callable, signs: Callable = pull_signs,
                  sign: int = 1, memo: dict | None = None, made: dict | None = None,
                  places: dict | None = None) -> Terms:
    """The terms of an equation without its q'' terms, in the lecture notes' order, from
    {velocity monomial (1 for none): coefficient}: degree 2 in q', then 1 (by coordinate),
    then others depending on q', then free of q'. Each coefficient (times `sign`) is
    tidied by `tidy` and its sign pulled out by `signs`; the coefficient of 1 gives one
    term per summand. The derive report's equations and the Routh reduction's use this.
    `made` remembers the terms of each (monomial, coefficient, sign) (`bucket_terms`) and
    which of them mention a velocity, `places` each monomial's place (both for one list
    of velocities): the equations, F and the explicit form's parts share their coefficients."""
    index = {v: k for k, v in enumerate(velocities)}
    memo = {} if memo is None else memo
    made = {} if made is None else made
    places = {} if places is None else places

    def key(monomial):
        found = places.get(monomial)
        if found is None:
            found = places[monomial] = _place(monomial, index)
        return found

    moving_set = set(velocities)
    out: Terms = []
    moving: list = []
    for monomial in sorted(buckets, key=key):
        entry = (monomial, buckets[monomial], sign)
        found = made.get(entry)
        if found is None:
            terms = bucket_terms(monomial, buckets[monomial], tidy, signs, sign)
            found = made[entry] = (terms, [_shows_velocity(t, monomial, moving_set)
                                           or not calculus.free_symbols(t, memo).isdisjoint(moving_set) for t in terms])
        out.extend(found[0])
        moving.extend(found[1])
    return [term for term, m in zip(out, moving) if m] + [term for term, m in zip(out, moving) if not m]


def _shows_velocity(term, monomial, velocities: set) -> bool:
    """term has the monomial's first factor, a velocity or a power of one, among its own
    factors (by identity: the product of a coefficient and the monomial keeps it): it
    mentions a velocity, known without collecting its free symbols (a sum of 40 masses
    among them); False says nothing."""
    first = monomial.args[0] if type(monomial) is sp.Mul else monomial
    base = first.args[0] if type(first) is sp.Pow else first
    return base in velocities and type(term) is sp.Mul and any(a is first for a in term.args)


def _place(monomial, index: dict) -> tuple:
    """The sort key of a monomial in `ordered_terms`: by degree in the velocities (`index`:
    velocity -> its coordinate's index), then by coordinates; anything else after them."""
    powers = monomial.as_powers_dict()
    if all(base in index and e.is_Integer for base, e in powers.items()) or monomial == 1:
        degree = sum(int(e) for base, e in powers.items() if base in index)
        indices = tuple(sorted(index[b] for b, e in powers.items() if b in index for _ in range(int(e))))
        return (0, -degree, indices, "")
    return (1, 0, (), sp.default_sort_key(monomial))   # not a monomial in q': after them


def bucket_terms(monomial, coefficient, tidy: Callable, signs: Callable, sign: int) -> Terms:
    """The terms of coefficient * monomial in `ordered_terms`: the coefficient (times `sign`)
    tidied, one term per summand for the monomial 1, none for 0."""
    coefficient = tidy(coefficient if sign == 1 else product(sp.Integer(sign), coefficient))
    if not nonzero(coefficient):
        return []
    if monomial is sp.S.One or (monomial.is_Number and monomial == 1):    # no sympy comparison for q'_j**2
        return [signs(term) for term in split(coefficient)]
    return [signed_product(coefficient, monomial, signs=signs)]


def signed_product(coefficient, *factors, signs: Callable = pull_signs) -> sp.Expr:
    """signs(product(coefficient, *factors)), `signs` pull_signs (or one remembering its
    results): the product itself, without pull_signs' walk, when that is known to keep it
    (`_keeps_signs`): the report's terms, a tidied coefficient times velocities."""
    term = product(coefficient, *factors)
    return term if _keeps_signs(term, coefficient, signs) else signs(term)


def _keeps_signs(term, coefficient, signs: Callable) -> bool:
    """pull_signs(term) is term, for the product `term` of coefficient and other factors:
    coefficient is no sum and `signs` keeps it, and each factor of term is an atom, a
    power of atoms or one of coefficient's own factors (by identity). pull_signs flips
    only the sums among a product's factors, and those are coefficient's, which it kept
    (tests/test_report_signed_product.py)."""
    if not term.is_Mul or coefficient.is_Add or signs(coefficient) is not coefficient:
        return False
    own = {id(a) for a in (coefficient.args if coefficient.is_Mul else (coefficient,))}
    return all(a.is_Atom or (a.is_Pow and a.base.is_Atom and a.exp.is_Atom) or id(a) in own for a in term.args)


def _cancelled(first, second, subtracted) -> tuple:
    """The terms of first + second - subtracted (C_ijl, j < l), where `subtracted` is often
    one of the others itself (d_i M_il twice in C_iil): those two cancel, and when the
    remaining one is 0 the sum is 0 with no sympy arithmetic (x - x is 0 exactly, floats
    too; a nonzero remainder is summed by sympy as before, whose float sums may round)."""
    zero = sp.S.Zero
    if subtracted is not zero and (subtracted is first or subtracted is second):
        other = second if subtracted is first else first
        if other is zero:
            return ()
    return first, second, _negated(subtracted)


def _negated(expr, half: bool = False):
    """-expr (-expr/2 with `half`) as sympy's operators build it; 0 stays 0 without them."""
    if expr is sp.S.Zero:
        return expr
    return -expr / 2 if half else -expr


PARTS = ("velocity", "mass_rate", "gyroscopic", "t1_rate", "position", "forces")


def _add(buckets: dict, monomial, coefficient) -> None:
    """buckets[monomial] += coefficient; a new monomial's coefficient is the object itself
    (0 + x is x in sympy, found through five layers of its arithmetic)."""
    if nonzero(coefficient):
        found = buckets.get(monomial)
        buckets[monomial] = coefficient if found is None else found + coefficient


def nonzero(expr) -> bool:
    """expr != 0, without sympy's comparison for its 0 (by identity) and for an expression
    that is no number (sympy compares trees: only a number can equal 0): ~10 000 tests of
    a 40-link chain's terms and coefficients."""
    if expr is sp.S.Zero:
        return False
    if isinstance(expr, sp.Basic) and not expr.is_Number:
        return True
    return expr != 0


def difference(a, b) -> sp.Expr:
    """a - b, the same expression as sympy's: a + (-b), b's terms negated one by one and
    summed once (`sums.total`; sympy's -b rebuilt the 40 terms of a chain's dV/dq_i by its
    Mul and Add, and `x - 0` re-sorted x)."""
    if a is sp.S.Zero:       # Q_i = -dV/dq_i: total(b's negated terms) is negative(b), which keeps
        return negative(b)   # a sum of products without numbers in its order instead of sorting it
    return total([a, *negated_terms(b)])
