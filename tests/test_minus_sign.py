"""lagcli.targets.minus_sign gives sympy's own `Add.could_extract_minus_sign` (the oracle)
on every sum generated code meets: those of the bundled specs' outputs and of a chain,
as derived and after the CSE's preprocessing, and on sums built to hit its edge cases."""
import pytest
import sympy as sp

from lagcli.interface import layout_of
from lagcli.render.tidy import factored
from lagcli.targets.cse import sums
from lagcli.targets.expressions import collect
from lagcli.targets.minus_sign import could_extract_minus_sign

SPECS = ["double_pendulum", "benchmark_bicycle", "chaplygin_sled", "heavy_symmetric_top",
         "rolling_disc", "gantry_crane", "bead_on_spinning_hoop", "ex19_oscillating_support"]


def every_sum(exprs) -> set:
    found = set()
    for expr in exprs:
        for form in (expr, factored(expr)):
            found |= sums(form)
    return found | {-s for s in found if isinstance(-s, sp.Add)}


def assert_as_sympy(adds) -> None:
    wrong = [a for a in adds if could_extract_minus_sign(a) != a.could_extract_minus_sign()]
    assert not wrong, wrong[:3]


@pytest.mark.parametrize("name", SPECS)
def test_the_sums_of_bundled_specs(name, derived):
    d = derived(name)
    outputs = collect(d, layout_of(d), tidy=False)
    adds = every_sum([e for exprs in outputs.groups().values() for e in exprs])
    assert adds
    assert_as_sympy(adds)


def test_the_sums_of_a_chain():
    q, qd, m, l = (sp.symbols(f"{s}1:7", real=True) for s in ("q", "qd", "m", "l"))
    x = [sum(l[i] * sp.sin(q[i]) for i in range(k + 1)) for k in range(6)]
    y = [-sum(l[i] * sp.cos(q[i]) for i in range(k + 1)) for k in range(6)]
    xd = [sum(sp.diff(e, qi) * v for qi, v in zip(q, qd)) for e in x]
    yd = [sum(sp.diff(e, qi) * v for qi, v in zip(q, qd)) for e in y]
    energy = sum(m[k] * (xd[k] ** 2 + yd[k] ** 2) / 2 + 9.81 * m[k] * y[k] for k in range(6))
    adds = every_sum([energy, sp.expand(energy), *xd, *yd])
    assert any(2 * sum(a.could_extract_minus_sign() for a in s.args) == len(s.args) for s in adds)  # ties met
    assert_as_sympy(adds)


def test_edge_cases():
    x, y, z = sp.symbols("x y z")
    d, e = sp.Dummy("d"), sp.Dummy("e")
    f = sp.Function("f")
    cases = [x - y, y - x, 1 - x, x - 1, sp.sqrt(2) * x - 2 * x, sp.pi * x - y, d - e, e - d, x - d,
             d - x, x ** 2 - x * y, x * y - x ** 2, 1 / x - y, y - 1 / x, sp.sqrt(x) - x, x - sp.sqrt(x),
             sp.sin(x) - sp.cos(x), sp.cos(x) - sp.sin(x), f(x) - f(y), sp.exp(x) - sp.exp(y),
             sp.exp(2 * x) - x, 2.5 * x - 1.5 * y, x * (y + z) - y * (x + z), (x + y) ** 2 - (x - y) ** 2,
             sp.Mul(-1, x - y, evaluate=False) + z, -x - y + z + 3, x + y - z - 3, x * y - z * x - y * z + x * y * z]
    assert_as_sympy([c for c in cases if isinstance(c, sp.Add)])


def test_term_sign_test_is_sympys():
    """`_term_extracts` (the shortcut for a sum's terms) answers as sympy's own test."""
    from lagcli.targets.minus_sign import _term_extracts

    x, y = sp.symbols("x y", real=True)
    terms = [x, -x, 2 * x * y, -3 * x * y / 2, sp.Mul(1, -1, x - y, evaluate=False),
             sp.Mul(-1, x - y, evaluate=False), sp.Mul(-2, sp.zoo, x, evaluate=False), sp.Mul(-2, x, sp.zoo, evaluate=False), sp.zoo * x,
             sp.Float(-1.5) * x, -sp.sqrt(2) * x, sp.Mul(0, x, evaluate=False), sp.Integer(-3),
             sp.Mul(-1, 2, x, evaluate=False), sp.sin(x) * -y, sp.I * x, -sp.I * x]
    for term in terms:
        assert _term_extracts(term) == term.could_extract_minus_sign(), term
