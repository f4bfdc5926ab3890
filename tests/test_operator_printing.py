"""Sums and products printed with each precedence found once (lagcli/render/operator_printing.py).

Every target's printer prints random expressions (sums, products, integer and half powers,
negative and rational coefficients, floats, functions; evaluated or built unevaluated as
the big system's CSE builds them) to the same text as sympy's own `parenthesize`,
`_print_Add` and `_print_Mul` under it, in sympy's term order and in the given order
(`in_given_order`, the big system's).
"""
from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st
from sympy.printing.str import StrPrinter

from lagcli.targets.c import CPrinter
from lagcli.targets.casadi import CasadiPrinter
from lagcli.targets.jax import JaxPrinter
from lagcli.targets.octave import OctavePrinter
from lagcli.render.operator_printing import RememberedPrecedence, _generic
from lagcli.targets.python import PythonPrinter
from lagcli.targets.rust import RustPrinter

PRINTERS = [CPrinter, PythonPrinter, OctavePrinter, RustPrinter, JaxPrinter, CasadiPrinter]
SYMBOLS = sp.symbols("a b c d")
TEMPORARIES = sp.numbered_symbols("x", cls=sp.Dummy)
TEMPS = [next(TEMPORARIES) for _ in range(3)]


def table(printer_class) -> dict:
    base, subscript = printer_class.index_base, printer_class.subscript
    slots = {s: subscript.format(array="y", index=k + base) for k, s in enumerate(SYMBOLS)}
    return {**slots, **{s: f"x{k}" for k, s in enumerate(TEMPS)}}


def sympys(printer_class):
    """`printer_class` printing sums and products with sympy's methods under the mixin."""
    after = printer_class.__mro__[printer_class.__mro__.index(RememberedPrecedence) + 1:]

    def sympy_method(name):
        return next(vars(k)[name] for k in after if name in vars(k))

    add, mul = sympy_method("_print_Add"), sympy_method("_print_Mul")
    return type("Sympys" + printer_class.__name__, (printer_class,), {
        "parenthesize": lambda self, item, level, strict=False: StrPrinter.parenthesize(self, item, level, strict),
        "_print_Add": lambda self, expr, order=None: add(self, expr, order=order),
        "_print_Mul": lambda self, expr, **kwargs: mul(self, expr, **kwargs),
    })


nonzero = st.integers(-7, 7).filter(bool)      # zeros inside unevaluated sums break sympy itself
numbers = st.one_of(nonzero.map(sp.Integer),
                    st.tuples(nonzero, st.integers(2, 5)).map(lambda pq: sp.Rational(*pq)),
                    st.sampled_from([sp.Float(0.5), sp.Float(-2.25), sp.pi]))
atoms = st.one_of(st.sampled_from(SYMBOLS + tuple(TEMPS)), numbers)


def _combine(children):
    nonempty = st.lists(children, min_size=2, max_size=4)
    return st.one_of(
        nonempty.map(lambda args: sp.Add(*args)),
        nonempty.map(lambda args: sp.Mul(*args)),
        nonempty.map(lambda args: sp.Add._from_args(args)),
        st.tuples(numbers, nonempty).map(lambda ca: sp.Mul._from_args([ca[0], *ca[1]])),
        st.tuples(children, st.sampled_from([-3, -2, -1, 2, 3, 5, sp.S.Half, -sp.S.Half])).map(
            lambda be: sp.Pow(*be)),
        children.map(sp.sin), children.map(sp.cos),
    )


expressions = st.recursive(atoms, _combine, max_leaves=10)


@pytest.mark.parametrize("printer_class", PRINTERS, ids=lambda c: c.__name__)
@settings(max_examples=150, deadline=None)
@given(expr=expressions, given_order=st.booleans())
def test_same_text_as_sympys_printer(printer_class, expr, given_order):
    printers = [printer_class(table(printer_class)), sympys(printer_class)(table(printer_class))]
    if given_order:
        printers = [p.in_given_order() for p in printers]
    fast, reference = (outcome(p, expr) for p in printers)
    assert fast == reference


def outcome(printer, expr):
    """The text, or the error sympy's printing raises (Rust's on a sum of two numbers)."""
    try:
        return printer.code(expr)
    except Exception as exc:        # noqa: BLE001 - the same error from both is the same outcome
        return type(exc)


def test_languages_with_their_own_operators_keep_them():
    assert _generic(CPrinter, "_print_Mul") and _generic(PythonPrinter, "_print_Add")
    assert not _generic(OctavePrinter, "_print_Mul") and not _generic(RustPrinter, "_print_Add")


@settings(max_examples=300, deadline=None)
@given(exprs=st.lists(expressions, min_size=1, max_size=4))
def test_spec_printer_prints_what_sympys_str_printer_prints(exprs):
    """The reports' printer (the mixin over StrPrinter, its own `_print_str_Mul`), plain and
    remembering across expressions sharing parts, against sympy's StrPrinter in the given order
    (floats, e, complex and infinite numbers aside: the spec language writes them its own way)."""
    from hypothesis import assume

    from lagcli.render.spec_printer import remembering_spec_str, spec_str

    assume(not any(e.has(sp.Float, sp.I, sp.E, sp.zoo, sp.nan, sp.oo, -sp.oo) for e in exprs))
    remembering = remembering_spec_str()
    reference = StrPrinter({"order": "none"})
    for expr in [*exprs, sp.Mul(*exprs), -sp.Add(*exprs), *(-e for e in exprs)]:
        assert spec_str(expr) == reference.doprint(expr), expr
        assert remembering(expr) == reference.doprint(expr), expr


def test_spec_printer_prints_plain_products_as_sympys_str_printer():
    """Products of symbols, their powers, calls and sums, without a number (a report's terms:
    l1*l7*q7_dot**2*(m7 + m8)*sin(q1 - q7), printed factor by factor), and the same products
    with a number, a negative or fractional power or an integer base among them, against
    sympy's StrPrinter, on seeded random products."""
    import random

    from lagcli.render.spec_printer import remembering_spec_str, spec_str

    names = sp.symbols("q1 q2 q10 m1 m2 m10 l1 l2 g x_b Z", real=True)
    reference = StrPrinter({"order": "none"})
    remembering = remembering_spec_str()
    for seed in range(400):
        rng = random.Random(seed)

        def factor():
            s = rng.choice(names)
            return rng.choice([s, s, s ** rng.choice([2, 3, -1, -2, sp.S.Half, -sp.S.Half]), sp.sin(s - rng.choice(names)),
                               sp.cos(s), s + rng.choice(names) + rng.choice(names), -s + rng.choice(names),
                               sp.Pow(2, s), sp.Pow(sp.Integer(3), 2, evaluate=False)])

        expr = sp.Mul(*(factor() for _ in range(rng.randint(2, 6))))
        if rng.random() < 0.3:
            expr = rng.choice([-1, 2, -sp.Rational(3, 4), sp.pi]) * expr
        for shown in (expr, sp.Mul._from_args(expr.args) if expr.is_Mul else expr):
            assert spec_str(shown) == reference.doprint(shown), shown
            assert remembering(shown) == reference.doprint(shown), shown
