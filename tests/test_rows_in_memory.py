"""In-memory runs keep floats (lagcli/run/rows.py, lagcli/trajectory.py).

The Python backends hand their rows to the in-memory sink as floats and
`System.simulate` builds its `Trajectory` from them with no CSV text on the way (the
text functions are made to fail here); the compiled driver's `%.17g` lines are read
once, each value the very double Python's own `float` reads from the same text.
"""
from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

import lagcli
from lagcli.run import rows

from conftest import SPECS


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def _no_text(*args, **kwargs):
    raise AssertionError("an in-memory run went through CSV text")


def test_python_backend_rows_reach_the_trajectory_as_floats(monkeypatch):
    """No row of a Python-backend run is formatted or parsed; the energy kept for each row
    is the generated module's invariant at the state kept with it, bit for bit, and it is
    conserved (a conservative pendulum: an independent check of the run)."""
    system = lagcli.load(SPECS / "double_pendulum.yaml")
    module = system.program("python").module           # generated before the text is refused
    monkeypatch.setattr(rows, "format_row", _no_text)
    monkeypatch.setattr(rows, "parse_block", _no_text)
    traj = system.simulate(t_end=1.0)
    assert traj.data.dtype == np.float64 and traj.shape == (101, len(system.layout.header))
    p = [system.layout.parameter_defaults[n] for n in system.layout.parameter_names]
    for row in traj.data[::25]:
        state = row[1:1 + len(system.layout.state_names)]
        assert module.invariants(row[0], state, p)["energy"] == row[traj.columns.index("energy")]
    energy = traj["energy"]
    assert np.max(np.abs(energy - energy[0])) < 1e-7 * max(1.0, abs(energy[0]))


def test_variational_rows_too(monkeypatch):
    system = lagcli.load(SPECS / "double_pendulum.yaml")
    system.program("python")
    monkeypatch.setattr(rows, "format_row", _no_text)
    traj = system.simulate(t_end=0.2, method="variational")
    assert traj.shape == (21, len(system.layout.header)) and traj.failure is None


@pytest.mark.skipif(shutil.which("cc") is None, reason="needs a C compiler")
def test_driver_rows_are_read_exactly(tmp_path):
    """The compiled driver's rows in memory are exactly what `float` reads from its CSV."""
    from lagcli.run.rows import CsvSink, Tee, Trajectory
    import io

    system = lagcli.load(SPECS / "double_pendulum.yaml")
    text, kept = io.StringIO(), Trajectory()
    system.run(_settings(system), {}, system.initial_state(), "c",
               sink=Tee(CsvSink(text), kept))
    lines = text.getvalue().splitlines()
    assert kept.header == lines[0].split(",") and kept.rows == len(lines) - 1 == 101
    exact = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert np.array_equal(kept.data, exact)


def _settings(system):
    from lagcli.run.options import Request, resolve_settings

    return resolve_settings(Request(system.model.source, 1.0), system.layout.settings.as_dict())


def test_the_parser_reads_every_spelling_of_the_driver():
    """C's printf writes nan as `nan` or `-nan`, infinities as `inf`; `%.17g` of a double
    reads back as that double."""
    values = [0.1, -0.0, 1e-300, 5e-324, 1.7976931348623157e308, 2.0 / 3.0, math.pi]
    block = "".join(format(v, ".17g") + ",-nan,inf\n" for v in values)
    data = rows.parse_block(block, 3)
    assert data.shape == (len(values), 3)
    assert [float(x).hex() for x in data[:, 0]] == [v.hex() for v in values]
    assert np.all(np.isnan(data[:, 1])) and np.all(data[:, 2] == math.inf)


def test_a_thinned_copy_keeps_the_same_rows_from_floats_and_from_text():
    """`Decimated` (the data of --plot) keeps rows 0, k, 2k, ... and the last one, whether
    they come as floats (Python backend) or as the driver's lines."""
    from lagcli.run.rows import Decimated

    floats, text = Decimated(limit=10), Decimated(limit=10)
    for sink in (floats, text):
        sink.begin(["t", "x"])
    for start in range(0, 1000, 7):
        block = range(start, min(start + 7, 1000))
        text.add_csv("".join(f"{k},{k * k}\n" for k in block))
        for k in block:
            floats.add_row([float(k), float(k * k)])
    a, b = floats.trajectory().data, text.trajectory().data
    assert np.array_equal(a, b) and a[-1, 0] == 999 and len(a) <= 21
    assert np.array_equal(a[:-1, 0] % floats.stride, np.zeros(len(a) - 1))
