"""The Python API (lagcli.load -> System -> Trajectory), notebook style, and the
examples of docs/api.md, which are executed here as doctests."""
from __future__ import annotations

import doctest
import math
import re
import shutil
import subprocess

import numpy as np
import pytest

import lagcli
from lagcli.errors import SpecError

from conftest import ROOT, SPECS

PENDULUM_TEXT = (SPECS / "cartesian_pendulum.yaml").read_text()


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def test_docs_api_examples_run(monkeypatch):
    monkeypatch.chdir(ROOT)                         # the examples use specs/... paths
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "api.md").read_text(), flags=re.S)
    text = "\n".join(blocks)                      # the ```python blocks, run as one session
    test = doctest.DocTestParser().get_doctest(text, {}, "docs/api.md", str(ROOT / "docs" / "api.md"), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.failures == 0 and runner.tries > 10


def test_notebook_session(tmp_path):
    """Load from a path and from a string, simulate with new parameters, arrays and a
    DataFrame, LaTeX for the notebook, generate C that compiles."""
    from_path = lagcli.load(SPECS / "cartesian_pendulum.yaml")
    from_text = lagcli.load(PENDULUM_TEXT)
    assert from_path.layout.columns == from_text.layout.columns
    trajectory = from_text.simulate(t_end=2.0, parameters={"l": 2.0, "g": 1.0})
    x, y, xd, yd = (trajectory[name] for name in ("x", "y", "x_dot", "y_dot"))
    assert np.max(np.abs(x ** 2 + y ** 2 - 4.0)) < 1e-8              # the new rod length
    assert np.max(np.abs(x * xd + y * yd)) < 1e-8                     # velocity along the circle
    energy = trajectory["energy"]
    assert np.max(np.abs(energy - energy[0])) < 1e-8                  # conserved
    # small-amplitude check is not possible here (amplitude is large): compare the
    # energy with its closed form instead, m (x'^2 + y'^2)/2 + m g y with m = 1, g = 1
    assert energy[0] == pytest.approx(0.5 * (xd[0] ** 2 + yd[0] ** 2) + y[0], abs=1e-12)
    frame = trajectory.to_pandas() if _has_pandas() else None
    if frame is not None:
        assert list(frame.columns) == list(trajectory.columns[1:]) and frame.index.name == "t"
        assert frame["x"].to_numpy() == pytest.approx(x)
        assert frame.index.to_numpy() == pytest.approx(trajectory.t)
    latex = from_path._repr_latex_()
    assert latex.startswith("$$") and r"\lambda_{\mathrm{rod}}" in latex
    files = from_path.generate("c", tmp_path / "c")
    assert (tmp_path / "c" / "cartesian_pendulum.h").read_text() == files["cartesian_pendulum.h"]
    if shutil.which("cc"):
        done = subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic",
                               *sorted(n for n in files if n.endswith(".c")), "-o", "pend", "-lm"],
                              cwd=tmp_path / "c", capture_output=True, text=True)
        assert done.returncode == 0, done.stderr


def test_small_oscillations_match_the_closed_form():
    """A pendulum of length 2 released from 0.01 rad: x(t) = l th0 cos(sqrt(g/l) t)."""
    system = lagcli.load(SPECS / "cartesian_pendulum.yaml")
    th0, l, g = 0.01, 2.0, 9.81
    start = {"x": l * math.sin(th0), "y": -l * math.cos(th0), "x_dot": 0.0, "y_dot": 0.0}
    trajectory = system.simulate(t_end=1.0, dt=0.1, parameters={"l": l}, initial=start)
    expected = l * th0 * np.cos(math.sqrt(g / l) * trajectory.t)
    assert np.max(np.abs(trajectory["x"] - expected)) < 1e-5         # O(th0^3) from the linearisation


