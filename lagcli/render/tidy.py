"""Tidying one expression before CSE: the cheapest of a few equivalent forms.

Only an optimisation of generated code (fewer operations at run time); every step
is bounded by the size of its input (operation counts, never a clock, so the same
spec gives the same code on any machine), and an expression no step improves stays
as it was.
"""
from __future__ import annotations

import functools
import math

import sympy as sp
from sympy.core.mul import _keep_coeff

from lagcli.model.angle_calls import trig_call
from lagcli.model.calculus import distinct_nodes
from lagcli.model.expansion import expanded as expand     # sympy.expand, faster on polynomials
from lagcli.model.products import product
from lagcli.model.sums import total
from lagcli.render.operations import count_ops

TIDY_MAX_OPS = 80             # rewrite trigonometry only in expressions this small (bench/codegen.py)
COLLECT_MAX_NODES = 5000      # expand + collect only expressions this small (tree nodes)
COLLECT_MAX_TERMS = 500       # ... and with at most this many terms expanded (`expanded_terms`)
MAX_POWER = 6                 # (a + b)**1000 counts as small, but expanding it would not be
MAX_EXPANDED_TERMS = 20000    # expand only what has at most this many terms once expanded
TRIGSIMP_FUNCTIONS = (sp.sin, sp.cos)   # rewrite only expressions calling nothing else
PRINTABLE = (sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.atan2, sp.sinh, sp.cosh,
             sp.tanh, sp.exp, sp.log, sp.Abs, sp.sign, sp.Min, sp.Max)


def tidy_expression(expr, velocities=(), cache: dict | None = None) -> sp.Expr:
    """The cheapest (sympy.count_ops) of: expr; expr expanded and collected over the
    `velocities`, each coefficient collected over its function calls (`collected`: the
    physical grouping of F = sum c_jk q'_j q'_k + c_j q'_j + c_0); and `display_form`
    (the reports' linear-time exact rewritings: sin^2 + cos^2 = 1, angle sums, common
    factors) of the better of these two when it has at most TIDY_MAX_OPS operations
    and calls only sin and cos (`trigsimp_safe`). A candidate may not call a function
    expr does not already call: a new cos(q1 - q2) costs more at run time than the
    multiplications it saves. Every step is bounded by sizes only: expressions over
    COLLECT_MAX_NODES tree nodes, with high powers or over COLLECT_MAX_TERMS terms
    expanded are left as they are (expanding costs time in proportion to the terms,
    and the CSE shares the parts of big expressions better than it shares the terms
    of their expansions)."""
    expr = sp.sympify(expr)
    if cache is not None and expr in cache:
        return cache[expr]
    result = expr
    if not expr.is_Atom and small(expr, COLLECT_MAX_NODES) and not has_high_power(expr) \
            and expanded_terms(expr) <= COLLECT_MAX_TERMS:
        calls = calls_in(expr)
        result = _cheaper(expr, collected(expr, velocities), calls)
        if count_ops(result) <= TIDY_MAX_OPS and trigsimp_safe(result):
            result = _cheaper(result, display_form(result), calls)
    if cache is not None:
        cache[expr] = result
    return result


def trigsimp_safe(expr) -> bool:
    """True when expr is built from numbers, symbols, +, * and powers, and calls only
    sin and cos: what trigsimp is meant for (and fast on)."""
    for node in distinct_nodes(expr):
        if node.is_Atom or node.is_Add or node.is_Mul or isinstance(node, TRIGSIMP_FUNCTIONS):
            continue
        if node.is_Pow and node.exp.is_Rational:
            continue
        return False
    return True


def has_high_power(expr) -> bool:
    """(a + b)**1000 counts as small, but expanding or trigsimp-ing it would not be."""
    return any(p.exp.is_Number and abs(p.exp) > MAX_POWER for p in expr.atoms(sp.Pow))


def expandable(expr) -> bool:
    """True when `sympy.expand(expr)` stays small: no high power and at most
    MAX_EXPANDED_TERMS terms by the bound `expanded_terms` (a product of ten sums of
    ten terms is small to write and 10**10 terms expanded)."""
    return not has_high_power(expr) and expanded_terms(expr) <= MAX_EXPANDED_TERMS


