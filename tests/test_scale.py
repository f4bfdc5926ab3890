"""Issue 24: no artificial ceiling on the length of a sum, and cost that grows with the work.

Each derivation is checked against its closed form (uncoupled springs: M = diag(m),
F = -k x; one particle riding on the sum of all coordinates: M = diag(m) + m0 * ones),
and the sizes that used to be refused or to take minutes are run to the end (their
CPU seconds are in bench/README.md: timings are never asserted)."""
import subprocess
from pathlib import Path
import sys

import pytest
import sympy as sp

from lagcli.derive.pipeline import load_model
from lagcli.derive import derive
from lagcli.errors import SpecError
from lagcli.model.expr import MAX_DEPTH, Scope, parse
from lagcli.errors import Loc

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from bench.codegen import uncoupled_spec  # noqa: E402  (the bench's spec, written once)


def test_a_long_sum_is_one_level_of_nesting():
    x = sp.symbols("x1:1001", real=True)
    scope = Scope({str(s): s for s in x}, sp.Symbol("t"))
    total = parse(" + ".join(map(str, x)) + " - x1", scope, Loc("<test>"))
    assert total == sp.Add(*x[1:])
    deep = "-(" * (MAX_DEPTH + 1) + "x1" + ")" * (MAX_DEPTH + 1)
    with pytest.raises(SpecError, match=f"nested too deeply \\(more than {MAX_DEPTH} levels\\)"):
        parse(deep, scope, Loc("<test>"))
    with pytest.raises(SpecError, match="too large"):        # the bounds still hold, and say what they bound
        parse(" + ".join(["x1"] * 3000), scope, Loc("<test>"))


def test_a_particle_on_a_sum_of_140_coordinates_derives(tmp_path):
    """Written as one flat sum (as bench/codegen.py writes the chains): refused before as
    "nested too deeply (more than 60 levels)"; its mass matrix is diag(m) + m0 * ones."""
    n = 140
    names = [f"x{i}" for i in range(1, n + 1)]
    vectors = " + ".join(f"[{q}, 0, 0]" for q in names[: n // 2])          # vector sums too
    scalars = " + ".join(names[n // 2:])
    spec = [f"coordinates: [{', '.join(names)}]", "parameters: {m: 1.0, m0: 3.0}", "particles:",
            f"  S: {{mass: m0, position: '{vectors} + [{scalars}, 0, 0]'}}"]
    spec += [f"  P{i}: {{mass: m, position: [{q}, {i}, 0]}}" for i, q in enumerate(names, start=1)]
    path = tmp_path / "sum.yaml"
    path.write_text("\n".join(spec) + "\n")
    d = derive(load_model(path))
    m, m0 = sp.Symbol("m", real=True), sp.Symbol("m0", real=True)
    assert d.mass_matrix == sp.eye(n) * m + sp.ones(n, n) * m0


def test_300_uncoupled_coordinates_derive_to_their_closed_form(tmp_path):
    n = 300
    path = tmp_path / "springs.yaml"
    path.write_text(uncoupled_spec(n))
    d = derive(load_model(path))
    model = load_model(path)
    m = [model.symbol(f"m{i}") for i in range(1, n + 1)]
    k = [model.symbol(f"k{i}") for i in range(1, n + 1)]
    assert d.mass_matrix == sp.diag(*m)
    assert list(d.forcing) == [-ki * xi for ki, xi in zip(k, model.q)]


@pytest.mark.slow
def test_check_of_1000_uncoupled_coordinates_finishes(tmp_path):
    """It did not finish before issue 24 (an n x n product per ignorable coordinate); its CPU
    time is measured in bench/README.md, not asserted here (machines are noisy)."""
    path = tmp_path / "springs.yaml"
    path.write_text(uncoupled_spec(1000))
    done = subprocess.run([sys.executable, "-m", "lagcli", "check", str(path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "DOF         : 1000" in done.stdout


def test_a_chains_mass_matrix_grows_as_its_entries(tmp_path):
    """Each entry of the n-link chain's M is l_i l_j cos(q_i - q_j) (m_max(i,j) + ... + m_n)
    (its closed form, checked here at n = 12): one product holding one sum of masses, so M
    holds ~n^3/6 mass symbols in all, not the ~n^3/6 products m_k X an expanded sum holds."""
    from conftest import nlink_spec
    n = 12
    model = load_model(nlink_spec(tmp_path, n))
    M = derive(model).mass_matrix
    sym = {s.name: s for s in M.free_symbols}
    for i in range(1, n + 1):
        for j in range(i, n + 1):
            masses = sum(sym[f"m{k}"] for k in range(j, n + 1))
            closed = sym[f"l{i}"] * sym[f"l{j}"] * masses * sp.cos(model.q[i - 1] - model.q[j - 1])
            assert sp.simplify(sp.expand_trig(M[i - 1, j - 1] - closed)) == 0, (i, j)
            assert not M[i - 1, j - 1].is_Add, "an entry is one product, not a sum of m_k X"


@pytest.mark.parametrize("kind", [sp.Matrix, sp.ImmutableMatrix])
def test_a_matrix_of_its_nonzero_entries_is_sympys_own(kind):
    """`matrix_of_entries` skips sympy's walk over every place; the matrix is the one
    sympy builds from a SparseMatrix (the same entries, type and equality both ways)."""
    from lagcli.model.calculus import matrix_of_entries

    x, y = sp.symbols("x y")
    entries = {(0, 0): x, (1, 2): sp.cos(y), (2, 1): sp.cos(y), (3, 3): x * y}
    ours, sympys = matrix_of_entries(4, 4, entries, kind), kind(sp.SparseMatrix(4, 4, entries))
    assert type(ours) is type(sympys)
    assert ours.tolist() == sympys.tolist() and ours == sympys and sympys == ours
    assert ours.todok() == entries


def test_a_jacobians_columns_are_in_the_variables_order():
    """The nonzero columns come in the order of the variables, whatever the order of
    the symbols in the expressions (`jacobian_columns` looks their places up)."""
    from lagcli.model.calculus import jacobian_columns

    q = sp.symbols("q0:6", real=True)
    exprs = [q[4] * sp.sin(q[1]), q[3] ** 2]
    columns = jacobian_columns(exprs, q, {})
    expected = sp.Matrix(exprs).jacobian(q)
    assert [j for j, _ in columns] == [j for j in range(6) if any(expected[:, j])]
    assert all(list(column) == list(expected[:, j]) for j, column in columns)
