"""A Derivation computes F, the equations and the total generalized forces on first use
(lagcli/derive/result.py): a derive report never computes them, and what is computed
is Lagrange's equations all the same.

The equations are checked against d/dt(dL/dq') - dL/dq - Q' taken here with sympy's
own `diff` and the chain rule (not lagcli's calculus), on bundled specs with points,
bodies, T1 and T0 terms (a moving frame), applied forces and constraints.
"""
from pathlib import Path

import pytest
import sympy as sp

import lagcli
import lagcli.derive.forcing
from lagcli.derive.closed_loop import closed_loop
from lagcli.derive.pipeline import derive_file
from lagcli.model.calculus import numerically_zero

SPECS = Path(__file__).parent.parent / "specs"
SMALL = ["double_pendulum", "cart_pole", "bead_on_spinning_hoop", "heavy_symmetric_top", "atwood",
         "disc_on_incline", "ex19_oscillating_support"]


@pytest.mark.parametrize("spec", ["double_pendulum", "heavy_symmetric_top", "ex6_9_two_wheels_axle"])
@pytest.mark.parametrize("format", ["json", "text", "latex"])
def test_derive_report_does_not_compute_forcing(spec, format, monkeypatch):
    calls = []
    monkeypatch.setattr(lagcli.derive.forcing, "forcing", lambda *args: calls.append(args))
    system = lagcli.load(str(SPECS / f"{spec}.yaml"))
    assert system.report(format)
    assert calls == []
    assert not {"forcing", "equations", "generalized_forces"} & set(vars(system.derivation))


def _lagrange_lhs(d) -> sp.Matrix:
    """d/dt(dL/dq'_i) - dL/dq_i - Q'_i, by sympy's diff and the chain rule."""
    m = d.model
    rows = []
    for q, v, Q in zip(m.q, m.qd, d.nonconservative_forces):
        p = d.L.diff(v)
        rate = p.diff(m.t) + sum(p.diff(x) * y + p.diff(y) * z for x, y, z in zip(m.q, m.qd, m.qdd))
        rows.append(rate - d.L.diff(q) - Q)
    return sp.Matrix(rows)


@pytest.mark.parametrize("spec", SMALL)
def test_lazy_equations_are_lagranges(spec):
    d = derive_file(SPECS / f"{spec}.yaml")
    lhs = sp.Matrix([eq.lhs for eq in d.equations])
    M_qdd = d.mass_matrix * sp.Matrix(d.model.qdd)
    assert numerically_zero(list(lhs - _lagrange_lhs(d)), trials=4)
    assert numerically_zero(list(lhs - (M_qdd - d.forcing)), trials=4)
    Q_total = d.nonconservative_forces - sp.Matrix([d.V.diff(q) for q in d.model.q])
    assert numerically_zero(list(d.generalized_forces - Q_total), trials=4)
    assert [eq.rhs for eq in d.equations] == list(d.generalized_constraint_forces)


def test_closed_loop_substitutes_the_laws_in_forcing_only():
    d = derive_file(SPECS / "hybrid" / "cart_pole_lqr.yaml")
    closed = closed_loop(d)
    laws = {law.symbol: law.expr for law in d.model.laws}
    assert laws and closed.input_laws and not d.input_laws
    assert closed.forcing == d.forcing.xreplace(laws)
    assert not closed.forcing.free_symbols & set(laws)
    assert closed.equations == d.equations       # the equations keep u, as before


BAD = Path(__file__).parent / "data" / "bad"


@pytest.mark.parametrize("command", [["generate", "--lang", "python"], ["simulate"], ["linearize"], ["check"]])
def test_commands_using_forcing_refuse_its_huge_constant(command, monkeypatch):
    """F is checked as it is computed (lagcli/derive/representable.py): as before, with the
    located message of tests/data/bad/derived_constant_huge_in_force.expected."""
    from click.testing import CliRunner

    from lagcli.cli import cli

    monkeypatch.chdir(BAD)
    result = CliRunner().invoke(cli, [*command, "derived_constant_huge_in_force.yaml"])
    assert result.exit_code == 2, result.output
    expected = (BAD / "derived_constant_huge_in_force.expected").read_text().strip()
    assert expected in result.output