def weighted_expandable(count: int, shared) -> bool:
    """`expandable` of a sum of `count` products w_k * shared, w_k symbols (a flat weighted
    sum: `render.weighted`), from `shared` alone: the sum's powers are shared's, and each
    term expands to as many terms as shared (tests/test_report_shared_terms.py)."""
    return not has_high_power(shared) and count * expanded_terms(shared) <= MAX_EXPANDED_TERMS


def expanded_terms(expr) -> int:
    """An upper bound on the number of terms of expr expanded (function arguments,
    which expand inside their call, count as one term each)."""
    if expr.is_Add:
        return sum(expanded_terms(a) for a in expr.args)
    if expr.is_Mul:
        count = 1
        for factor in expr.args:
            count *= expanded_terms(factor)
            if count > MAX_EXPANDED_TERMS:
                return count
        return count
    if expr.is_Pow and expr.exp.is_Integer and expr.exp > 1:
        return expanded_terms(expr.base) ** min(int(expr.exp), MAX_POWER + 1)
    return 1


def collected(expr, velocities) -> sp.Expr:
    """expr expanded, its terms grouped by their monomial in the `velocities`, each
    coefficient grouped by its product of function calls with common factors pulled
    out: what `sympy.collect(expand(expr), velocities, func=lambda c:
    factor_terms(collect(c, calls)))` gives, in one pass over the terms (sympy's
    collect substitutes term by term, quadratic in their number)."""
    velocities = frozenset(velocities)
    expanded = expr if is_expanded(expr) else expand(expr)
    by_velocity = grouped_terms(expanded, lambda base: base in velocities)
    return total([product(monomial, factored(_grouped_by_calls(total(coefficients))))
                  for monomial, coefficients in by_velocity.items()])


def _grouped_by_calls(expr) -> sp.Expr:
    by_call = grouped_terms(expr, lambda base: isinstance(base, sp.Function))
    return total([product(calls, factored(total(coefficients))) for calls, coefficients in by_call.items()])


def grouped_terms(expr, in_key) -> dict:
    """{key: [coefficient, ...]} of the terms of the sum expr, key the product of each
    term's factors whose base satisfies `in_key`, coefficient the product of the others
    (term = key * coefficient), keys in order of first appearance. Sums and products
    here and in `collected` are built by `sums.total` and `products.product` (sympy's
    Add and Mul, the same expressions, without their general flatten)."""
    groups: dict = {}
    for term in sp.Add.make_args(expr):
        key, rest = [], []
        for factor in sp.Mul.make_args(term):
            (key if in_key(factor.as_base_exp()[0]) else rest).append(factor)
        groups.setdefault(product(*key), []).append(product(*rest))
    return groups


def factored(expr, memo: dict | None = None) -> sp.Expr:
    """expr with the common factors of every sum pulled out, inner sums first: the
    content (gcd of the numerators over the lcm of the denominators when no term has
    an integer coefficient, negated when every term is negative) and the powers every
    term has, of one sign (x**2*y + x**3 -> x**2*(x + y), y/x + z/x**2 -> (x*y + z)/x**2).
    What sympy's `factor_terms` gives on the sums of a mechanical system, in one pass
    over the distinct subexpressions (`memo`; factor_terms' gcd_terms costs
    milliseconds per sum and is the whole time of sympy.cse's 'basic' preprocessing
    on a bicycle-sized system)."""
    if expr.is_Atom:
        return expr
    memo = {} if memo is None else memo
    found = memo.get(expr)
    if found is None:
        node = _distributed(expr) if expr.is_Mul else expr
        args = tuple(factored(a, memo) for a in node.args)
        found = node if args == node.args else _rebuilt(node, args)
        if found.is_Add:
            found = _common_factor_out(found)
        memo[expr] = found
    return found


def _rebuilt(node, args) -> sp.Expr:
    """`node.func(*args)`, sums and products built by `total` and `product` (the same expressions)."""
    if node.is_Add:
        return total(args)
    if node.is_Mul:
        return product(*args)
    return node.func(*args)


def _distributed(mul) -> sp.Expr:
    """A number times one sum, unevaluated (sympy.cse writes -(b - a) as 1*-1*(b - a)),
    with the number multiplied into the sum, as factor_terms does before it factors."""
    factors = [f for f in mul.args if f is not sp.S.One]
    if len(factors) == 2 and factors[0].is_Number and factors[1].is_Add:
        return sp.Mul(*factors)
    return mul