def test_csv_of_the_api_is_the_cli_csv():
    from click.testing import CliRunner

    from lagcli.cli import cli

    spec = SPECS / "atwood.yaml"
    api = lagcli.load(spec).simulate(t_end=0.5, parameters={"L": 12.0}).to_csv()
    cli_run = CliRunner().invoke(cli, ["simulate", str(spec), "--t-end", "0.5", "--set", "L=12",
                                       "--backend", "python"])
    assert cli_run.exit_code == 0
    assert cli_run.stdout == api


def test_bad_text_spec_is_located_in_string():
    with pytest.raises(SpecError) as caught:
        lagcli.load("coordinates: [x, p_x]\nkinetic: x_dot**2/2\n")
    assert str(caught.value).startswith("<string>:1:18: coordinates[1]: the name 'p_x' is reserved")


def _has_pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def test_plot_gives_the_simulate_figure(tmp_path):
    pytest.importorskip("matplotlib")
    trajectory = lagcli.load(SPECS / "cartesian_pendulum.yaml").simulate(t_end=0.2)
    figure = trajectory.plot(tmp_path / "p.png")
    assert (tmp_path / "p.png").read_bytes().startswith(b"\x89PNG")
    assert [line.get_label() for line in figure.axes[0].get_lines()] == ["x", "y"]


def test_parts_show_the_derivation():
    """system.parts: the double pendulum's mass matrix against its closed form, the
    text parsing back, LaTeX with dots, and a missing part named."""
    import sympy as sp

    from lagcli.render.spec_printer import parse_output

    system = lagcli.load(SPECS / "double_pendulum.yaml")
    m1, m2, l1, l2, th1, th2 = (system.model.symbol(n) for n in ("m1", "m2", "l1", "l2", "theta1", "theta2"))
    closed = sp.Matrix([[(m1 + m2) * l1 ** 2, m2 * l1 * l2 * sp.cos(th1 - th2)],
                        [m2 * l1 * l2 * sp.cos(th1 - th2), m2 * l2 ** 2]])
    mass = system.parts.mass_matrix
    assert sp.simplify(mass.value - closed) == sp.zeros(2, 2)
    lagrangian = system.parts.lagrangian
    assert sp.simplify(parse_output(repr(lagrangian).removeprefix("L = "), system.model) - lagrangian.value) == 0
    assert r"\dot{\theta}_1" in lagrangian._repr_latex_()         # the spec's latex: \theta_1
    assert len(system.parts.equations.value) == 2
    with pytest.raises(AttributeError, match="no constraints"):
        system.parts.constraints
    assert "constraints" not in dir(system.parts)


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_the_c_backend_of_the_api_agrees_with_the_python_backend():
    """A spec given as text, new parameters: the compiled driver and scipy give the same
    trajectory, on the rod of the new length."""
    from lagcli.errors import UsageError

    system = lagcli.load(PENDULUM_TEXT)
    compiled = system.simulate(t_end=1.0, parameters={"l": 2.0}, backend="c")
    scipy_run = system.simulate(t_end=1.0, parameters={"l": 2.0}, backend="python")
    assert compiled.names == scipy_run.names and compiled.notes == scipy_run.notes
    assert np.max(np.abs(compiled.data - scipy_run.data)) < 1e-7
    x, y = compiled["x"], compiled["y"]
    assert np.max(np.abs(x ** 2 + y ** 2 - 4.0)) < 1e-8 and compiled.failure is None
    with pytest.raises(UsageError, match="RK45, DOP853 and variational only"):
        system.simulate(method="Radau", backend="c")


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_the_cached_driver_carries_the_layout(tmp_path):
    """meta.json of the compiled driver is the system's Layout (its own JSON), which the
    warm path reads back without sympy."""
    from lagcli.interface import Layout
    from lagcli.run import c_backend

    system = lagcli.load(PENDULUM_TEXT)
    system.simulate(t_end=0.1, backend="c")
    cached = system.program("c")
    meta = cached.entry.contents[c_backend.META]
    assert Layout.from_json(meta) == system.layout == cached.layout
    assert cached.layout.start.values == system.initial_state().values
    assert [c.kind for c in cached.layout.columns][-1] == "residual"
