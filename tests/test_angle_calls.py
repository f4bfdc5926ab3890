"""`trig_call` (lagcli/model/angle_calls.py) builds the very expression sympy's sin and cos do."""
import random

import sympy as sp

from lagcli.model.angle_calls import trig_call


def _sums(seed=20261127, count=400):
    rng = random.Random(seed)
    names = [f"q{k}" for k in range(1, 13)] + ["x", "theta", "a_b", "Z"]
    real = [sp.Symbol(n, real=True) for n in names]
    plain = [sp.Symbol(n) for n in names[:4]] + [sp.Symbol("p", positive=True), sp.Symbol("z", zero=True)]
    for _ in range(count):
        k = rng.randint(1, 5)
        pool = real if rng.random() < 0.8 else real + plain
        symbols = rng.sample(pool, k)
        coefficients = [rng.choice([1, -1, 2, -2, 3, -3]) for _ in symbols]
        arg = sp.Add(*(c * s for c, s in zip(coefficients, symbols)))
        if rng.random() < 0.1:
            arg += rng.choice([1, sp.pi / 2, sp.Rational(1, 3)])
        yield arg


def test_trig_call_is_sympys_call():
    for arg in _sums():
        for function in (sp.sin, sp.cos):
            ours, theirs = trig_call(function, arg), function(arg)
            assert ours == theirs and sp.srepr(ours) == sp.srepr(theirs), (function, arg)


def test_trig_call_of_other_arguments():
    x, y = sp.symbols("x y", real=True)
    for arg in (sp.S.Zero, sp.pi, x * y, x / 2 - y, sp.I * x, sp.sqrt(x) - y):
        for function in (sp.sin, sp.cos):
            assert trig_call(function, arg) == function(arg)
