"""`lagcli simulate` against independent results: closed forms and conservation laws.

Each test runs the CLI on both backends (python; c, skipped without `cc`) and
checks the CSV against a result derived by hand, not by lagcli:

- the lecture notes' Ex 6-9 (two wheels on an axle): x = (v0/w) sin wt, y = (v0/w)(1 - cos wt),
  lambda = -2 m v0 w (the notes' closed-form solution);
- the lecture notes' Ex 19 (wedge): x1 = a t^2 / 2 with a = m2 g / (2 m1 + m2);
- double pendulum: the energy is conserved;
- spherical pendulum: p_phi = m L^2 sin^2(theta) phi_dot is conserved;
- Kapitza pendulum: upright is stable iff a^2 w^2 > 2 g l;
- the lecture notes' Ex 20: the Jacobi integral is conserved, the energy T + V is not;
- Cartesian pendulum: the Baumgarte-stabilised rod constraint stays satisfied;
- disc rolling down an incline and the Atwood machine (over their `simulate:`
  blocks, default Baumgarte gains): s = g sin(alpha) t^2 / 3, friction multiplier
  -m g sin(alpha) / 3; y1'' = (m1 - m2) g / (m1 + m2), rope tension as multiplier,
  constraints kept to 1e-10 (with the step controller running the stabilisation
  mode at its stability edge they drifted to 1e-6).
"""
from __future__ import annotations

import math
import shutil

import numpy as np
import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.run.rows import parse_csv

from conftest import spec_path

BACKENDS = ["python", pytest.param("c", marks=pytest.mark.skipif(shutil.which("cc") is None,
                                                                 reason="no C compiler (cc)"))]


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    """One driver cache for the whole session, outside the user's home."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


@pytest.fixture(params=BACKENDS)
def run(request):
    """`run(spec, *options)` -> {column: values} from `lagcli simulate --backend <param>`."""
    return lambda spec, *options: _run(spec, "--backend", request.param, *options)


def _run(spec: str, *options: str) -> dict[str, np.ndarray]:
    result = CliRunner().invoke(cli, ["simulate", str(spec_path(spec)), *options], catch_exceptions=False)
    assert result.exit_code == 0, result.stderr
    header, rows = parse_csv(result.stdout)
    data = np.array(rows)
    return {name: data[:, i] for i, name in enumerate(header)}


def test_two_wheels_axle_closed_form(run):
    c = run("ex6_9_two_wheels_axle", "--t-end", "10", "--dt", "0.05", "--rtol", "1e-11", "--atol", "1e-13")
    t, v0, w, m = c["t"], 1.0, 2.0, 1.0            # the spec's initial state and mass
    assert t[-1] == 10.0
    assert np.max(np.abs(c["x"] - v0 / w * np.sin(w * t))) < 1e-8
    assert np.max(np.abs(c["y"] - v0 / w * (1 - np.cos(w * t)))) < 1e-8
    assert np.max(np.abs(c["phi"] - w * t)) < 1e-8
    assert np.max(np.abs(c["lambda_1"] - (-2 * m * v0 * w))) < 1e-8


def test_wedge_accelerates_uniformly(run):
    c = run("ex19_wedge", "--t-end", "2", "--dt", "0.1")
    m1, m2, g = 2.0, 1.0, 9.81
    a = m2 * g / (2 * m1 + m2)
    assert np.max(np.abs(c["x1"] - a * c["t"] ** 2 / 2)) < 1e-9


def test_double_pendulum_conserves_energy(run):
    c = run("double_pendulum", "--t-end", "20", "--rtol", "1e-11", "--atol", "1e-13", "--dt", "0.05")
    energy = c["energy"]
    assert np.max(np.abs(energy - energy[0])) / abs(energy[0]) < 1e-9
    assert np.allclose(c["jacobi"], energy, rtol=0, atol=1e-12)


def test_spherical_pendulum_conserves_p_phi(run):
    c = run("spherical_pendulum", "--t-end", "5", "--dt", "0.05", "--rtol", "1e-11", "--atol", "1e-13")
    m, L = 1.0, 1.0
    p_phi = m * L**2 * np.sin(c["theta"]) ** 2 * c["phi_dot"]     # independent formula
    assert np.allclose(c["p_phi"], p_phi, rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(c["p_phi"] - c["p_phi"][0])) < 1e-9
    assert p_phi[0] == pytest.approx(math.sin(1.0) ** 2 * 2.0)


def test_kapitza_pendulum_stays_up_when_shaken_fast(run):
    a, w, g, l = 0.02, 200.0, 9.81, 0.2
    assert a**2 * w**2 > 2 * g * l
    c = run("kapitza_pendulum", "--t-end", "3", "--dt", "0.01")
    assert np.max(np.abs(c["theta"] - math.pi)) < 0.5


def test_kapitza_pendulum_falls_when_shaken_slowly(run):
    a, w, g, l = 0.02, 60.0, 9.81, 0.2
    assert a**2 * w**2 < 2 * g * l
    c = run("kapitza_pendulum", "--t-end", "3", "--dt", "0.01", "--set", f"w={w}")
    assert np.max(np.abs(c["theta"] - math.pi)) > 2.0


def test_spinning_disk_conserves_jacobi_not_energy(run):
    c = run("ex20_spinning_disk_double_pendulum", "--t-end", "5", "--dt", "0.05")
    h, e = c["jacobi"], c["energy"]
    assert np.max(np.abs(h - h[0])) < 1e-9 * max(1.0, abs(h[0]))
    assert np.max(np.abs(e - e[0])) > 1e-3


def test_cartesian_pendulum_stays_on_the_rod(run):
    c = run("cartesian_pendulum", "--t-end", "20", "--dt", "0.05")
    assert np.max(c["constraint_residual"]) < 1e-8
    assert np.max(np.abs(np.hypot(c["x"], c["y"]) - 1.0)) < 1e-8       # l = 1
    energy = c["energy"]
    assert np.max(np.abs(energy - energy[0])) < 1e-7 * abs(energy[0])


def test_disc_rolls_down_the_incline_uniformly(run):
    c = run("disc_on_incline")                     # the spec's block: 5 s, output every 0.01 s
    m, g, slope = 1.0, 9.81, math.pi / 6
    a = g * math.sin(slope) / (1 + 1 / 2)          # I = m r^2 / 2: a = g sin(alpha) / (1 + I/(m r^2))
    t = c["t"]
    assert t[-1] == 5.0
    assert np.max(np.abs(c["s"] - a * t**2 / 2)) < 1e-9
    assert np.max(np.abs(c["s_dot"] - a * t)) < 1e-9
    # m s'' = m g sin(alpha) + lambda * 1 (rolling row a = [1, -r]): friction up the slope
    assert np.max(np.abs(c["lambda_rolling"] - (m * a - m * g * math.sin(slope)))) < 1e-9
    assert np.max(c["constraint_residual"]) < 1e-10


def test_atwood_machine_accelerates_uniformly(run):
    c = run("atwood")
    m1, m2, g = 1.05, 1.0, 9.81
    a = (m1 - m2) * g / (m1 + m2)                  # y1 is depth below the pulley: heavier m1 sinks
    t = c["t"]
    assert np.max(np.abs(c["y1"] - (5.0 + a * t**2 / 2))) < 1e-9
    assert np.max(np.abs(c["y1"] + c["y2"] - 10.0)) < 1e-10
    tension = 2 * m1 * m2 * g / (m1 + m2)
    assert np.max(np.abs(np.abs(c["lambda_rope"]) - tension)) < 1e-9
    assert np.max(c["constraint_residual"]) < 1e-10
