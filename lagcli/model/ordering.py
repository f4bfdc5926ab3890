"""sympy's canonical order of terms and factors (`Basic.compare`) as a plain sort key.

`Add` and `Mul` sort their arguments with `cmp_to_key(Basic.compare)`: a Python call per
comparison that walks both trees again, ~5 ms to sort the 100 terms of a mass matrix
entry of the 100-link chain (m_k times the same sum, k = 1..100). `sort_key(e)` is the
same comparison written as nested tuples, built once per distinct subexpression
(remembered) and compared by Python's own tuple comparison:

    compare:  class order (`_cmp_name`), then len(_hashable_content()), then its items
              in turn (Basic items by compare, others by < and >)
    key:      (class key, len(hc), key or value of each item)

so sorting by either gives the same list (both sorts are stable). A node whose
hashable content holds a frozenset (compared as `Basic(*set)`, in the set's order) has
no key: `sort_args` then sorts with `Basic.compare` itself. tests/test_sums_and_ordering.py
compares both on random expressions.

`sort_args` follows the key's order without building whole keys: by class, then length,
then item by item among the arguments still equal, each position's distinct expressions
ordered by `sort_args` itself. Only the items that decide are looked at: the row sums of
a 100-link chain's T2 (q1'*M_1j + q2'*M_2j + ...) keyed every 100-term M_ij whole.
"""
from __future__ import annotations

import functools

from sympy.core.basic import Basic, _args_sortkey as _COMPARE_KEY, ordering_of_classes

FEW = 8        # lists up to this long of leaf-like expressions are sorted by their keys at once
SMALL = 12     # nodes: an expression this small has a `leaf_key` even when it is not made of leaves
_UNKNOWN = len(ordering_of_classes) + 1        # `_cmp_name`'s place of an unlisted class
_PLACE: dict = {}
for _k, _name in enumerate(ordering_of_classes):
    _PLACE.setdefault(_name, _k)               # list.index: the first place


class NoKey(Exception):
    """The expression holds something `sort_key` does not order as compare does."""


@functools.lru_cache(maxsize=1 << 10)
def class_key(cls: type) -> tuple:
    """`_cmp_name` as a key: listed classes by their place, unlisted ones after them by name."""
    name = cls.__name__
    return (_PLACE.get(name, _UNKNOWN), name)


@functools.lru_cache(maxsize=1 << 17)   # shared subexpressions keyed once
def sort_key(expr: Basic) -> tuple:
    """A key ordering expressions as `Basic.compare` does (raises NoKey where it cannot)."""
    return _key(expr)


def _key(expr: Basic) -> tuple:
    """`sort_key` of expr, its parts' keys remembered but not its own: the terms a sum sorts
    are mostly sorted once (the 170 000 terms m_k X of a 100-link chain's mass matrix:
    remembering them pushed the shared X out of the cache)."""
    content = expr._hashable_content()
    parts = [class_key(type(expr)), len(content)]
    for item in content:
        if isinstance(item, Basic):
            parts.append(sort_key(item))
        elif isinstance(item, frozenset):
            raise NoKey(expr)
        else:
            parts.append(item)
    return tuple(parts)


def sort_args(args: list) -> None:
    """Sort `args` in place into sympy's canonical order (what `_addsort`/`_mulsort` do):
    by class first, and by key only among arguments of one class. A product's factors
    are mostly of different classes (m3*cos(q3)*(sum of 100 terms)): keying the sum
    itself walked its terms at every product."""
    if len(args) < 3:      # one comparison (`_pair_out_of_order`)
        _sort_one_class(args)
        return
    if len(args) <= FEW and all(_shallow(a) for a in args):   # the factors of a term: m3, l3, cos(q3)
        try:
            args[:] = sorted(args, key=sort_key)
            return
        except (NoKey, TypeError):
            pass
    classes = [class_key(type(a)) for a in args]
    order = sorted(range(len(args)), key=classes.__getitem__)
    result, start = [], 0
    for end in range(1, len(order) + 1):
        if end == len(order) or classes[order[end]] != classes[order[start]]:
            run = [args[k] for k in order[start:end]]
            if len(run) > 1:
                _sort_one_class(run)
            result += run
            start = end
    args[:] = result


def sort_keyed(args: list, keys: list) -> None:
    """`sort_args(args)` where each argument's `leaf_key` is known (`keys`; None for one
    without): the same order, the keys not found again and nothing walked to find out
    whether an argument is made of leaves (a product's factors: `products.product` looks
    each up once; a 40-term sum of masses among them was walked at every product)."""
    n = len(args)
    if n < 2:
        return
    if n <= FEW and None not in keys:
        try:
            order = sorted(range(n), key=keys.__getitem__)
        except TypeError:      # items of different kinds at one place
            pass
        else:
            args[:] = [args[k] for k in order]
            return
    if n == 2:         # one comparison, of any classes
        if _keyed_pair_out_of_order(args[0], args[1], keys[0], keys[1]):
            args.reverse()
        return
    classes = [class_key(type(a)) for a in args]
    order = sorted(range(n), key=classes.__getitem__)
    result, start = [], 0
    for end in range(1, n + 1):
        if end == n or classes[order[end]] != classes[order[start]]:
            run = order[start:end]
            if len(run) == 2 and _keyed_pair_out_of_order(args[run[0]], args[run[1]], keys[run[0]], keys[run[1]]):
                run.reverse()
            members = [args[k] for k in run]
            if len(run) > 2:
                _sort_one_class(members)
            result += members
            start = end
    args[:] = result


