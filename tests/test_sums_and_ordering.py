"""`total` (lagcli/model/sums.py) builds the very expression sympy's Add does, and
`sort_key` (lagcli/model/ordering.py) orders expressions as `Basic.compare` does."""
import functools
import random

import sympy as sp
from hypothesis import given, settings, strategies as st

from lagcli.model.ordering import sort_args, sort_key
from lagcli.model.products import product
from lagcli.model.sums import dot, negated_terms, negative, scaled, total

x, y, z = sp.symbols("x y z", real=True)
m1, m10, m2, q1, q10 = sp.symbols("m1 m10 m2 q1 q10")
a, b = sp.symbols("a b", commutative=False)
f = sp.Function("f")
POOL = [x, y, z, m1, m10, m2, q1, q10, sp.cos(q1), sp.sin(q1 - q10), f(x), sp.Dummy("d")]
NUMBERS = [sp.Integer(2), sp.Integer(-1), sp.Rational(1, 2), sp.Rational(-3, 4), sp.S.One, sp.S.Zero,
           sp.Float(0.5), sp.pi, sp.sqrt(2), sp.I, sp.oo, sp.zoo, sp.nan]


def _expression(rng, depth=0):
    kind = rng.random()
    if kind < 0.3 or depth > 2:
        return rng.choice(POOL)
    if kind < 0.4:
        return rng.choice(NUMBERS[:7] if rng.random() < 0.9 else NUMBERS)
    if kind < 0.5:
        return rng.choice([sp.sin, sp.cos, sp.exp, sp.Abs])(_expression(rng, depth + 1))
    if kind < 0.6:
        return _expression(rng, depth + 1) ** rng.choice([2, 3, -1, sp.Rational(1, 2)])
    if kind < 0.75:
        return sp.Add(*(_expression(rng, depth + 1) for _ in range(rng.randint(2, 4))))
    if kind < 0.8:
        return sp.Mul(rng.choice([2, -1, sp.Rational(1, 3)]), _expression(rng, depth + 1), evaluate=False)
    if kind < 0.85:
        return rng.choice([a, b]) * rng.choice(POOL)
    return sp.Mul(*(_expression(rng, depth + 1) for _ in range(rng.randint(2, 3))))


@settings(max_examples=400, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12))
def test_total_is_sympys_add(seed, count):
    rng = random.Random(seed)
    terms = [_expression(rng) for _ in range(count)]
    terms += rng.sample(terms, min(2, len(terms)))      # like terms to collect
    terms += [product(rng.choice(POOL), t) for t in terms[:2]]
    ours, theirs = total(terms), sp.Add(*terms)
    assert ours == theirs and type(ours) is type(theirs), terms
    assert ours.args == theirs.args, terms
    assert ours.is_commutative == theirs.is_commutative
    minus, theirs = negative(ours), -theirs
    assert minus == theirs and minus.args == theirs.args and type(minus) is type(theirs), terms


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 30))
def test_sort_key_orders_as_compare(seed, count):
    rng = random.Random(seed)
    exprs = [_expression(rng) for _ in range(count)]
    ours, theirs = list(exprs), sorted(exprs, key=functools.cmp_to_key(sp.Basic.compare))
    sort_args(ours)
    assert ours == theirs and [type(e) for e in ours] == [type(e) for e in theirs]
    for u, v in zip(exprs, exprs[1:]):
        c = u.compare(v)
        assert (sort_key(u) > sort_key(v)) - (sort_key(u) < sort_key(v)) == c, (u, v)


