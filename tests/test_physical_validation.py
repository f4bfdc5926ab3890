"""Physical validation (lagcli/model/validation.py): the warnings corpus and the checks' edges.

The errors (negative masses, impossible inertias, a coordinate without inertia, the
common slips) are cases of the bad-spec corpus, tests/data/bad/ (test_bad_specs.py).
Warnings are `tests/data/warn/<case>.yaml` with `<case>.expected`: `check` succeeds
and every expected line is on stderr.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import pytest
from click.testing import CliRunner

from lagcli.errors import SpecError, SpecWarning

WARN = Path(__file__).parent / "data" / "warn"
CASES = sorted(WARN.glob("*.yaml"))


def _runner() -> CliRunner:
    try:
        return CliRunner(mix_stderr=False)
    except TypeError:
        return CliRunner()


@pytest.mark.parametrize("case", CASES, ids=lambda p: p.name)
def test_suspicious_spec_is_checked_with_a_warning(case: Path, monkeypatch):
    from lagcli.cli import cli

    monkeypatch.chdir(WARN)
    result = _runner().invoke(cli, ["check", case.name])
    assert result.exit_code == 0, result.stderr
    assert "DOF" in result.stdout or "dof" in result.stdout.lower()
    for line in filter(None, map(str.strip, case.with_suffix(".expected").read_text().splitlines())):
        assert line in result.stderr


def test_warnings_reach_library_users_as_python_warnings():
    import lagcli

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lagcli.load(str(WARN / "zero_mass.yaml"))
    assert any(isinstance(w.message, SpecWarning) and "marker" in str(w.message) for w in caught)


SPHERE_ABOUT_AXIS = """
coordinates: [th]
parameters: {m: 2.0, r: 0.5}
definitions: {I: 2*m*r**2/5}
bodies:
  b: {mass: m, inertia: [I, I, I], position: [0, 0, 0], orientation: [[z, th]]}
"""


@pytest.mark.parametrize("inertia,ok", [
    ("[I, I, I]", True),                            # a sphere
    ("[0, I, I]", True),                            # a thin rod along x: I1 = 0 is possible
    ("[I, I, 2*I]", True),                          # a thin disc in xy: the equality case
    ("[I, I, 2.1*I]", True),                        # beyond the triangle inequality: a warning only
    ("[I, I, -0.1*I]", False),                      # a negative principal moment
    ("[I, I, I, 0.1*I, 0, 0]", True),               # products of inertia, still positive definite
    ("[[I, 0, 0], [0, I, 0], [0, 0.1, I]]", False), # not symmetric
])
def test_inertia_tensors_real_bodies_can_have(inertia, ok):
    import lagcli

    text = SPHERE_ABOUT_AXIS.replace("[I, I, I], position", f"{inertia}, position")
    if ok:
        lagcli.load(text)
    else:
        with pytest.raises(SpecError):
            lagcli.load(text)


def test_a_coordinate_regularised_by_a_constraint_is_accepted():
    """A massless coordinate tied by a constraint to one with inertia is fine: the mass
    matrix is singular, but not on the motions the constraint allows."""
    import lagcli

    lagcli.load("""
coordinates: [x, s]
parameters: {m: 1.0}
particles:
  P: {mass: m, position: [x, 0]}
constraints:
  - s - 2*x
""")


def test_a_coordinate_without_inertia_is_named():
    import lagcli

    with pytest.raises(SpecError, match="'y' carries no inertia"):
        lagcli.load("coordinates: [x, y]\nparticles:\n  P: {mass: 1, position: [x, 0]}\npotential: y**2\n")


def test_specs_with_only_kinetic_and_potential_pass():
    import lagcli

    with warnings.catch_warnings():
        warnings.simplefilter("error", SpecWarning)
        lagcli.load("coordinates: [x]\nparameters: {m: 1.0, k: 4.0}\nkinetic: m*x_dot**2/2\n"
                    "potential: k*x**2/2\ninitial: {x: 0.1}\n")


def test_plain_cholesky_agrees_with_numpy():
    """The mass-matrix check's own Cholesky (no numpy import for a 40-link chain) says
    "has a factor" exactly where numpy's does, on random symmetric matrices well away from
    the boundary (positive definite, and shifted to have a clearly negative eigenvalue)."""
    import random

    import numpy as np

    from lagcli.model.validation import _has_cholesky_factor

    rng = random.Random(20261128)
    for n in (1, 2, 5, 40, 120):
        for shift in (-0.5, 0.5):
            B = np.array([[rng.uniform(-1, 1) for _ in range(n)] for _ in range(n)])
            A = B @ B.T / n
            A -= (np.linalg.eigvalsh(A)[0] + shift) * np.eye(n)     # smallest eigenvalue: -shift
            try:
                np.linalg.cholesky(A)
                expected = True
            except np.linalg.LinAlgError:
                expected = False
            assert expected is (shift < 0)
            assert _has_cholesky_factor(A.tolist()) is expected, (n, shift)
