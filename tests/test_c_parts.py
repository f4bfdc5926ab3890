"""The generated C of a big system in parts (lagcli/targets/c_parts.py).

No bundled spec is big enough to be split (checked here), so the split is tested on bundled
specs with its threshold lowered to 0 and parts of a few statements: the C model evaluates
to the Derivation's values at seeded random states (the mpmath reference of
test_codegen_python.py), through the big system's CSE (`linear_cse`, budget 0) as a big
system goes, and through sympy's; the parts' loads and stores are checked on their own.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from test_codegen_python import compare, random_inputs

ROOT = Path(__file__).resolve().parent.parent
SPECS = ["double_pendulum", "ex6_9_two_wheels_axle", "rolling_disc", "cart_pole",
         "ex18_slider_compound_pendulum", "benchmark_bicycle"]


@pytest.fixture
def in_parts(monkeypatch):
    """Every body of more than 0 statements split into parts of 7."""
    from lagcli.targets import c_parts

    monkeypatch.setattr(c_parts, "MAX_STATEMENTS", 0)
    monkeypatch.setattr(c_parts, "PART_STATEMENTS", 7)


@pytest.mark.parametrize("linear", [True, False], ids=["linear_cse", "sympy_cse"])
@pytest.mark.parametrize("name", SPECS)
def test_c_model_in_parts_agrees_with_engine(name, linear, in_parts, monkeypatch, derived, rng, tmp_path):
    test_codegen_c = pytest.importorskip("test_codegen_c")
    if test_codegen_c.CC is None:
        pytest.skip("no C compiler (cc)")
    if linear:
        from lagcli.targets import cse

        monkeypatch.setattr(cse, "LINEAR_CSE_MIN_NODES", 0)
    built = test_codegen_c.Built(ROOT / "specs" / f"{name}.yaml", tmp_path)
    source = (tmp_path / f"{built.name}.c").read_text()
    assert f"static void {built.name}_rhs_part2(" in source, "the right-hand side was not split"
    d = derived(f"{name}.yaml")
    for i, case in enumerate(random_inputs(d, rng)):
        compare(d, case, test_codegen_c.call(built, d, case), f"{name} state {i}")


def test_each_part_loads_what_earlier_parts_stored():
    from lagcli.targets.c_parts import split_body

    temporaries = [("x0", "y[0]"), ("x1", "x0*x0"), ("x2", "sin(x1)"), ("x3", "x2 + x0"), ("x4", "p[0]")]
    stores = ["M[0] = x3*x1;", "M[1] = x4;", "M[2] = x10;"]    # x10: not a temporary of this body
    split = split_body(temporaries, stores, after=["x2 + y[1]"], limit=0, size=3)
    assert [len(part.statements) for part in split.parts] == [3, 3, 2]
    stored: dict = {}
    for part in split.parts:
        assert all(stored.get(slot) == name for name, slot in part.loads)
        stored.update(part.stores)
    assert [name for name, _ in split.parts[1].loads] == ["x0", "x1", "x2"]
    assert [name for name, _ in split.parts[2].loads] == ["x4"]
    assert [name for name, _ in split.after] == ["x2"] and stored[split.after[0][1]] == "x2"
    assert split.shared == len(set(stored)) == 4
    assert split_body(temporaries, stores) is None          # small: one body


def test_no_bundled_spec_reaches_the_threshold(derived):
    from lagcli.interface import layout_of
    from lagcli.targets.c import body_parts, c_context

    for spec in sorted((ROOT / "specs").glob("*.yaml")):
        d = derived(spec.name)
        assert not any(body_parts(c_context(d, layout_of(d))).values()), spec.name
