"""`lagcli animate` / `System.animate`: frames put the bodies where the coordinates say.

The expected positions are computed here independently of the model's expressions:
the double pendulum's bobs from (l sin theta, -l cos theta), the rolling disc's centre
(x, y, r cos theta) and its axes from scipy's Rotation of the body-fixed z-x-y angles
(psi, theta, phi). The double pendulum's frame is also checked in pixels: the PNG has
the marker's colour where the axes' transform puts the bob.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from click.testing import CliRunner

import lagcli
from lagcli.cli import cli

from conftest import SPECS, spec_path

pytest.importorskip("matplotlib")
BLUE = np.array([31, 119, 180]) / 255          # matplotlib's tab:blue, the first point's marker
ORANGE = np.array([255, 127, 14]) / 255        # tab:orange, the second's


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


@pytest.fixture(scope="module")
def pendulum():
    system = lagcli.load(spec_path("double_pendulum"))
    return system, system.simulate(t_end=1.0)


def test_double_pendulum_frame_has_the_bobs_where_the_angles_say(pendulum, tmp_path):
    system, traj = pendulum
    png = tmp_path / "frame.png"
    drawing = system.animate(png, trajectory=traj, links=[("origin", "P1"), ("P1", "P2")], traces=["P2"],
                             frame=0.73)
    row = int(np.argmin(np.abs(traj.t - 0.73)))
    th1, th2 = traj["theta1"][row], traj["theta2"][row]
    p1 = np.array([math.sin(th1), -math.cos(th1)])                   # l1 = l2 = 1
    p2 = p1 + np.array([math.sin(th2), -math.cos(th2)])
    for name, expected in (("P1", p1), ("P2", p2)):
        np.testing.assert_allclose(np.ravel(drawing.markers[name].get_data()), expected, atol=1e-12)
    np.testing.assert_allclose(np.array(drawing.links[1].get_data()).T, [p1, p2], atol=1e-12)
    assert drawing.clock.get_text() == f"t = {traj.t[row]:.2f}"
    image = __import__("matplotlib.image", fromlist=["imread"]).imread(png)
    height = image.shape[0]
    for point, colour in ((p1, BLUE), (p2, ORANGE)):                     # one colour per bob
        x, y = drawing.ax.transData.transform(point)
        pixel = image[int(round(height - y)), int(round(x)), :3]
        np.testing.assert_allclose(pixel, colour, atol=0.08)
    x, y = drawing.ax.transData.transform(p2 + [0.3, 0.3])                # away from every artist
    assert not np.allclose(image[int(round(height - y)), int(round(x)), :3], BLUE, atol=0.08)


def test_rolling_disc_frame_has_its_centre_and_axes_where_the_angles_say():
    from scipy.spatial.transform import Rotation

    system = lagcli.load(spec_path("rolling_disc"))
    traj = system.simulate(t_end=0.6)
    drawing = system.animate(trajectory=traj, traces=["disc"], frame=0.5)
    row = int(np.argmin(np.abs(traj.t - 0.5)))
    x, y, psi, theta, phi = (traj[n][row] for n in ("x", "y", "psi", "theta", "phi"))
    r = system.layout.parameter_defaults["r"]
    centre = np.array([x, y, r * math.cos(theta)])
    np.testing.assert_allclose(np.ravel(drawing.markers["disc"].get_data_3d()), centre, atol=1e-12)
    R = Rotation.from_euler("ZXY", [psi, theta, phi]).as_matrix()        # intrinsic z, then x, then y
    half = [math.sqrt(3) / 2 * r, 0.0, math.sqrt(3) / 2 * r]           # a uniform disc's box: sqrt(3/4) r
    for k, line in enumerate(drawing.axes["disc"]):
        ends = np.array(line.get_data_3d()).T
        np.testing.assert_allclose(ends, [centre - half[k] * R[:, k], centre + half[k] * R[:, k]], atol=1e-12)
    # the contact point, centre - r b_z with b_z the leaned (not spun) frame's z axis, is on the ground
    b_z = Rotation.from_euler("ZX", [psi, theta]).as_matrix()[:, 2]
    assert abs((centre - r * b_z)[2]) < 1e-12


def test_gif_has_one_frame_per_output_step(pendulum, tmp_path):
    from PIL import Image

    system, traj = pendulum
    gif = tmp_path / "motion.gif"
    system.animate(gif, trajectory=traj, links=[("origin", "P1"), ("P1", "P2")], fps=10)
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.n_frames == 11          # t = 0, 0.1, ..., 1.0


def test_cli_animates_a_csv_of_simulate(tmp_path):
    csv = tmp_path / "traj.csv"
    spec = str(spec_path("double_pendulum"))
    assert CliRunner().invoke(cli, ["simulate", spec, "--t-end", "0.5", "-o", str(csv)]).exit_code == 0
    result = CliRunner().invoke(cli, ["animate", spec, "--csv", str(csv), "--link", "origin:P1",
                                      "--frame", "0.2", "-o", str(tmp_path / "f.png")])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "f.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("args, expected", [
    (["-o", "m.avi"], "expected a .gif, .mp4, or a .png, .svg or .pdf"),
    (["-o", "m.png"], "give --frame T"),
    (["--link", "origin:P9", "--frame", "0", "-o", "m.png"], "unknown point 'P9'"),
    (["--link", "P1", "-o", "m.gif"], "expected A:B"),
])
def test_bad_animate_options_exit_2(tmp_path, args, expected):
    csv = tmp_path / "traj.csv"
    csv.write_text("t,theta1,theta2,theta1_dot,theta2_dot\n0,1,0.5,0,0\n")
    args = [a if not a.startswith("m.") else str(tmp_path / a) for a in args]
    result = CliRunner().invoke(cli, ["animate", str(spec_path("double_pendulum")), "--csv", str(csv), *args])
    assert result.exit_code == 2 and expected in result.output


# --- plots: panels by kind, --columns, --phase (lagcli/viz/plot.py) -------------------

def test_angles_are_told_from_the_model():
    from lagcli.derive.pipeline import load_model
    from lagcli.model.angles import angle_coordinates

    assert angle_coordinates(load_model(spec_path("rolling_disc"))) == {"psi", "theta", "phi"}
    assert angle_coordinates(load_model(spec_path("cart_pole"))) == {"theta"}
    assert angle_coordinates(load_model(spec_path("cartesian_pendulum"))) == set()


def test_simulate_plot_groups_the_chosen_columns_by_kind(tmp_path):
    png = tmp_path / "p.png"
    result = CliRunner().invoke(cli, ["simulate", str(spec_path("cart_pole")), "--t-end", "0.5", "-o",
                                      str(tmp_path / "c.csv"), "--plot", str(png), "--columns",
                                      "theta_dot,x,theta,energy", "--phase", "theta"])
    assert result.exit_code == 0, result.output
    from lagcli.viz.plot import PlotOptions, build_figure
    from lagcli.run.rows import Trajectory

    header, *lines = (tmp_path / "c.csv").read_text().splitlines()
    figure = build_figure(Trajectory(header.split(","), lines), ["x", "theta"], True, "cart",
                          PlotOptions(("theta_dot", "x", "theta", "energy"), ("theta",), frozenset({"theta"}),
                                      {"x": "m"}, lagcli.load(spec_path("cart_pole")).layout.kinds))
    labels = [ax.get_ylabel() for ax in figure.axes]
    assert labels == ["angle (rad)", "x [m]", "velocities", "invariants", "drift / residual", "theta_dot"]
    assert [t.get_text() for t in figure.axes[1].get_legend().get_texts()] == ["x [m]"]
    assert figure.axes[-1].get_xlabel() == "theta"
    bad = CliRunner().invoke(cli, ["simulate", str(spec_path("cart_pole")), "--t-end", "0.1", "-o",
                                   str(tmp_path / "c2.csv"), "--plot", str(tmp_path / "q.png"), "--columns", "zz"])
    assert bad.exit_code == 2 and "no column 'zz'" in bad.output


def test_rolling_disc_is_drawn_as_its_rim_touching_its_plane():
    """The wheel of a rolling element is drawn as its rim, of the wheel's radius, about the
    wheel's axis; at every frame the rim's lowest point is on the ground (the rolling
    contact, z = 0, the physics the rim must show), the plane is drawn, and the centre's
    path is traced."""
    system = lagcli.load(spec_path("rolling_disc_frames"))
    traj = system.simulate(t_end=0.5)
    drawing = system.animate(trajectory=traj, frame=0.4)
    r = system.layout.parameter_defaults["r"]
    for k in range(0, len(traj.t), 10):
        rim = drawing.scene.rim("disc", traj.t[k], traj.states[k], drawing.p)
        centre = np.array([traj["x"][k], traj["y"][k], r * math.cos(traj["theta"][k])])
        np.testing.assert_allclose(np.linalg.norm(rim - centre, axis=1), r, rtol=1e-12)
        assert abs(rim[:, 2].min()) < r * (1 - math.cos(math.pi / 24)) + 1e-12   # to the rim's polygon
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    assert any(isinstance(c, Poly3DCollection) for c in drawing.ax.collections)
    assert drawing.trace_names == ("disc",)


def test_dampers_are_drawn_between_their_ends(tmp_path):
    spec = tmp_path / "damped.yaml"
    spec.write_text("coordinates: [x]\nparameters: {m: 1.0, k: 4.0, c: 0.5}\n"
                    "particles: {P: {mass: m, position: [x, 0]}}\n"
                    "springs: [{between: [P, [0, 0]], stiffness: k, rest_length: 0}]\n"
                    "dampers: [{between: [P, [0, 0]], damping: c}]\ninitial: {x: 1.0}\n")
    system = lagcli.load(spec)
    traj = system.simulate(t_end=1.0)
    drawing = system.animate(trajectory=traj, frame=0.5)
    row = int(np.argmin(np.abs(traj.t - 0.5)))
    (line,) = drawing.dampers
    np.testing.assert_allclose(np.array(line.get_data()).T, [[traj["x"][row], 0], [0, 0]], atol=1e-12)
    assert line.get_linestyle() == "--"


def test_a_fast_spinning_angle_gets_its_own_panel():
    """The rolling disc's spin angle phi grows to tens of rad while the tilt theta moves
    by hundredths: they are drawn on separate axes (each panel's columns within a factor
    SCALE_SPLIT of each other's range), not one flattening the other."""
    from lagcli.viz.plot import SCALE_SPLIT, by_scale

    column = {"a": np.array([0.0, 0.1]), "b": np.array([0.0, 0.5]), "c": np.array([0.0, 500.0])}
    assert by_scale([("angle (rad)", ["c", "a", "b"])], column) == [("angle (rad)", ["a", "b"]),
                                                                    ("angle (rad)", ["c"])]
    system = lagcli.load(spec_path("rolling_disc_frames"))
    figure = system.simulate(t_end=3.0).plot()
    lines = {line.get_label(): ax for ax in figure.axes for line in ax.get_lines()}
    assert lines["phi"] is not lines["theta"]
    for ax in figure.axes[:-1]:
        spans = [float(np.ptp(line.get_ydata())) for line in ax.get_lines()]
        if len(spans) > 1 and min(spans) > 0:
            assert max(spans) <= SCALE_SPLIT * min(spans)


def test_the_floor_of_an_impact_or_a_landing_is_drawn():
    """An impact or stop event whose gap is a point's coordinate plus a constant is drawn as
    that surface: the ball's floor y = 0, the Cartesian pendulum's floor y = -h (h = 0.8 in
    its spec), a 3-D ball's floor z = 0 as a plane; a gap in an angle draws nothing."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    def horizontal_lines(name):
        system = lagcli.load(SPECS / "hybrid" / f"{name}.yaml")
        drawing = system.animate(trajectory=system.simulate(t_end=0.5), frame=0.2)
        return [line.get_ydata()[0] for line in drawing.ax.get_lines()
                if len(line.get_ydata()) == 2 and line.get_ydata()[0] == line.get_ydata()[1]
                and tuple(line.get_xdata()) == (0, 1)]

    assert horizontal_lines("bouncing_ball") == [0.0]
    assert horizontal_lines("cartesian_pendulum_floor") == [-0.8]
    assert horizontal_lines("pendulum_wall") == []
    ball = lagcli.load("coordinates: [x, y, z]\nparameters: {m: 1.0, g: 9.81}\ngravity: [0, 0, -g]\n"
                       "particles: {P: {mass: m, position: [x, y, z]}}\n"
                       "events: [{name: floor, when: z, action: impact, restitution: 0.5}]\n"
                       "initial: {z: 1.0, x_dot: 0.3}\n")
    drawing = ball.animate(trajectory=ball.simulate(t_end=1.0), frame=0.5)
    assert len([c for c in drawing.ax.collections if isinstance(c, Poly3DCollection)]) == 1
    ((axis, value),) = drawing.scene.surfaces
    assert axis == 2 and float(np.ravel(value(drawing.p))[0]) == 0.0


@pytest.mark.parametrize("x_unit, l_unit, label", [(None, None, "x"), ("m", "m", "x [m]"), ("mm", "mm", "x [mm]"),
                                                   ("m", "mm", "x")])
def test_the_views_axes_carry_the_length_unit_when_the_spec_gives_units(tmp_path, x_unit, l_unit, label):
    """Units on every axis (issue 21): the view's axes carry the unit the spec gives its
    lengths (a coordinate x and a pendulum length l); none without units, and none when
    the spec mixes units of length (lagcli does not rescale, so no one unit is right)."""
    spec = tmp_path / "units.yaml"
    unit = lambda u, extra="": f", unit: {u}{extra}" if u else ""
    spec.write_text(f"coordinates: [{{name: x{unit(x_unit)}}}, theta]\n"
                    f"parameters: {{m: {{value: 1.0{unit(x_unit and 'kg')}}}, l: {{value: 0.5{unit(l_unit)}}},"
                    f" g: {{value: 9.81{unit(x_unit and (x_unit + '/s^2'))}}}}}\n"
                    "gravity: [0, -g]\nparticles: {C: {mass: m, position: [x, 0]},"
                    " P: {mass: m, position: [x + l*sin(theta), -l*cos(theta)]}}\ninitial: {theta: 0.3}\n")
    system = lagcli.load(spec)
    drawing = system.animate(trajectory=system.simulate(t_end=0.2), frame=0.1)
    assert drawing.ax.get_xlabel() == label and drawing.ax.get_ylabel() == label.replace("x", "y", 1)
