"""`rest: true` on an impact event: after the accumulation of its bounces the contact is
held as a constraint and the run goes on (lagcli/run/contact.py), on the Python backend.

Closed forms: the ball dropped from rest at h0 lands at t1 = sqrt(2 h0 / g), bounces with
the speed multiplied by e each time and so accumulates at t_inf = t1 (1 + e)/(1 - e);
from then on it lies on the floor: y = 0, y_dot = 0, and the energy T + V = 0 stays
constant. A constrained pendulum with a floor rests on it at x = sqrt(l^2 - h^2).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import lagcli

from test_hybrid_events import HYBRID, run

SPEC = HYBRID / "bouncing_ball_rest.yaml"


def test_the_ball_rests_on_the_floor_after_its_accumulation_time():
    traj = lagcli.load(SPEC).simulate()
    e, g, h0 = 0.5, 9.81, 1.0
    t1 = math.sqrt(2 * h0 / g)
    t_inf = t1 * (1 + e) / (1 - e)
    times = [r.t for r in traj.events]
    expected = [t1 + sum(2 * e ** j * t1 for j in range(1, k + 1)) for k in range(len(times))]
    assert np.allclose(times[:10], expected[:10], rtol=1e-9, atol=0)           # the bounces before it
    assert times[-1] == pytest.approx(t_inf, abs=1e-6)
    assert traj.t[-1] == 3.0                                                    # the run goes on to t_end
    resting = traj.t > t_inf + 1e-6
    assert resting.sum() > 150
    assert np.all(np.abs(traj["y"][resting]) < 1e-12)
    assert np.all(np.abs(traj["y_dot"][resting]) < 1e-12)
    energy = traj["energy"][resting]
    assert np.all(np.abs(energy) < 1e-12) and np.ptp(energy) < 1e-12
    assert "its contact is held from there on (rest: true)" in traj.end_note


def test_a_pendulum_on_a_floor_rests_there_keeping_its_rod(tmp_path):
    text = (HYBRID / "cartesian_pendulum_floor.yaml").read_text()
    spec = tmp_path / "rest.yaml"
    spec.write_text(text.replace("restitution: e}", "restitution: e, rest: true}").replace("t_end: 3.0", "t_end: 6.0"))
    traj = lagcli.load(spec).simulate()
    last = traj.t > traj.events[-1].t + 1e-6
    assert last.sum() > 100
    assert np.allclose(traj["x"][last], math.sqrt(1.0 - 0.8 ** 2), atol=1e-9)
    assert np.allclose(traj["y"][last], -0.8, atol=1e-12)
    assert np.all(traj["constraint_residual"][last] < 1e-10)
    assert np.ptp(traj["energy"][last]) < 1e-10


def test_without_rest_the_run_ends_at_the_accumulation(tmp_path):
    spec = tmp_path / "ball.yaml"
    spec.write_text(SPEC.read_text().replace(", rest: true", ""))
    traj = lagcli.load(spec).simulate()
    assert traj.t[-1] == pytest.approx(math.sqrt(2 / 9.81) * 3, abs=1e-6) and "the run ends there" in traj.end_note


@pytest.mark.parametrize("item, message", [
    ("{name: top, when: y - 2, action: reset, reset: {y: 0}, rest: true}", "'rest' belongs to an impact, not a reset"),
    ("{name: floor, when: y, action: impact, restitution: e, rest: 'yes'}", "expected true or false"),
])
def test_bad_rest_is_a_located_error(tmp_path, item, message):
    spec = tmp_path / "bad.yaml"
    text = SPEC.read_text()
    start = text.index("  - {name: floor")
    spec.write_text(text[:start] + f"  - {item}\n" + text[text.index("\n", start) + 1:])
    result = run("check", spec)
    assert result.exit_code == 2 and message in result.stderr and "bad.yaml:" in result.stderr, result.stderr


@pytest.mark.parametrize("lang", ["octave", "fmu"])
def test_targets_with_events_refuse_rest_clearly(lang, tmp_path):
    result = run("generate", SPEC, "--lang", lang, "-o", tmp_path / "out")
    assert result.exit_code == 2 and f"--lang {lang} does not implement an event's rest: true yet" in result.stderr
    assert "`lagcli simulate` runs them (--backend python only)" in result.stderr   # C refuses a held contact
