"""Dampers and Rayleigh dissipation (docs/spec.md, "Dampers and dissipation").

A spherical spring pendulum (3-D) with a dashpot from the bob to a fixed point off the
pivot, so the dashpot's line is neither radial nor along a coordinate. Checked:

- energy decays at the rate the dissipation function predicts: along a simulation,
  E(t) - E(0) = -int 2R dt, with R = 1/2 c (dL/dt)^2 computed here from the bob's
  Cartesian position and velocity (independently of lagcli's derivation);
- a Rayleigh `dissipation:` written by hand gives the same equations as the dashpot,
  and so do `generalized_forces:` written by hand from the dashpot force;
- a planar dashpot along the motion gives the textbook m x'' + c x' + k x = 0.
"""
from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import cumulative_trapezoid

import lagcli

ANCHOR = (0.3, 0.1, 0.2)   # the dashpot's fixed end

SPHERICAL = """
coordinates: [r, theta, phi]
parameters: {m: 1.5, k: 40.0, L0: 1.0, c: 0.8, g: 9.81}
gravity: [0, 0, -g]
definitions:
  px: r*sin(theta)*cos(phi)
  py: r*sin(theta)*sin(phi)
  pz: -r*cos(theta)
particles:
  P: {mass: m, position: [px, py, pz]}
springs:
  - {between: [P, [0, 0, 0]], stiffness: k, rest_length: L0}
dampers:
  - {between: [P, [0.3, 0.1, 0.2]], damping: c}
initial: {r: 1.2, theta: 0.6, phi: 0.1, r_dot: 0.2, theta_dot: 0.5, phi_dot: 1.5}
"""

CARTESIAN = """
coordinates: [x, y, z]
parameters: {m: 1.5, k: 40.0, L0: 1.0, c: 0.8, g: 9.81}
gravity: [0, 0, -g]
particles:
  P: {mass: m, position: [x, y, z]}
springs:
  - {between: [P, [0, 0, 0]], stiffness: k, rest_length: L0}
"""
DASHPOT = "dampers:\n  - {between: [[0.3, 0.1, 0.2], P], damping: c}\n"
LENGTH2 = "((x - 0.3)**2 + (y - 0.1)**2 + (z - 0.2)**2)"
RATE = "((x - 0.3)*x_dot + (y - 0.1)*y_dot + (z - 0.2)*z_dot)"
RAYLEIGH = f"dissipation: c*{RATE}**2/(2*{LENGTH2})\n"
BY_HAND = "generalized_forces:\n" + "".join(
    f"  {q}: -c*{RATE}*({q} - {a})/{LENGTH2}\n" for q, a in zip("xyz", ANCHOR))


def _bob_in_cartesian(traj):
    """(position, velocity) of the bob, 3 x N, from either spec's columns."""
    if "x" in traj.names:
        return (np.stack([traj["x"], traj["y"], traj["z"]]),
                np.stack([traj["x_dot"], traj["y_dot"], traj["z_dot"]]))
    r, th, ph = traj["r"], traj["theta"], traj["phi"]
    rd, thd, phd = traj["r_dot"], traj["theta_dot"], traj["phi_dot"]
    position = np.stack([r * np.sin(th) * np.cos(ph), r * np.sin(th) * np.sin(ph), -r * np.cos(th)])
    velocity = np.stack([
        rd * np.sin(th) * np.cos(ph) + r * np.cos(th) * thd * np.cos(ph) - r * np.sin(th) * np.sin(ph) * phd,
        rd * np.sin(th) * np.sin(ph) + r * np.cos(th) * thd * np.sin(ph) + r * np.sin(th) * np.cos(ph) * phd,
        -rd * np.cos(th) + r * np.sin(th) * thd])
    return position, velocity


@pytest.mark.parametrize("spec", [
    CARTESIAN + DASHPOT + "initial: {x: 0.5, y: 0.2, z: -1.1, y_dot: 1.0, z_dot: 0.4}\n",
    pytest.param(SPHERICAL, marks=pytest.mark.slow),   # the same check in spherical coordinates
], ids=["cartesian", "spherical"])
def test_energy_decays_as_the_dissipation_function_predicts(spec):
    traj = lagcli.load(spec).simulate(t_end=4.0, dt=0.002, rtol=1e-11, atol=1e-12)
    assert traj.failure is None
    position, velocity = _bob_in_cartesian(traj)
    delta = position - np.array(ANCHOR)[:, None]
    length_rate = (delta * velocity).sum(axis=0) / np.linalg.norm(delta, axis=0)
    R = 0.8 * length_rate ** 2 / 2                             # 1/2 c (dL/dt)^2, c = 0.8
    dissipated = cumulative_trapezoid(2 * R, traj["t"], initial=0.0)
    energy = traj["energy"]
    assert dissipated[-1] > 0.2                                # joules: a real decay
    np.testing.assert_allclose(energy - energy[0], -dissipated, atol=1e-5 * dissipated[-1])


def _numeric_equations(system, rng: random.Random):
    """M and F of M q'' = F at seeded random states, with the parameters' defaults."""
    d = system.derivation
    values = {p.symbol: p.value for p in system.model.parameters}
    out = []
    for _ in range(5):
        state = {s: rng.uniform(-1.5, 1.5) for s in (*system.model.q, *system.model.qd)}
        subs = {**values, **state, system.model.t: 0.0}
        out.append((np.array(d.mass_matrix.xreplace(subs), dtype=float),
                    np.array(d.forcing.xreplace(subs), dtype=float)))
    return out


def test_rayleigh_dissipation_and_hand_written_forces_match_the_dashpot():
    dashpot = lagcli.load(CARTESIAN + DASHPOT)
    for other in (CARTESIAN + RAYLEIGH, CARTESIAN + BY_HAND):
        for (M1, F1), (M2, F2) in zip(_numeric_equations(dashpot, random.Random(7)),
                                      _numeric_equations(lagcli.load(other), random.Random(7))):
            np.testing.assert_allclose(M1, M2, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(F1, F2, rtol=1e-12, atol=1e-12)


def test_planar_dashpot_along_the_motion_is_the_textbook_damped_oscillator():
    system = lagcli.load("""
coordinates: [x]
parameters: {m: 2.0, c: 0.3, k: 5.0}
particles:
  P: {mass: m, position: [x, 0]}
springs:
  - {between: [P, [-1, 0]], stiffness: k, rest_length: 1}
dampers:
  - {between: [P, [-1, 0]], damping: c}
initial: {x: 0.1}
""")
    m, c, k, x, xd, xdd = (system.model.symbol(name) for name in ("m", "c", "k", "x", "x_dot", "x_ddot"))
    lhs = system.derivation.equations[0].lhs
    textbook = m * xdd + c * xd + k * x
    for value in (sp.Rational(1, 20), sp.Rational(3, 10), 2):   # x > -1: the dashpot pulls along +x
        assert sp.simplify((lhs - textbook).subs(x, value)) == 0
    assert system.derivation.jacobi_integral is None     # Q' != 0: no conserved energy


def test_the_report_shows_the_dashpot_in_the_nonconservative_forces():
    content = lagcli.load(CARTESIAN + DASHPOT).report("dict")
    assert "c" in str(content["generalized_forces"]["x"])