def _common_factor_out(add) -> sp.Expr:
    """content * common powers * (the sum divided by them), or `add` when nothing is common."""
    split = []
    for term in add.args:
        number, rest = term.as_coeff_Mul()
        powers: dict = {}           # base -> exponent, a Python int (no sympy arithmetic)
        for factor in sp.Mul.make_args(rest):
            base, exponent = factor.as_base_exp()
            if not exponent.is_Integer:     # sqrt(x) and x share nothing (factor_terms' radical=False)
                base, exponent = factor, 1
            powers[base] = powers.get(base, 0) + int(exponent)
        split.append((number, powers))
    common = dict(split[0][1])
    for _, powers in split[1:]:
        common = {base: common_exponent(e, powers[base]) for base, e in common.items() if base in powers}
        common = {base: e for base, e in common.items() if e != 0}
    content = numeric_content([number for number, _ in split])
    if content == 1 and not common:
        return add
    # sympy's Add and Mul, the same expressions (lagcli.model.sums, .products): the flatten
    # of these products was most of the CSE's preprocessing of a 10-link chain's code
    primitive = total([product(number / content, product(*(_power(b, e - common.get(b, 0)) for b, e in powers.items())))
                       for number, powers in split])
    return _keep_coeff(content, product(product(*(_power(b, e) for b, e in common.items())), primitive), clear=True, sign=True)


def _power(base, exponent: int) -> sp.Expr:
    """base ** exponent (base itself for 1, as sympy's Pow gives it, without building the Pow)."""
    return base if exponent == 1 else base ** exponent


def common_exponent(a, b):
    """The power of a base both terms share: the smaller one when both are of one sign, else 0."""
    if a > 0 and b > 0:
        return min(a, b)
    if a < 0 and b < 0:
        return max(a, b)
    return 0


def numeric_content(numbers) -> sp.Rational:
    """The numeric content of terms with these coefficients, as sympy's factor_terms
    (clear=False) takes it; 1 when one is not rational."""
    if not all(n.is_Rational for n in numbers):
        return sp.S.One
    numerator, denominator = 0, 1
    for number in numbers:
        numerator = math.gcd(numerator, abs(number.p))
        denominator = math.lcm(denominator, number.q)
    content = sp.Rational(numerator, denominator if all(n.q != 1 for n in numbers) else 1)
    return -content if all(n.is_negative for n in numbers) else content


def _cheaper(current, candidate, calls) -> sp.Expr:
    """candidate when it has fewer operations and calls only known functions among `calls`."""
    found = calls_in(candidate)
    if found <= calls and all(isinstance(f, PRINTABLE) for f in found) \
            and count_ops(candidate) < count_ops(current):
        return candidate
    return current


# -- display (reports): small parts tidied once, big expressions assembled from them -----

DISPLAY_MAX_NODES = 400       # tidy for display only expressions this small (tree nodes)


def small(expr, budget: int = DISPLAY_MAX_NODES) -> bool:
    """True when expr (or a list of expressions, together) has at most `budget` tree
    nodes, as `sympy.preorder_traversal` counts them (`tree_size`)."""
    total = 0
    for e in (expr if isinstance(expr, list) else [expr]):
        total += tree_size(e, budget - total)
        if total > budget:
            return False
    return True


_SIZES: dict = {}          # expression -> its tree size (`tree_size`), bounded
_SIZES_KEPT = 1 << 17


def tree_size(expr, cap: int) -> int:
    """The number of nodes `sympy.preorder_traversal(expr)` visits, or some number above
    `cap` once it passes it (stops there: cheap on the megabyte expressions of a big
    system). Each distinct subexpression is counted once and remembered: a mass matrix
    entry m_1 X + ... + m_n X has n copies of X, which the traversal walked n times."""
    found = _SIZES.get(expr)
    if found is not None:
        return found
    total = 1
    for arg in (expr._argset if hasattr(expr, "_argset") else expr.args):
        size = _SIZES.get(arg)      # a known child without a call
        total += tree_size(arg, cap - total) if size is None else size
        if total > cap:
            return total
    if len(_SIZES) >= _SIZES_KEPT:
        _SIZES.clear()
    _SIZES[expr] = total
    return total


