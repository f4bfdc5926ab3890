"""The report's forcing F (`explicit_form.forcing`, built from the equation's terms, each
negated) is the derivation's F, which is found another way (Kane's form: the points'
accelerations dotted with their Jacobians, lagcli/derive/forcing.py): both printed
strings are parsed back and compared at random states, for every bundled spec and a
5-link chain, with the equation's own terms too (lhs = M q'' - F)."""
import sys
from pathlib import Path

import pytest
import sympy as sp

from lagcli.model.calculus import numerically_zero
from lagcli.system import load
from lagcli.render.spec_printer import parse_output

ROOT = Path(__file__).parent.parent
SPECS = sorted((ROOT / "specs").glob("*.yaml"))


def _chain(tmp_path_factory) -> Path:
    sys.path.insert(0, str(ROOT))
    from bench.codegen import spec_text

    path = tmp_path_factory.mktemp("chain") / "chain5.yaml"
    path.write_text(spec_text(5))
    return path


@pytest.fixture(scope="module", params=[*SPECS, "chain5"], ids=lambda p: getattr(p, "stem", p))
def system(request, tmp_path_factory):
    return load(_chain(tmp_path_factory) if request.param == "chain5" else request.param)


def test_the_reports_forcing_is_the_derivations(system):
    d, report = system.derivation, system.report("dict")
    m = d.model
    printed = [parse_output(report["explicit_form"]["forcing"][q.name], m, d.multipliers) for q in m.q]
    lhs = sp.Matrix([parse_output(eq["lhs"], m, d.multipliers) for eq in report["equations"]])
    from_lhs = d.mass_matrix * sp.Matrix(m.qdd) - lhs        # F = M q'' - lhs
    assert numerically_zero([p - F for p, F in zip(printed, d.forcing)], trials=3)
    assert numerically_zero([f - F for f, F in zip(from_lhs, d.forcing)], trials=3)
