"""The typed layout of a system (lagcli/interface.py) against the output format of the
project's docs (docs/design.md, "CSV columns"), written out by hand here."""
from __future__ import annotations

import pytest

from lagcli.interface import Layout, Settings, layout_of


def test_unconstrained_layout_order_and_kinds(derived):
    layout = layout_of(derived("spherical_pendulum"))     # phi is ignorable, h exists
    assert layout.header == ("t", "theta", "phi", "theta_dot", "phi_dot", "energy", "jacobi", "p_phi")
    assert [c.kind for c in layout.columns] == ["time", "coordinate", "coordinate", "velocity",
                                                "velocity", "energy", "jacobi", "momentum"]
    assert layout.column("p_phi").of == "phi"
    assert not layout.constrained


def test_constrained_layout_has_multipliers_and_residual(derived):
    layout = layout_of(derived("cartesian_pendulum"))
    assert layout.multiplier_names == ("lambda_rod",)          # the constraint is named `rod`
    assert layout.multipliers[0].kind == "holonomic"
    assert layout.columns[-1].name == "constraint_residual"
    assert layout.columns[-1].kind == "residual"
    assert [c.kind for c in layout.columns].index("multiplier") == 1 + len(layout.states)


def test_parameters_and_settings_come_from_the_spec(derived):
    d = derived("cartesian_pendulum")
    layout = layout_of(d)
    assert layout.parameter_defaults == {p.symbol.name: p.value for p in d.model.parameters}
    assert layout.settings == d.model.settings


def test_settings_defaults_are_the_documented_ones():
    # README / the project's docs: DOP853, rtol 1e-9, atol 1e-12, dt 0.01, t_end 10
    assert Settings() == Settings(t_end=10.0, dt=0.01, method="DOP853", rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("spec", ["atwood", "rolling_disc", "heavy_symmetric_top"])
def test_layout_json_round_trip(derived, spec):
    layout = layout_of(derived(spec))
    assert Layout.from_json(layout.to_json()) == layout


@pytest.mark.parametrize("spec", ["spherical_pendulum", "cartesian_pendulum", "cart_pole"])
def test_every_code_target_writes_the_layouts_header(derived, spec):
    """The header of the generated Python module (`HEADER`, and the rows `simulate`
    returns), of the Octave and Rust targets and the generated module's row writer all
    come from the one `Layout.header` (written out by hand above for two specs)."""
    import types

    from lagcli.targets.octave import octave_context
    from lagcli.targets.python import python_module
    from lagcli.targets.rust import rust_context

    d = derived(spec)
    layout = layout_of(d)
    module = types.ModuleType("generated")
    exec(compile(python_module(d, layout), "generated", "exec"), module.__dict__)
    assert tuple(module.HEADER) == layout.header
    header, rows = module.simulate(t_end=0.02, dt=0.01)
    assert tuple(header) == layout.header and rows.shape == (3, len(layout.header))
    assert octave_context(d, layout)["header"] == layout.header
    assert rust_context(d, layout)["header"] == layout.header
    assert layout.fields == (layout.state_names + layout.parameter_names + layout.multiplier_names
                             + tuple(c.name for c in layout.invariants))