def display_form(expr) -> sp.Expr:
    """A tidier, equal form of a small expr for reports, by a fixed sequence of cheap
    exact rewritings: expand; the Pythagorean identity (`pythagorean`); angle sums
    folded (`fold_angle_sums`: a sin x sin y + a cos x cos y -> a cos(x - y)); terms
    grouped by their function calls with common factors pulled out (`group_by_calls`);
    signs pulled out (`pull_signs`). The original is kept when the result has more
    operations. Every step is linear or nearly so in the number of terms: no trigsimp
    (~1 s per expression) nor fu's TR10i (pairwise, ~50 ms per sum); an expression
    over DISPLAY_MAX_NODES nodes or with a big expansion is returned as it is
    (reports assemble big expressions from tidied parts instead)."""
    expr = sp.sympify(expr)
    if expr.is_Atom or sum_of_symbols(expr) or not small(expr) or not expandable(expr):
        return expr      # a sum of symbols (a chain's m_k + ... + m_n): every step keeps it
    return display_steps(expr)


def display_steps(expr) -> sp.Expr:
    """`display_form`'s steps on a small expr."""
    grouped = expr if separate_calls(expr) else _grouped_calls(expr)
    result = pull_signs(common_factor(grouped))
    return result if count_ops(result) <= count_ops(expr) else pull_signs(expr)


def _grouped_calls(expr) -> sp.Expr:
    """`display_form`'s steps before the common factors: expand, the Pythagorean identity,
    angle sums folded, terms grouped by their calls."""
    result = expr if is_expanded(expr) else expand(expr)
    if result.has(sp.sin, sp.cos):
        result = fold_angle_sums(pythagorean(result))
    return group_by_calls(result)


def separate_calls(expr) -> bool:
    """expr is a sum whose every term is a rational number times symbols (and positive
    integer powers of them) times one sin or cos of a symbol, a different call in each
    term (the sums of a chain's potential, l1 cos(q1) + ... + lk cos(qk)): `_grouped_calls`
    gives such a sum back as it is (it is expanded; no sin or cos is squared, no term
    has two to fold; each group of calls is one term, its coefficient tidy already).
    tests/test_tidy_separate_calls.py compares both ways."""
    if not expr.is_Add or not expr.is_commutative:
        return False
    calls = set()
    for term in expr.args:
        call = _single_call(term)
        if call is None or call in calls:
            return False
        calls.add(call)
    return True


def _single_call(term):
    """The one factor sin(x) or cos(x), x a symbol, of a term c * symbols * that call; else None."""
    if not term.is_Mul:
        return None
    call = None
    for factor in term.args:
        if type(factor) in (sp.sin, sp.cos):
            if call is not None or not factor.args[0].is_Symbol:
                return None
            call = factor
        elif not (factor.is_Rational or factor.is_Symbol
                  or (factor.is_Pow and factor.base.is_Symbol and factor.exp.is_Integer and factor.exp > 0)):
            return None
    return call


def sum_of_symbols(expr) -> bool:
    """expr is a sum of symbols, each with the coefficient 1."""
    return expr.is_Add and all(term.is_Symbol for term in expr.args)


LINEAR_CALLS = (sp.sin, sp.cos, sp.tan)   # expand leaves f(a - b) alone (no expand_trig)


def is_expanded(expr) -> bool:
    """True when `sympy.expand(expr)` is expr itself, recognised cheaply for the common case:
    a sum of products of numbers, symbols, integer powers of them and sin/cos/tan of sums
    of symbols with integer coefficients (the mass matrix's entries)."""
    return all(_plain_factor(f) for term in sp.Add.make_args(expr) for f in sp.Mul.make_args(term))


def _plain_factor(factor) -> bool:
    if factor.is_Atom:
        return True
    if factor.is_Pow:
        return factor.exp.is_Integer and (factor.base.is_Symbol or _plain_call(factor.base))
    return _plain_call(factor)


def _plain_call(call) -> bool:
    if not isinstance(call, LINEAR_CALLS):
        return False
    for term in sp.Add.make_args(call.args[0]):
        number, rest = term.as_coeff_Mul()
        if not (number.is_Integer and (rest.is_Symbol or rest == 1)):
            return False
    return True


