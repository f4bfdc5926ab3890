"""T2 = 1/2 q'^T M q' (`energy.quadratic_part`) against sympy: sympy's own matrix product,
and each velocity times an entry of M exactly as `sympy.Mul` builds it (the same factors
in the same order: T2's printed and generated forms depend on it)."""
import pytest
import sympy as sp

from conftest import nlink_spec, spec_path
from lagcli.derive.energy import _times_velocity, quadratic_part
from lagcli.derive.pipeline import derive_file
from lagcli.model.symbols import Velocity


@pytest.fixture(scope="module", params=["chain6", "double_pendulum", "heavy_symmetric_top", "cart_pole"])
def derivation(request, tmp_path_factory):
    name = request.param
    path = nlink_spec(tmp_path_factory.mktemp("chain"), 6) if name == "chain6" else spec_path(name)
    return derive_file(path)


def test_every_velocity_times_entry_is_sympys_product(derivation):
    M, qd = derivation.mass_matrix, derivation.model.qd
    for (i, _), entry in M.todok().items():
        mine, sympys = _times_velocity(qd[i], entry), sp.Mul(qd[i], entry)
        assert mine == sympys and mine.args == sympys.args


def test_quadratic_part_is_half_the_matrix_product(derivation):
    M, qd = derivation.mass_matrix, sp.Matrix(derivation.model.qd)
    expected = (qd.T * sp.Matrix(M) * qd)[0] / 2
    assert sp.expand(quadratic_part(M, derivation.model.qd) - expected) == 0


@pytest.mark.parametrize("velocity", [Velocity("x_dot", real=True), sp.Symbol("v", real=True)])
@pytest.mark.parametrize("number", [1, 3, sp.Rational(-2, 7)])
def test_a_product_of_sums_takes_the_velocity_where_sympy_puts_it(velocity, number):
    a, b, c, m1, m2 = sp.symbols("a b c m1 m2", real=True)
    entry = sp.Mul(number, sp.sin(a) * b + c, m1 + m2 + a)
    mine, sympys = _times_velocity(velocity, entry), sp.Mul(velocity, entry)
    assert mine == sympys and mine.args == sympys.args