def _keyed_pair_out_of_order(a: Basic, b: Basic, key_a: tuple | None, key_b: tuple | None) -> bool:
    """`_pair_out_of_order(a, b)` with their `leaf_key`s known."""
    if key_a is not None and key_b is not None:
        try:
            return key_b < key_a
        except TypeError:      # items of different kinds at one place
            pass
    return b.compare(a) < 0


def _sort_one_class(args: list) -> None:
    """`sort_args` of arguments of one class (or of two of any classes)."""
    if len(args) < 3:
        if len(args) == 2 and _pair_out_of_order(*args):
            args.reverse()
        return
    try:
        contents = [a._hashable_content() for a in args]
        lengths = [len(c) for c in contents]
        if min(lengths) == max(lengths):
            order = _by_items(list(range(len(args))), contents, 0)
        else:
            order = sorted(range(len(args)), key=lengths.__getitem__)
            order = [k for run in _runs(order, lengths) for k in _by_items(run, contents, 0)]
    except (NoKey, TypeError):    # TypeError: items of different kinds at one place
        args.sort(key=_COMPARE_KEY)
        return
    args[:] = [args[k] for k in order]


def leaf_key(expr: Basic) -> tuple | None:
    """`sort_key(expr)` of an expression of leaves (`_shallow`) or a small one (at most
    SMALL nodes: cos(q1 - q2), which a chain's report multiplies thousands of times; a
    product with an unkeyed factor is sorted class by class), None for a bigger one or
    one without a key: what `sort_args` orders a few such expressions by."""
    if not (_shallow(expr) or _nodes_left(expr, SMALL) >= 0):
        return None
    try:
        return sort_key(expr)
    except NoKey:
        return None


def _pair_out_of_order(a: Basic, b: Basic) -> bool:
    """b before a in compare's order. Expressions of leaves (m3, cos(q3)) by their keys,
    remembered (`sort_key`: compare walked them anew at every product of a chain's dot
    products); bigger ones by compare, which stops at the first difference where a key
    of a new sum walks it whole."""
    if _shallow(a) and _shallow(b):
        try:
            return sort_key(b) < sort_key(a)
        except (NoKey, TypeError):    # TypeError: items of different kinds at one place
            pass
    return b.compare(a) < 0


def _nodes_left(expr: Basic, budget: int) -> int:
    """budget less the number of nodes of expr; negative (not all counted) when it has more."""
    budget -= 1
    for arg in expr.args:
        if budget < 0:
            break
        budget = _nodes_left(arg, budget)
    return budget


def _shallow(expr: Basic) -> bool:
    """A leaf, or a node of leaves."""
    return all(not arg.args for arg in expr.args)


def _by_items(run: list, contents: list, position: int) -> list:
    """`run` (indices of hashable contents of one length, equal before `position`) in the
    order of their items from `position` on: by the place of each item among that
    position's distinct items, then the next position among equal ones. Only the items
    that decide are ordered (keying a sum whole walked every term: q1'*M_1j, q2'*M_2j...
    keyed each 100-term M_ij; the terms of T2 all start with 1/2)."""
    if len(run) < 2 or position == len(contents[run[0]]):
        return run
    items = [contents[k][position] for k in run]
    places = _places(items)
    ordered = sorted(range(len(run)), key=places.__getitem__)
    ranked = [run[k] for k in ordered]
    if len(set(places)) == len(places):      # all different: decided here
        return ranked
    return [k for same in _runs(ranked, dict(zip(run, places))) for k in _by_items(same, contents, position + 1)]


def _places(items: list) -> list:
    """Values ordering `items` (of one position of hashable contents) as compare does;
    equal items get equal values."""
    if any(isinstance(item, frozenset) for item in items):
        raise NoKey(items)
    basic = [isinstance(item, Basic) for item in items]
    if not any(basic):
        return items
    if not all(basic):
        raise TypeError("expressions and other items at one place")
    if not any(item.args for item in items):        # symbols, numbers: small keys, remembered
        return [sort_key(item) for item in items]
    distinct = list(dict.fromkeys(items))
    sort_args(distinct)
    place = {item: k for k, item in enumerate(distinct)}
    return [place[item] for item in items]


def _runs(order: list, value) -> list[list]:
    """`order` cut into runs of equal `value[k]`."""
    runs: list[list] = []
    for k in order:
        if runs and value[runs[-1][-1]] == value[k]:
            runs[-1].append(k)
        else:
            runs.append([k])
    return runs