def group_by_calls(expr) -> sp.Expr:
    """sum over distinct products of function calls f of (common factors pulled out of
    the sum of their coefficients) * f: `sympy.collect` over the calls, in one pass."""
    groups: dict = {}     # the calls (in the canonical order of a product's factors) -> coefficients
    for term in sp.Add.make_args(expr):
        calls, rest = _calls_and_rest(term)
        groups.setdefault(calls, []).append(rest)
    return total([_grouped_term(common_factor(total(coefficients)), calls) for calls, coefficients in groups.items()])


@functools.lru_cache(maxsize=1 << 15)     # a chain's potential: l_1 cos(q_1) in the sums of every mass
def _calls_and_rest(term) -> tuple:
    """(the factors of term calling a function, the product of the others)."""
    calls, rest = [], []
    for factor in sp.Mul.make_args(term):
        (calls if factor.has(sp.Function) else rest).append(factor)
    return tuple(calls), product(*rest)


@functools.lru_cache(maxsize=1 << 15)
def _grouped_term(coefficient, calls: tuple) -> sp.Expr:
    """coefficient * the calls (`group_by_calls`' terms; most recur in the next sum of a chain's potential)."""
    return product(coefficient, product(*calls))


@functools.lru_cache(maxsize=1 << 15)     # the sums of masses of a chain recur in every entry
def common_factor(expr) -> sp.Expr:
    """`sympy.factor_terms(expr)`, the same expression, computed directly (several times
    faster) for the sums the reports tidy: terms that are a rational number times
    positive integer powers of symbols and function calls. The content pulled out is
    the terms' common powers times the gcd of their numerators, over the lcm of their
    denominators when no coefficient is an integer (factor_terms' `clear=False`).
    Anything else goes to factor_terms itself."""
    if expr.is_Atom:
        return expr
    if not expr.is_Add:    # factor_terms works inside: when that changes nothing, neither do we
        unchanged = all(common_factor(a) == a for a in expr.args)
        return expr if unchanged else sp.factor_terms(expr)
    if _signed_symbols(expr):
        return expr        # distinct symbols, each times 1 or -1, not all -1: nothing in common
    split = []
    for term in expr.args:
        found = _number_and_powers(term)
        if found is None:
            return sp.factor_terms(expr)
        split.append(found)
    common = dict(split[0][1])
    for _, powers in split[1:]:
        common = {base: min(e, powers[base]) for base, e in common.items() if base in powers}
    numerator, denominator = 0, 1
    for number, _ in split:
        numerator = math.gcd(numerator, abs(number.p))
        denominator = math.lcm(denominator, number.q)
    content = sp.Rational(numerator, denominator if all(n.q != 1 for n, _ in split) else 1)
    if all(number.is_negative for number, _ in split):
        content = -content
    if common:
        primitive = total([product(number / content, product(*(_power(b, e - common.get(b, 0)) for b, e in powers.items())))
                           for number, powers in split])
    else:
        primitive = total([_divided(term, content) for term in expr.args])
    return _keep_coeff(content, product(product(*(_power(b, e) for b, e in common.items())), primitive),
                       clear=True, sign=True)


@functools.lru_cache(maxsize=1 << 15)    # a chain's potential: its sums share their terms
def _number_and_powers(term) -> tuple | None:
    """(rational number, {base: positive integer exponent}) of a term of `common_factor`'s
    kind, None for any other term. The dict is shared: read it, never change it."""
    number, rest = term.as_coeff_Mul()
    if not number.is_Rational:
        return None
    powers: dict = {}
    for factor in sp.Mul.make_args(rest):
        base, exponent = factor.as_base_exp()
        if not (exponent.is_Integer and exponent > 0) or base.is_Number:
            return None
        powers[base] = powers.get(base, 0) + int(exponent)
    return number, powers


@functools.lru_cache(maxsize=1 << 15)
def _divided(term, content) -> sp.Expr:
    """term / content rebuilt as `common_factor` rebuilds it when no power is common."""
    number, powers = _number_and_powers(term)
    return product(number / content, product(*(_power(b, e) for b, e in powers.items())))


