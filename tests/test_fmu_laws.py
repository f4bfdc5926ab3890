"""Input laws inside the FMU (`--lang fmu` of a spec with `simulate: inputs:`): the law runs
in the FMU and its FMI input adds to it. FMPy's CVode run against `lagcli simulate`."""
from __future__ import annotations

import shutil

import numpy as np
import pytest

import lagcli

from test_hybrid_events import HYBRID

fmpy = pytest.importorskip("fmpy")
pytestmark = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc): the FMU cannot be built")

LAW = "k1*x + k2*theta + k3*x_dot + k4*theta_dot"


@pytest.fixture(scope="module")
def cart_pole(tmp_path_factory):
    system = lagcli.load(HYBRID / "cart_pole_lqr.yaml")
    path = tmp_path_factory.mktemp("fmu") / "cart_pole_lqr.fmu"
    (data,) = system.generate("fmu").values()
    path.write_bytes(data)
    return system, str(path)


def run_fmu(path, **options):
    return fmpy.simulate_fmu(path, stop_time=3.0, output_interval=0.01, solver="CVode", relative_tolerance=1e-12,
                             output=["x", "theta", "x_dot", "theta_dot"], **options)


def test_lqr_law_runs_inside_the_fmu(cart_pole):
    """The LQR law brings the pole back upright in FMPy as in lagcli simulate (1e-9)."""
    system, path = cart_pole
    result = run_fmu(path)
    expected = system.simulate(t_end=3.0, rtol=1e-12, atol=1e-14)
    for name in ("x", "theta", "x_dot", "theta_dot"):
        assert np.allclose(result[name], expected[name], rtol=0, atol=1e-9), name
    assert abs(result["theta"][-1]) < 0.01


def test_the_fmu_input_adds_to_the_law(cart_pole):
    """F = 0.3 given to the FMU input: the motion of the law F = 0.3 - K x (1e-9)."""
    system, path = cart_pole
    signal = np.array([(0.0, 0.3), (3.0, 0.3)], dtype=[("time", float), ("F", float)])
    result = run_fmu(path, input=signal)
    expected = system.simulate(t_end=3.0, rtol=1e-12, atol=1e-14, inputs={"F": f"0.3 - ({LAW})"})
    for name in ("x", "theta"):
        assert np.allclose(result[name], expected[name], rtol=0, atol=1e-9), name
    description = fmpy.read_model_description(path)
    (F,) = [v for v in description.modelVariables if v.name == "F"]
    assert F.causality == "input" and F.description == "added to its law -k1*x - k2*theta - k3*x_dot - k4*theta_dot"
