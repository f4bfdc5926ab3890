"""The C runtime's dense solves (lagcli/runtime/c/lagcli_linalg.h) against numpy.

The header is compiled with the contract's strict flags into a small library whose
functions call `lagcli_solve_symmetric` and `lagcli_solve_lu` with the size as a literal,
as the generated code does (once inlined, the compiler sees it), and once with the size
as an argument. Checked:

- symmetric positive definite matrices (the N-link chain's mass matrix, random A A^T + I)
  of 1 to 40 rows: x agrees with numpy.linalg.solve; the square-root-free Cholesky reads
  and writes the lower triangle only, so K's diagonal and upper triangle are still M;
- symmetric matrices that are not positive definite: regular ones fall back to LU and
  still agree with numpy; exactly singular ones return 1;
- a NaN or inf in K's lower triangle (off the diagonal, on it, +inf included: it would
  give a finite x) or in r returns 2, and so does an x that overflows; a pivot too small
  to invert goes to LU;
- the generated C model of the 10-link chain: its right-hand side is numpy's solve of
  its own mass matrix and forcing.

Skipped when there is no `cc`.
"""
from __future__ import annotations

import ctypes
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
RUNTIME = ROOT / "lagcli" / "runtime" / "c"
CC = shutil.which("cc")
CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]
SIZES = (1, 2, 3, 4, 5, 7, 10, 11, 20, 40)

pytestmark = pytest.mark.skipif(CC is None, reason="no C compiler (cc)")

DOUBLES = ctypes.POINTER(ctypes.c_double)