def _signed_symbols(add) -> bool:
    """add is a sum of symbols and negated symbols (q1 - q2), not all negated."""
    positive = False
    for term in add.args:
        if term.is_Symbol:
            positive = True
        elif not (term.is_Mul and len(term.args) == 2 and term.args[0] is sp.S.NegativeOne
                  and term.args[1].is_Symbol):
            return False
    return positive


def _power(base, exponent: int) -> sp.Expr:
    """base ** exponent, without building a power for the exponents 0 and 1."""
    return base if exponent == 1 else sp.S.One if exponent == 0 else base ** exponent


_ANGLE_SUMS = {   # (kinds of the two terms) -> (ratio of their coefficients, function, sign of y)
    ("cc", "ss"): ((1, sp.cos, -1), (-1, sp.cos, 1)),
    ("sc", "cs"): ((1, sp.sin, 1), (-1, sp.sin, -1)),
}


def fold_angle_sums(expr) -> sp.Expr:
    """In an expanded sum, c cos x cos y + c sin x sin y -> c cos(x - y),
    c cos x cos y - c sin x sin y -> c cos(x + y), c sin x cos y + c cos x sin y ->
    c sin(x + y) and c sin x cos y - c cos x sin y -> c sin(x - y): fu's TR10i for the
    pairs of a mechanical system's dot products, found by a dictionary in one pass."""
    slots: dict = {}
    others = []
    for term in sp.Add.make_args(expr):
        split = _two_angles(term)
        if split is None:
            others.append(term)
            continue
        kind, x, y, number, rest = split
        slots.setdefault((x, y, rest), {}).setdefault(kind, []).append(number)
    out, folded = list(others), False
    for (x, y, rest), kinds in slots.items():
        for (first, second), rules in _ANGLE_SUMS.items():
            a, b = kinds.get(first, []), kinds.get(second, [])
            while a and b:
                for ratio, function, sign in rules:
                    if b[0] == ratio * a[0]:
                        out.append(product(product(a[0], rest), trig_call(function, x + sign * y)))
                        a.pop(0), b.pop(0)
                        folded = True
                        break
                else:
                    break
        out += [number * rest * _KINDS[kind](x, y) for kind, numbers in kinds.items() for number in numbers]
    return total(out) if folded else expr     # nothing folded: the same terms, not re-added


_KINDS = {"cc": lambda x, y: sp.cos(x) * sp.cos(y), "ss": lambda x, y: sp.sin(x) * sp.sin(y),
          "sc": lambda x, y: sp.sin(x) * sp.cos(y), "cs": lambda x, y: sp.cos(x) * sp.sin(y)}


def _two_angles(term):
    """(kind, x, y, number, rest) when term = number * rest * f(x) g(y), f, g in {sin, cos}
    to the first power, x before y; None otherwise."""
    number, factors = term.as_coeff_mul()
    trig = [f for f in factors if isinstance(f, (sp.sin, sp.cos))]
    if len(trig) != 2 or trig[0].args[0] == trig[1].args[0]:
        return None
    first, second = sorted(trig, key=lambda f: sp.default_sort_key(f.args[0]))
    rest = product(*(f for f in factors if f not in trig))
    if rest.has(*(trig_call(f, arg) for arg in (first.args[0], second.args[0]) for f in (sp.sin, sp.cos))):
        return None
    kind = ("s" if isinstance(first, sp.sin) else "c") + ("s" if isinstance(second, sp.sin) else "c")
    return kind, first.args[0], second.args[0], number, rest


def pythagorean(expr) -> sp.Expr:
    """expr (expanded) with sin(x)**2 + cos(x)**2 = 1 used for each argument x whose
    sin**2 and cos**2 both appear, in the direction (eliminating sin**2 or cos**2)
    that leaves fewer terms (then fewer distinct powers, then fewer minus signs).
    Repeated while it helps, at most once per argument: one identity can open the way
    for another (sin(b)**2 + cos(b)**2*(sin(c)**2 + cos(c)**2) needs c, then b)."""
    arguments = _square_arguments(expr)
    nested: dict = {}
    for _ in range(len(arguments)):
        before = expr
        for x in arguments:
            options = [expr, _eliminate_square(expr, sp.sin(x), sp.cos(x), nested),
                       _eliminate_square(expr, sp.cos(x), sp.sin(x), nested)]
            expr = min(options, key=_pythagorean_cost)
        if expr == before:
            break
        arguments = _square_arguments(expr)
    return expr