def test_mass_matrix_entry():
    """The chain's mass matrix entries: 100 masses times one dot product."""
    X = q1 * sp.cos(x) * sp.cos(y) + q1 * sp.sin(x) * sp.sin(y)
    masses = sp.symbols("m1:101")
    terms = [product(m, X) for m in masses]
    assert all(t == sp.Mul(m, X) and t.args == sp.Mul(m, X).args for m, t in zip(masses, terms))
    assert total(terms).args == sp.Add(*terms).args


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_difference_is_sympys_minus(seed):
    """total([a, negative(b)]) is sympy's a - b (= Add(a, -b)): the equations' M q'' - F.
    Terms evaluated (`doit`): an unevaluated c*x (sympy.Mul(..., evaluate=False)) is never
    in a derivation, and sympy's own `-` leaves it unevaluated where `total` need not."""
    rng = random.Random(seed)
    a, b = (sp.Add(*(_expression(rng).doit() for _ in range(rng.randint(1, 5)))) for _ in range(2))
    ours, theirs = total([a, negative(b)]), a - b
    assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), (a, b)


@settings(max_examples=400, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_pairs_sort_as_compare(seed):
    """Two expressions (leaves and nodes of leaves are ordered by their keys) in compare's order."""
    rng = random.Random(seed)
    pair = [_expression(rng, depth=rng.choice([2, 3])) for _ in range(2)]
    ours, theirs = list(pair), sorted(pair, key=functools.cmp_to_key(sp.Basic.compare))
    sort_args(ours)
    assert ours == theirs and [type(e) for e in ours] == [type(e) for e in theirs], pair


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 6))
def test_dot_is_sympys_matrix_dot(seed, n):
    """`dot(u, w)` is sympy's Matrix.dot: V's g . r and T1 = a . q'."""
    rng = random.Random(seed)
    commutative = [e for e in POOL if e.is_commutative]

    def entry():
        kind = rng.random()
        if kind < 0.3:
            return sp.S.Zero
        if kind < 0.6:
            return rng.choice(NUMBERS[:7]) * rng.choice(commutative)
        return sp.Add(*(product(rng.choice(NUMBERS[:5]), rng.choice(commutative), rng.choice(POOL[8:10]))
                        for _ in range(rng.randint(1, 6))))
    u, w = [entry() for _ in range(n)], [entry() for _ in range(n)]
    ours, theirs = dot(u, w), sp.Matrix(u).dot(sp.Matrix(w))
    assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), (u, w)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_negated_terms_sum_to_sympys_minus(seed):
    """total([*terms of a, *negated_terms(b)]) is sympy's a - b, like terms and all (the
    equations' M q'' - F and F's -dV, each sorted once)."""
    rng = random.Random(seed)
    commutative = [e for e in POOL if e.is_commutative]

    def term():      # evaluated products and powers (sympy's own canonical forms)
        factors = [rng.choice(NUMBERS[:5])] + [rng.choice(commutative) for _ in range(rng.randint(0, 3))]
        if rng.random() < 0.3:
            factors.append(sp.Add(*(rng.choice(commutative) for _ in range(3))))
        return sp.Mul(*factors)
    a = [term() for _ in range(rng.randint(0, 5))]
    b = sp.Add(*(term() for _ in range(rng.randint(0, 6))))
    ours, theirs = total([*a, *negated_terms(b)]), sp.Add(*a) - b
    assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), (a, b)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_scaled_is_sympys_product_with_a_number(seed):
    """`scaled(c, e)` is sympy's c*e: a sum distributed term by term (T2 = 1/2 (...)), a sum
    with a number of its own (2*(x + y)), a non-sum and any other number left to sympy."""
    rng = random.Random(seed)
    number = rng.choice(NUMBERS[:5] + [sp.Integer(-2), sp.Rational(5, 3)])
    expr = _expression(rng)
    if rng.random() < 0.6:
        expr = sp.Add(*(_expression(rng, 1) for _ in range(rng.randint(2, 5))))
    ours, theirs = scaled(number, expr), number * expr
    assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), (number, expr)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_negative_is_sympys_minus(seed):
    """`negative(b)` is sympy's -b, a sum of products without numbers (kept in its order)
    and any other sum (summed again) alike."""
    rng = random.Random(seed)
    commutative = [e for e in POOL if e.is_commutative]

    def term():
        factors = [rng.choice(commutative) for _ in range(rng.randint(1, 3))]
        if rng.random() < 0.2:
            factors.append(rng.choice(NUMBERS[:5]))
        if rng.random() < 0.2:
            factors.append(sp.Add(*(rng.choice(commutative) for _ in range(2))))
        return sp.Mul(*factors)
    b = sp.Add(*(term() for _ in range(rng.randint(1, 8))))
    ours, theirs = negative(b), -b
    assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), b


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_sort_keyed_is_sort_args(seed):
    """`sort_keyed` (the arguments' leaf keys given) orders as `sort_args` and compare do."""
    from lagcli.model.ordering import leaf_key, sort_keyed
    rng = random.Random(seed)
    args = list(dict.fromkeys(_expression(rng, depth=rng.choice([1, 2, 3])) for _ in range(rng.randint(1, 10))))
    ours, theirs = list(args), sorted(args, key=functools.cmp_to_key(sp.Basic.compare))
    sort_keyed(ours, [leaf_key(a) for a in ours])
    assert ours == theirs and [type(e) for e in ours] == [type(e) for e in theirs], args


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_two_products_are_sympys_add(seed):
    """The sum of two products (a chain's dot products: `total`'s two-term path) is sympy's
    Add, like products (2*a), products with numbers and the chain's own alike."""
    rng = random.Random(seed)
    l1, l2, q1, q2 = sp.symbols("l1 l2 q1 q2", real=True)
    chain = [product(l1 * sp.cos(q1), l2 * sp.cos(q2)), product(l1 * sp.sin(q1), l2 * sp.sin(q2)),
             product(l1 * sp.cos(q1), l1 * sp.cos(q1)), l1 * l2 * sp.sin(q1 - q2)]

    def term():
        if rng.random() < 0.3:
            return rng.choice(chain)
        factors = [_expression(rng, depth=2) for _ in range(rng.randint(2, 3))]
        if rng.random() < 0.2:
            factors.append(rng.choice(NUMBERS[:7]))
        return sp.Mul(*factors)
    a = term()
    b = a if rng.random() < 0.2 else term()
    for terms in ([a, b], [b, a]):
        ours, theirs = total(terms), sp.Add(*terms)
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), terms


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_negative_with_remembered_terms_is_sympys_minus(seed):
    """`negative(b, negated)` is sympy's -b however many sums share the memo `negated`,
    and a term of a sum of products without numbers, met again, is negated to the object
    made the first time."""
    rng = random.Random(seed)
    commutative = [e for e in POOL if e.is_commutative]
    terms = [sp.Mul(*(rng.choice(commutative) for _ in range(rng.randint(2, 3)))) for _ in range(8)]
    negated: dict = {}
    for _ in range(4):
        b = sp.Add(*rng.sample(terms, rng.randint(1, 6)))
        ours, theirs = negative(b, negated), -b
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), b
        if b.is_Add and all(t.is_Mul and not t.args[0].is_Number for t in b.args):    # the chain's sums
            again = negative(b, negated)
            assert all(x is y for x, y in zip(again.args, ours.args))


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_scaled_sum_of_products_is_sympys(seed):
    """`scaled(c, b)` of a sum of products without numbers (T2 = 1/2 (q1'*M_1j*q_j' + ...):
    kept in its order, not sorted again) is sympy's c*b."""
    rng = random.Random(seed)
    commutative = [e for e in POOL if e.is_commutative]

    def term():
        factors = [rng.choice(commutative) for _ in range(rng.randint(1, 4))]
        if rng.random() < 0.2:
            factors.append(sp.Add(*(rng.choice(commutative) for _ in range(2))))
        return sp.Mul(*factors)
    number = rng.choice([sp.Rational(1, 2), sp.Integer(2), sp.Integer(-1), sp.Rational(-3, 4)])
    b = sp.Add(*(term() for _ in range(rng.randint(2, 10))))
    ours, theirs = scaled(number, b), number * b
    assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), (number, b)
