"""`calculus.leaves` (one walk by identity) finds what sympy's own traversal finds: the
nodes without arguments, on a derivation's shared expressions and on equal copies."""
import sympy as sp

from conftest import nlink_spec
from lagcli.derive.pipeline import derive_file
from lagcli.model.calculus import leaves


def _atoms(*exprs) -> set:
    return {node for e in exprs for node in sp.preorder_traversal(e) if not node.args}


def test_leaves_of_a_chains_energies_are_sympys(tmp_path):
    d = derive_file(nlink_spec(tmp_path, 4))
    exprs = [d.T, d.V, *d.mass_matrix.values()]
    assert leaves(*exprs) == _atoms(*exprs)


def test_equal_copies_and_numbers_are_found():
    x, y = sp.symbols("x y")
    shared = sp.sin(x) + y / 3
    copy = sp.Add(sp.sin(x), sp.Rational(1, 3) * y, evaluate=False)     # equal, another object
    exprs = [shared * sp.pi, copy + 2.5, sp.Integer(7)]
    assert leaves(*exprs) == _atoms(*exprs) == {x, y, sp.Rational(1, 3), sp.pi, sp.Float(2.5), sp.Integer(7)}