def fewest_squares(expr) -> sp.Expr:
    """A sum with sin(x)**2 or cos(x)**2 (one of them is enough, unlike `pythagorean`)
    rewritten by sin**2 + cos**2 = 1 in the direction that leaves fewer terms (then fewer
    powers, fewer minus signs): m + mc - m cos(x)**2 -> mc + m sin(x)**2, the solved forms'
    denominators (lagcli/derive/hamilton_form.py) as a textbook writes them."""
    if not expr.is_Add:
        return expr
    squares = {p.base.args[0] for p in powers_in(expr) if isinstance(p.base, (sp.sin, sp.cos))
               and p.exp.is_Integer and p.exp >= 2}
    for x in sorted(squares, key=sp.default_sort_key):
        options = [expr, _eliminate_square(expr, sp.sin(x), sp.cos(x)), _eliminate_square(expr, sp.cos(x), sp.sin(x))]
        expr = min(options, key=_pythagorean_cost)
    return expr


def _square_arguments(expr) -> list:
    """The arguments x of which both sin(x)**k and cos(x)**l (k, l >= 2) appear in expr."""
    squares = {p.base for p in powers_in(expr) if isinstance(p.base, (sp.sin, sp.cos))
               and p.exp.is_Integer and p.exp >= 2}
    return sorted({f.args[0] for f in squares if f.func(f.args[0]) in squares
                   and (sp.cos if f.func == sp.sin else sp.sin)(f.args[0]) in squares},
                  key=sp.default_sort_key)


def calls_in(expr) -> set:
    """`expr.atoms(sp.Function)`, each distinct subexpression visited once."""
    return {node for node in distinct_nodes(expr) if isinstance(node, sp.Function)}


def powers_in(expr) -> set:
    """expr.atoms(sp.Pow), each distinct subexpression visited once: a big expression
    shares its parts (the frames bicycle's 1/sqrt(S) in hundreds of terms), which
    `atoms` would walk through again at every occurrence."""
    return {node for node in distinct_nodes(expr) if isinstance(node, sp.Pow)}


def _pythagorean_cost(expr) -> tuple[int, int, int]:
    """Fewer terms, then fewer distinct powers, then fewer minus signs."""
    terms = sp.Add.make_args(expr)
    return len(terms), len(powers_in(expr)), sum(t.could_extract_minus_sign() for t in terms)


