"""Equilibria listed once per pose, and explained where the coordinates are singular
(lagcli/analysis/pose.py, singular_chart.py), against rotation matrices built here with
numpy, closed forms and the Maxwell-Klein criterion of the sleeping top."""
from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import lagcli
from conftest import SPECS
from lagcli.cli import cli

DATA = Path(__file__).parent / "data"
OFFSET_BODY = """\
name: offset_body
coordinates: [psi, theta, phi]
parameters: {m: 1.0, h: 0.2, A: 0.01, B: 0.02, C: 0.03, g: 9.81}
gravity: [0, 0, -g]
definitions:
  Rx: h*(cos(psi)*cos(phi) - sin(psi)*cos(theta)*sin(phi))
  Ry: h*(sin(psi)*cos(phi) + cos(psi)*cos(theta)*sin(phi))
  Rz: h*sin(theta)*sin(phi)
bodies:
  body:
    mass: m
    inertia: [A, B, C]
    position: [Rx, Ry, Rz]
    orientation: [[z, psi], [x, theta], [z, phi]]
initial: {psi: 0.3, theta: 1.0, phi: 0.4}
"""


def rotation(axis: str, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return {"x": np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            "y": np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            "z": np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def zxz(psi: float, theta: float, phi: float) -> np.ndarray:
    return rotation("z", psi) @ rotation("x", theta) @ rotation("z", phi)


def test_a_body_hanging_off_its_axis_has_one_hanging_and_one_standing_family(tmp_path):
    # CM at h R e_x: at rest only with R e_x = -e_z (hanging) or +e_z (standing), at any
    # rotation about the vertical. z-x-z angles also give theta = 0 points where the CM is
    # horizontal: stationary in the chart only (it cannot tilt the way gravity pulls).
    spec = tmp_path / "offset_body.yaml"
    spec.write_text(OFFSET_BODY)
    found = lagcli.load(spec).equilibria()
    poses = [zxz(e.point["psi"], e.point["theta"], e.point["phi"]) for e in found]
    heights = sorted(round(float((R @ [1, 0, 0])[2]), 9) for R in poses)
    assert heights == [-1.0, 1.0]
    for Ra, Rb in itertools.combinations(poses, 2):          # not one family: R_b R_a^T no turn about z
        assert abs((Rb @ Ra.T)[2, 2] - 1) > 1e-6
    verdicts = {round(float((R @ [1, 0, 0])[2])): e.verdict for R, e in zip(poses, found)}
    assert verdicts[1] == "unstable" and verdicts[-1] != "unstable"


def _pose_oracle(model, e) -> np.ndarray:
    """Positions and numpy-built rotation matrices of every particle and body at `e`."""
    import sympy as sp

    values = {q: e.point[q.name] for q in model.q} | {p.symbol: p.value for p in (*model.parameters, *model.inputs)}
    values |= {model.t: 0} | {v: 0 for v in model.qd}
    out = []
    for item in (*model.particles, *model.bodies):
        out += [float(sp.sympify(x).xreplace(values)) for x in item.position]
    for body in model.bodies:
        R = np.eye(3)
        for axis, angle in body.rotations:
            R = R @ rotation(axis, float(sp.sympify(angle).xreplace(values)))
        out += list(R.reshape(-1))
    return np.array(out)


def _one_family(a, b, angles) -> bool:
    """Both are of a family along the same coordinates and agree in the others."""
    if not a.free or set(a.free) != set(b.free):
        return False
    return all(abs(math.remainder(a.point[k] - b.point[k], 2 * math.pi) if k in angles
                   else a.point[k] - b.point[k]) < 1e-7 for k in a.point if k not in a.free)


@pytest.mark.parametrize("name", sorted(p.stem for p in SPECS.glob("*.yaml")
                                        if not p.stem.startswith("benchmark_bicycle")))
@pytest.mark.core_specs
def test_every_bundled_spec_lists_each_pose_once(name):
    from lagcli.errors import UsageError
    from lagcli.model.angles import angle_coordinates

    system = lagcli.load(SPECS / f"{name}.yaml")
    try:
        found = system.equilibria()
    except UsageError as exc:
        assert "depend explicitly on t" in str(exc)
        return
    model = system.derivation.model
    poses = [_pose_oracle(model, e) for e in found]
    angles = angle_coordinates(model)
    if model.particles or model.bodies:
        for (a, pa), (b, pb) in itertools.combinations(zip(found, poses), 2):
            assert np.max(np.abs(pa - pb)) > 1e-6, (name, a, b)
    for a, b in itertools.combinations(found, 2):
        assert not _one_family(a, b, angles), (name, a, b)


def test_the_tops_gimbal_lock_is_explained_and_decided():
    # at rest the upright top falls and the hanging one swings, both at
    # omega^2 = m g h / (A + m h^2) about two tilt axes
    for spec in ("heavy_symmetric_top", "heavy_symmetric_top_frames"):
        system = lagcli.load(SPECS / f"{spec}.yaml")
        values = {q.symbol.name: q.value for q in system.derivation.model.parameters}
        omega = math.sqrt(values["m"] * values["g"] * values["h"] / (values["A"] + values["m"] * values["h"] ** 2))
        found = {round(e.point["theta"], 9): e for e in system.equilibria()}
        assert set(found) == {0.0, round(math.pi, 9)}
        up, down = found[0.0], found[round(math.pi, 9)]
        assert up.verdict == "unstable"
        assert sorted(s.real for s in up.eigenvalues) == pytest.approx([-omega, -omega, omega, omega], rel=1e-9)
        assert down.verdict != "unstable"
        assert all(s.real == 0 for s in down.eigenvalues)
        assert sorted(abs(s) for s in down.eigenvalues) == pytest.approx([omega] * 4, rel=1e-9)
        for e in (up, down):
            assert "psi and phi describe the same rotation here: the coordinates are singular, not the physics" \
                in e.singular.notes


def test_spherical_pendulum_poles_hang_stable_and_stand_unstable():
    found = lagcli.load(SPECS / "spherical_pendulum.yaml").equilibria()
    values = {q.symbol.name: q.value for q in lagcli.load(SPECS / "spherical_pendulum.yaml").derivation.model.parameters}
    omega = math.sqrt(values["g"] / values["L"])
    hanging, standing = found                     # theta = 0 (hanging), pi (standing)
    assert (hanging.point["theta"], standing.point["theta"]) == (0.0, pytest.approx(math.pi))
    assert hanging.verdict == "stable" and standing.verdict == "unstable"
    assert sorted(abs(s) for s in hanging.eigenvalues) == pytest.approx([omega] * 4, rel=1e-9)
    assert hanging.singular.notes[0] == "phi moves nothing here: the coordinates are singular, not the physics"


@pytest.mark.parametrize("spin, stable", [(0.97, False), (1.03, True)])
def test_sleeping_top_in_a_regular_chart_follows_maxwell_klein(spin, stable):
    # C^2 w^2 > 4 (A + m h^2) m g h: the top of the docs' "Coordinate singularities"
    system = lagcli.load(DATA / "sleeping_top_cardan.yaml")
    v = {q.symbol.name: q.value for q in system.derivation.model.parameters}
    critical = math.sqrt(4 * (v["A"] + v["m"] * v["h"] ** 2) * v["m"] * v["g"] * v["h"]) / v["C"]
    lin = system.linearize(at={"phi_dot": spin * critical})
    assert (max(s.real for s in lin.eigenvalues) < 1e-9) == stable


def test_text_json_api_and_notebook_list_the_same_equilibria(tmp_path):
    spec = str(SPECS / "heavy_symmetric_top.yaml")
    found = lagcli.load(spec).equilibria()
    text = CliRunner().invoke(cli, ["equilibria", spec]).output
    content = json.loads(CliRunner().invoke(cli, ["equilibria", spec, "--json"]).output)["equilibria"]
    html = found._repr_html_()
    assert [e["coordinates"] for e in content] == [e.point for e in found]
    assert [e["verdict"] for e in content] == [e.verdict for e in found]
    assert [e["coordinate_singularity"] for e in content] == [list(e.singular.notes) for e in found]
    for e in found:
        assert f": {e.verdict}" in text and e.verdict in html and e.singular.notes[0] in html
        assert e.singular.notes[0] in text
