"""`_check_size` (lagcli/model/expr.py) measures the syntax tree with its common nodes taken
apart by their known fields: it refuses the same texts, with the same message, as the plain
walk written here with `ast.iter_child_nodes` itself. The checks of the result, remembered
per subexpression (`_tree_size`, `_unreal`), say what sympy's own walks said."""
import ast
import random

from lagcli.errors import Loc, SpecError
from lagcli.model import expr as E


def _reference(tree, text, loc, limits):
    count, stack = 0, [(tree, 0)]
    while stack:
        node, depth = stack.pop()
        count += 1
        if count > limits.nodes:
            E._fail(loc, f"expression is too large (more than {limits.nodes} terms)")
        if depth > limits.depth:
            E._fail(loc, f"expression is nested too deeply (more than {limits.depth} levels): {E._short(text)!r}")
        stack.extend((child, depth if E._is_sum(node) and child is node.left and E._is_sum(child) else depth + 1)
                     for child in ast.iter_child_nodes(node))


def _text(rng, budget, depth=0):
    budget[0] -= 1
    kind = rng.random()
    if budget[0] < 0 or depth > rng.randint(1, 80) or kind < 0.2:
        return rng.choice(["x", "1", "2.5", "y"])
    if kind < 0.5:
        return " + ".join(_text(rng, budget, depth + 1) for _ in range(rng.randint(2, 30)))
    if kind < 0.7:
        return f"({_text(rng, budget, depth + 1)})*{_text(rng, budget, depth + 1)}"
    if kind < 0.8:
        return f"-({_text(rng, budget, depth + 1)})"
    if kind < 0.9:
        return f"f({_text(rng, budget, depth + 1)}, {_text(rng, budget, depth + 1)})"
    return f"[{_text(rng, budget, depth + 1)}, {_text(rng, budget, depth + 1)}]"


def _verdict(walk, tree, text, limits):
    try:
        walk(tree, text, Loc("x"), limits)
    except SpecError as exc:
        return str(exc)
    return None


def test_size_walk_refuses_what_the_plain_walk_refuses():
    rng, refused = random.Random(20261128), 0
    for _ in range(600):
        text = _text(rng, [rng.choice([20, 200, 2000])])
        try:
            tree = ast.parse(text, mode="eval")
        except (SyntaxError, RecursionError, MemoryError):
            continue
        limits = E.Limits(nodes=rng.choice([50, 500, 5000]), depth=rng.choice([5, 20, 60]))
        expected = _verdict(_reference, tree, text, limits)
        assert _verdict(E._check_size, tree, text, limits) == expected, text
        refused += expected is not None
    assert refused > 100


def _sympy_expression(rng, depth=0):
    import sympy as sp
    x, y = sp.symbols("x y")
    kind = rng.random()
    if depth > 3 or kind < 0.25:
        return rng.choice([x, y, sp.Integer(2), sp.Rational(1, 3), sp.Float(0.5), sp.pi,
                           sp.I, sp.oo, sp.zoo, sp.nan] if rng.random() < 0.2 else [x, y, sp.Integer(3)])
    if kind < 0.5:
        return sp.Add(*(_sympy_expression(rng, depth + 1) for _ in range(rng.randint(2, 5))))
    if kind < 0.7:
        return sp.Mul(*(_sympy_expression(rng, depth + 1) for _ in range(rng.randint(2, 3))))
    if kind < 0.85:
        return rng.choice([sp.sin, sp.cos, sp.exp])(_sympy_expression(rng, depth + 1))
    shared = _sympy_expression(rng, depth + 1)      # one subexpression at two places
    return shared * sp.Symbol("z") + shared ** 2


def test_result_checks_say_what_sympys_walks_say():
    """`_tree_size` (remembered per subexpression) refuses where counting
    `sympy.preorder_traversal` up to the bound refused; `_unreal` is `has(I, zoo, nan, oo)`."""
    import sympy as sp

    def exceeds(expr, limit):     # the check as it was written before the sizes were remembered
        for count, _ in enumerate(sp.preorder_traversal(expr)):
            if count > limit:
                return True
        return False

    rng, sizes, unreal = random.Random(20261128), {}, {}
    for _ in range(400):
        expr = _sympy_expression(rng)
        for limit in (0, 1, 5, 20, 100):
            assert (E._tree_size(expr, sizes) > limit + 1) == exceeds(expr, limit), (expr, limit)
        assert E._unreal(expr, unreal) == expr.has(sp.I, sp.zoo, sp.nan, sp.oo), expr
