"""Chaplygin sled (knife edge with the centre of mass b ahead of the contact
point), and the classification of velocity constraints.

With u = forward speed of the contact point and w = phi', the sled obeys
    u' = b w^2,    w' = -m b u w / (Ic + m b^2)
and the multiplier of x' sin(phi) - y' cos(phi) = 0 is
    lambda = -Ic m u w / (Ic + m b^2)
(derived by hand from T = m |v_G|^2/2 + Ic phi'^2/2 with the augmented system).
"""
import textwrap

import numpy as np
import pytest
import sympy as sp
from click.testing import CliRunner

SPEC = "chaplygin_sled"


def test_constraint_is_nonholonomic_and_not_integrable(derived):
    d = derived(SPEC)
    (row,) = d.constraints
    assert row.kind == "nonholonomic"
    assert row.integrable is False
    assert d.n == 3 and d.n_nonholonomic == 1 and d.dof == 2
    assert d.multipliers[0].name == "lambda_knife"
    assert d.ignorable == ()


def test_sled_equations_at_random_states(derived, augmented, rng):
    d = derived(SPEC)
    model = d.model
    p = {info.symbol.name: info.value for info in model.parameters}
    m, Ic, b = p["m"], p["Ic"], p["b"]
    for _ in range(5):
        x, y, phi = rng.uniform(-2, 2, 3)
        u, w = rng.uniform(-2, 2, 2)
        state = dict(zip((*model.q, *model.qd), (x, y, phi, u * np.cos(phi), u * np.sin(phi), w)))
        qdd, lam = augmented(d, state)
        udot = qdd[0] * np.cos(phi) + qdd[1] * np.sin(phi)
        assert udot == pytest.approx(b * w**2, rel=1e-10, abs=1e-12)
        assert qdd[2] == pytest.approx(-m * b * u * w / (Ic + m * b**2), rel=1e-10, abs=1e-12)
        assert lam[0] == pytest.approx(-Ic * m * u * w / (Ic + m * b**2), rel=1e-10, abs=1e-12)
        # no sideways acceleration of the contact point beyond what keeps it on the blade
        side = -qdd[0] * np.sin(phi) + qdd[1] * np.cos(phi)
        assert side == pytest.approx(u * w, rel=1e-10, abs=1e-12)


def test_energy_conserved(derived, augmented, assert_zero, rng):
    d = derived(SPEC)
    model = d.model
    assert d.jacobi_integral is not None
    assert d.energy_is_jacobi is True
    assert_zero(d.jacobi_integral - d.energy, "h - E")
    grad_q = [sp.diff(d.energy, q) for q in model.q]
    grad_qd = [sp.diff(d.energy, qd) for qd in model.qd]
    params = {info.symbol: info.value for info in model.parameters}
    for _ in range(3):
        x, y, phi, u, w = rng.uniform(-2, 2, 5)
        vals = (x, y, phi, u * np.cos(phi), u * np.sin(phi), w)
        state = dict(zip((*model.q, *model.qd), vals))
        qdd, _ = augmented(d, state)
        subs = {**params, **state}
        rate = sum(float(gq.xreplace(subs)) * v for gq, v in zip(grad_q, vals[3:]))
        rate += sum(float(gv.xreplace(subs)) * a for gv, a in zip(grad_qd, qdd))
        assert abs(rate) < 1e-10


ROLLING_LINE = """\
name: rolling_line
description: disc rolling on a straight line; the velocity constraint integrates to x = r phi
coordinates: [x, phi]
parameters: {m: 1.0, r: 0.1}
bodies:
  disc: {mass: m, inertia: m*r**2/2, position: [x, r], angle: -phi}
constraints:
  - {name: rolling, expr: x_dot - r*phi_dot}
"""

NONLINEAR = """\
name: nonlinear_velocity
description: a velocity constraint that is not linear in the velocities (invalid)
coordinates: [x, y]
parameters: {m: 1.0}
particles:
  P: {mass: m, position: [x, y]}
constraints:
  - {name: bad_speed, expr: x_dot**2 - y_dot}
"""


def test_integrable_velocity_constraint_is_reported(tmp_path):
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive

    path = tmp_path / "rolling_line.yaml"
    path.write_text(ROLLING_LINE)
    d = derive(load_model(str(path)))
    (row,) = d.constraints
    assert row.kind == "nonholonomic"
    assert row.integrable is True


def test_nonlinear_velocity_constraint_is_an_error(tmp_path):
    from lagcli.derive.pipeline import load_model
    from lagcli.derive import derive
    from lagcli.errors import LagcliError

    path = tmp_path / "nonlinear_velocity.yaml"
    path.write_text(NONLINEAR)
    with pytest.raises(LagcliError) as info:
        derive(load_model(str(path)))
    assert info.value.exit_code == 2
    assert "constraints[0]" in str(info.value) or "bad_speed" in str(info.value)


def test_nonlinear_velocity_constraint_check_exits_2(tmp_path):
    from lagcli.cli import cli

    path = tmp_path / "nonlinear_velocity.yaml"
    path.write_text(NONLINEAR)
    result = CliRunner().invoke(cli, ["check", str(path)])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    assert "nonlinear_velocity.yaml" in result.stderr
    assert "constraints[0]" in result.stderr or "bad_speed" in result.stderr
    assert result.stdout == ""
