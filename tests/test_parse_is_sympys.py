"""The safe parser (lagcli/model/expr.py) builds the very expression Python's own evaluation
of the text with sympy objects builds: products through `products.product`, sin and cos of
plain angles through `angle_calls.trig_call`, negated sums with their terms remembered
(`sums.negative`), all tested here against sympy's own arithmetic on the same text, in
one scope parsing text after text as a spec's positions are parsed."""
import random

import sympy as sp
from sympy.parsing.sympy_parser import auto_number, parse_expr, rationalize

from lagcli.errors import Loc
from lagcli.model.expr import Scope, parse

NAMES = ["x", "y", "z", "l1", "l2", "q1", "q2", "q10", "m1"]
SYMBOLS = {name: sp.Symbol(name, real=True) for name in NAMES}


def _text(rng, depth=0) -> str:
    kind = rng.random()
    if depth > 3 or kind < 0.25:
        return rng.choice(NAMES + ["2", "0.5", "3", "1"])
    if kind < 0.45:
        return "*".join(_text(rng, depth + 1) for _ in range(rng.randint(2, 3)))
    if kind < 0.65:
        return " + ".join(_text(rng, depth + 1) for _ in range(rng.randint(2, 5)))
    if kind < 0.75:
        return f"-({_text(rng, depth + 1)})"
    if kind < 0.9:
        angle = rng.choice(["q1", "q2", "q2 - q1", "-q1", "q1 + q10", "2*q1 - q2", _text(rng, depth + 1)])
        return f"{rng.choice(['sin', 'cos'])}({angle})"
    return f"({_text(rng, depth + 1)})*({_text(rng, depth + 1)})"


def _chain_terms(rng) -> list[str]:
    """A chain's position: l_k*sin(q_k) terms, some negated sums of them."""
    terms = [f"{rng.choice(['l1', 'l2', 'm1'])}*{rng.choice(['sin', 'cos'])}({rng.choice(['q1', 'q2', 'q10'])})"
             for _ in range(rng.randint(1, 6))]
    return terms


def test_parse_is_pythons_sympy_arithmetic():
    rng = random.Random(20261128)
    scope = Scope(SYMBOLS, sp.Symbol("t"))
    for _ in range(1500):
        if rng.random() < 0.3:
            text = " + ".join(_chain_terms(rng))
            text = f"-({text})" if rng.random() < 0.5 else text
        else:
            text = _text(rng)
        ours = parse(text, scope, Loc("test"))
        theirs = parse_expr(text, local_dict=dict(SYMBOLS), transformations=(auto_number, rationalize))   # 0.5 -> 1/2, as the spec language
        assert ours == theirs and ours.args == theirs.args and type(ours) is type(theirs), text