def _eliminate_square(expr, drop, keep, nested: dict | None = None) -> sp.Expr:
    """drop**k -> drop**(k mod 2) * (1 - keep**2)**(k // 2), expanded. `nested` remembers
    the expanded roots and reciprocals of sums met on the way (`_expanded_term`)."""
    powers = {p for p in powers_in(expr) if p.base == drop and p.exp.is_Integer and p.exp >= 2}
    if not powers:
        return expr
    table = {p: drop ** (int(p.exp) % 2) * total([sp.S.One, -keep ** 2]) ** (int(p.exp) // 2) for p in powers}
    nested = {} if nested is None else nested
    terms = []
    for term in sp.Add.make_args(expr):      # expr is expanded: only terms with a power change
        if not term.has(*powers):
            terms.append(term)
        else:
            terms.extend(_binomial_terms(term, powers, keep)
                         or sp.Add.make_args(_expanded_term(term, table, nested)))
    return total(terms)


def _expanded_term(term, table: dict, nested: dict) -> sp.Expr:
    """sympy.expand(term.xreplace(table)), with each factor of `term` that is a root or
    a reciprocal of a sum (the frames bicycle's front wheel: 1/sqrt(S), S a sum of
    hundreds of terms) expanded once for all the terms that share it and held as a
    symbol meanwhile: expand leaves such a power of an expanded sum as it is, so the
    result is the same, without expanding S again for every term."""
    held, factors = {}, []
    for factor in sp.Mul.make_args(term):
        shown = _nested_power(factor, table, nested)
        if shown is None:
            factors.append(factor.xreplace(table))
        else:
            symbol = held.setdefault(shown, sp.Dummy(f"held{len(held)}", commutative=True))
            factors.append(symbol)
    expanded = sp.expand(sp.Mul(*factors))
    return expanded.xreplace({symbol: shown for shown, symbol in held.items()}) if held else expanded


def _nested_power(factor, table: dict, nested: dict):
    """expand(factor.xreplace(table)) when `factor` is a power of a sum with an exponent
    that expand leaves alone (negative or not an integer, |exponent| <= 1); else None."""
    if not (factor.is_Pow and factor.base.is_Add and factor.exp.is_Rational
            and abs(factor.exp) <= 1 and not (factor.exp.is_Integer and factor.exp > 0)):
        return None
    key = (factor, tuple(sorted(table.items(), key=sp.default_sort_key)))
    if key not in nested:
        nested[key] = sp.expand(factor.xreplace(table))
    shown = nested[key]
    return shown if shown.is_Pow and shown.base.is_Add and shown.exp == factor.exp else None


def _binomial_terms(term, powers, keep) -> list | None:
    """The expansion of a product `rest * drop**e` with drop**2 = 1 - keep**2, written out
    by the binomial theorem: rest * drop**(e % 2) * C(k, i) (-keep**2)**i, i = 0..k, k = e // 2
    (what sympy.expand gives, without its general machinery: that was most of the
    bicycle's report). None when the power is not a plain factor of `term`."""
    factors = sp.Mul.make_args(term)
    found = [f for f in factors if f in powers]
    if len(found) != 1:
        return None
    power = found[0]
    rest = sp.Mul(*(f for f in factors if f is not power))
    if rest.has(*powers):
        return None
    k = int(power.exp) // 2
    base = rest * power.base ** (int(power.exp) % 2)
    return [base * (-1) ** i * math.comb(k, i) * keep ** (2 * i) for i in range(k + 1)]


def pull_signs(expr, memo: dict | None = None) -> sp.Expr:
    """-a*(-b + c) -> a*(b - c): in every product, a sum with more negative than positive
    terms is negated (and the product's sign with it), so no double negative prints.
    `memo` remembers the result for every subexpression (big assembled expressions share
    their parts, and the reports pass the same parts through here more than once)."""
    if expr.is_Atom:
        return expr
    memo = {} if memo is None else memo
    found = memo.get(expr)
    if found is not None:
        return expr if found is _UNCHANGED else found
    args = []
    for a in expr.args:      # each child looked up here first: most are known (a call each cost more)
        known = a if a.is_Atom else memo.get(a)
        args.append(pull_signs(a, memo) if known is None else a if known is _UNCHANGED else known)
    flips = [i for i, a in enumerate(args) if a.is_Add and _mostly_negative(a)] if expr.is_Mul else []
    for i in flips:
        args[i] = -args[i]
    if flips:
        args.append(sp.S.NegativeOne ** len(flips))
        result = expr.func(*args)
    elif all(new is old for new, old in zip(args, expr.args)):
        result = expr        # nothing changed: no need to rebuild (and re-sort) the node
    else:
        result = expr.func(*args)
    # an unchanged node is remembered as such: an equal node met later (not the same object)
    # is then returned itself, and its parents are not rebuilt around an equal copy
    memo[expr] = _UNCHANGED if result is expr else result
    return result


_UNCHANGED = object()


@functools.lru_cache(maxsize=1 << 15)    # a chain's sums of masses stand in thousands of its reports' terms
def _mostly_negative(add) -> bool:
    """More negative terms than positive ones, or as many and the leading one negative."""
    signs = [term.could_extract_minus_sign() for term in add.args]
    negative, positive = sum(signs), len(signs) - sum(signs)
    return negative > positive or (negative == positive and leading_term(add).could_extract_minus_sign())


def leading_term(add) -> sp.Expr:
    """`add.as_ordered_terms()[0]`, the term printed first, found directly for a sum of
    numbers times distinct symbols (q1 - q2, an angle difference: the one with the first
    symbol in sympy's sort order leads); as_ordered_terms builds a polynomial view of the
    sum for that (a third of a big chain's report went into angle differences)."""
    symbols = [term.as_coeff_Mul()[1] for term in add.args]
    if all(s.is_Symbol for s in symbols) and len(set(symbols)) == len(symbols):
        return min(zip(symbols, add.args), key=lambda pair: sp.default_sort_key(pair[0]))[1]
    return add.as_ordered_terms()[0]