def solves_source() -> str:
    lines = ['#include "lagcli_linalg.h"']
    for n in SIZES:
        lines.append(f"int symmetric{n}(double *K, double *r, double *d) "
                     f"{{ return lagcli_solve_symmetric({n}, K, r, d); }}")
        lines.append(f"int lu{n}(double *K, double *r) {{ return lagcli_solve_lu({n}, K, r); }}")
    lines.append("int symmetric_any(int n, double *K, double *r, double *d) "
                 "{ return lagcli_solve_symmetric(n, K, r, d); }")
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def solves(tmp_path_factory):
    folder = tmp_path_factory.mktemp("linalg")
    (folder / "solves.c").write_text(solves_source())
    done = subprocess.run([CC, *CFLAGS, f"-I{RUNTIME}", "-shared", "-fPIC", "solves.c", "-o", "libsolves.so",
                           "-lm"], cwd=folder, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return ctypes.CDLL(str(folder / "libsolves.so"))


def pointer(array: np.ndarray):
    return array.ctypes.data_as(DOUBLES)


def symmetric(solves, M, F, constant=True) -> tuple[int, np.ndarray, np.ndarray]:
    """(return code, x, K after the call) of lagcli_solve_symmetric on copies of M and F."""
    n = len(F)
    K, r, d = np.array(M, dtype=float), np.array(F, dtype=float), np.zeros(n)
    if constant:
        rc = getattr(solves, f"symmetric{n}")(pointer(K), pointer(r), pointer(d))
    else:
        rc = solves.symmetric_any(n, pointer(K), pointer(r), pointer(d))
    return rc, r, K


def lu(solves, M, F) -> tuple[int, np.ndarray]:
    K, r = np.array(M, dtype=float), np.array(F, dtype=float)
    return getattr(solves, f"lu{len(F)}")(pointer(K), pointer(r)), r


def chain_mass_matrix(q: np.ndarray) -> np.ndarray:
    """The planar chain of unit masses and unit rods, absolute angles:
    M[i][j] = (n - max(i, j)) cos(q_i - q_j)."""
    n = len(q)
    i, j = np.indices((n, n))
    return (n - np.maximum(i, j)) * np.cos(q[:, None] - q[None, :])


def positive_definite(n: int, rng) -> list[np.ndarray]:
    A = rng.normal(size=(n, n))
    return [chain_mass_matrix(rng.uniform(-np.pi, np.pi, n)), A @ A.T + np.eye(n),
            np.diag(rng.uniform(0.1, 10.0, n))]


def assert_solves(M, F, x, what=""):
    """x solves M x = F as well as numpy's does, to the condition of M."""
    reference = np.linalg.solve(M, F)
    tolerance = 1e-13 * np.linalg.cond(M) * max(1.0, np.abs(reference).max())
    assert np.abs(x - reference).max() <= tolerance, (what, x, reference)


@pytest.mark.parametrize("n", SIZES)
def test_positive_definite_matrices_agree_with_numpy(solves, n):
    rng = np.random.default_rng(n)
    for k, M in enumerate(positive_definite(n, rng)):
        F = rng.normal(size=n)
        for constant in (True, False):
            rc, x, K = symmetric(solves, M, F, constant)
            assert rc == 0
            assert_solves(M, F, x, f"matrix {k}")
            upper = np.triu_indices(n)
            assert np.array_equal(K[upper], M[upper]), "the diagonal and upper triangle are M's"


@pytest.mark.parametrize("n", SIZES)
def test_lu_agrees_with_numpy(solves, n):
    rng = np.random.default_rng(100 + n)
    M = rng.normal(size=(n, n)) + n * np.eye(n)
    F = rng.normal(size=n)
    rc, x = lu(solves, M, F)
    assert rc == 0
    assert_solves(M, F, x)


@pytest.mark.parametrize("n", [2, 3, 5, 10, 11, 20, 40])
def test_indefinite_regular_matrices_fall_back_to_lu(solves, n):
    rng = np.random.default_rng(200 + n)
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    eigenvalues = rng.uniform(0.5, 2.0, n) * np.where(np.arange(n) % 2, -1.0, 1.0)
    leading_zero = np.eye(n)
    leading_zero[[0, 1]] = leading_zero[[1, 0]]                      # M[0][0] = 0: LDL^T's first pivot
    for M in ((Q * eigenvalues) @ Q.T, leading_zero, -positive_definite(n, rng)[0]):
        M = (M + M.T) / 2
        F = rng.normal(size=n)
        rc, x, _ = symmetric(solves, M, F)
        assert rc == 0
        assert_solves(M, F, x)


@pytest.mark.parametrize("M", [[[0.0]], [[1.0, 2.0], [2.0, 4.0]], [[0.0, 0.0], [0.0, 1.0]],
                               [[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 3.0]],
                               np.ones((10, 10)).tolist()],
                         ids=["zero", "rank1", "zero_row", "repeated_rows", "ones10"])
def test_exactly_singular_matrices_return_1(solves, M):
    M = np.array(M)
    assert np.linalg.matrix_rank(M) < len(M)
    assert symmetric(solves, M, np.ones(len(M)))[0] == 1
    assert lu(solves, M, np.ones(len(M)))[0] == 1


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf], ids=["nan", "inf", "-inf"])
@pytest.mark.parametrize("n", [1, 2, 3, 10, 11, 40])
def test_a_non_finite_entry_returns_2(solves, n, value):
    rng = np.random.default_rng(300 + n)
    M = positive_definite(n, rng)[0]
    F = rng.normal(size=n)
    places = {(i, j) for i in range(n) for j in range(i + 1)}           # every lower entry at 10 rows
    if n > 10:
        places = {(0, 0), (n - 1, n - 1), (n - 1, 0), (n // 2, n // 3), (1, 0), (n - 1, n - 2)}
    for i, j in sorted(places):
        K = M.copy()
        K[i, j] = K[j, i] = value                                       # as the generated code writes M
        assert symmetric(solves, K, F)[0] == 2, (i, j)
        assert lu(solves, K, F)[0] == 2, (i, j)
    for i in range(n):
        r = F.copy()
        r[i] = value
        assert symmetric(solves, M, r)[0] == 2, i
        assert lu(solves, M, r)[0] == 2, i


def test_positive_infinity_on_the_diagonal_is_not_a_finite_solution(solves):
    """1/inf = 0 would be a finite x: the pivot test sends it to LU, which says 2."""
    M = np.array([[math.inf, 0.0], [0.0, 1.0]])
    assert symmetric(solves, M, np.array([1.0, 1.0]))[0] == 2


def test_a_pivot_too_small_to_invert_is_left_to_lu(solves):
    """1/D = inf would make 0 * inf = NaN of an exact zero: LU solves it."""
    M = np.diag([1e-310, 1.0])
    rc, x, _ = symmetric(solves, M, np.array([0.0, 2.0]))
    assert rc == 0 and list(x) == [0.0, 2.0]


def test_an_overflowing_solution_returns_2(solves):
    M = np.diag([1e-300, 1.0])
    assert symmetric(solves, M, np.array([1e300, 1.0]))[0] == 2
    tiny = np.diag([1e-310, 1.0])                                       # 1/D overflows: LU, then x does
    assert symmetric(solves, tiny, np.array([1.0, 1.0]))[0] == 2


def test_generated_chain_rhs_is_numpys_solve_of_its_own_m_and_f(tmp_path):
    """The 10-link chain's generated C: q'' = numpy.linalg.solve(M, F) of the model's own
    mass_matrix and forcing at seeded random states (the solve as the generated code
    inlines it, the size a literal)."""
    from conftest import nlink_spec
    from lagcli import commands

    n = 10
    commands.generate(str(nlink_spec(tmp_path, n)), "c", str(tmp_path))
    done = subprocess.run([CC, *CFLAGS, "-shared", "-fPIC", f"nlink{n}.c", "-o", "libchain.so", "-lm"],
                          cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lib = ctypes.CDLL(str(tmp_path / "libchain.so"))
    p = np.array((ctypes.c_double * (2 * n + 1)).in_dll(lib, f"nlink{n}_parameter_defaults"))
    rng = np.random.default_rng(24)
    for _ in range(8):
        y = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.uniform(-2.0, 2.0, n)])
        dydt, M, F = np.zeros(2 * n), np.zeros(n * n), np.zeros(n)
        assert getattr(lib, f"nlink{n}_rhs")(ctypes.c_double(0.0), pointer(y), pointer(p), pointer(dydt)) == 0
        assert getattr(lib, f"nlink{n}_mass_matrix")(ctypes.c_double(0.0), pointer(y), pointer(p), pointer(M)) == 0
        assert getattr(lib, f"nlink{n}_forcing")(ctypes.c_double(0.0), pointer(y), pointer(p), pointer(F)) == 0
        assert np.array_equal(dydt[:n], y[n:])
        assert_solves(M.reshape(n, n), F, dydt[n:])
