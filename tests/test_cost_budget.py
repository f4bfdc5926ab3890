"""What a spec may cost is bounded before the work starts (docs/robustness.md): at most
MAX_COORDINATES coordinates (the mass matrix has n^2 entries: ten thousand coordinates
were 10^8 entries before anything said no). The refusal is a case of the bad-spec corpus
(tests/data/bad/too_many_coordinates.yaml); here the bound itself and its edge."""
from __future__ import annotations

import pytest

from lagcli.errors import SpecError
from lagcli.spec.reader import MAX_COORDINATES


def _uncoupled(n: int, springs: bool = True) -> str:
    names = [f"q{i}" for i in range(n)]
    lines = ["coordinates: [" + ", ".join(names) + "]", "parameters: {m: 1.0, k: 2.0}", "particles:"]
    lines += [f"  P{i}: {{mass: m, position: [{q}, 0]}}" for i, q in enumerate(names)]
    if springs:
        lines += ["springs:"] + [f"  - {{between: [P{i}, [0, 0]], stiffness: k}}" for i in range(n)]
    return "\n".join(lines) + "\n"


def test_ten_thousand_coordinates_are_refused_before_any_work(monkeypatch):
    import lagcli
    import lagcli.derive.pipeline as pipeline

    def no_model(*args, **kwargs):
        raise AssertionError("the model was built: the bound came after the work")

    monkeypatch.setattr(pipeline, "build_model", no_model)      # "before any work", checked without a clock
    with pytest.raises(SpecError, match=f"too many coordinates: 10000, the bound is {MAX_COORDINATES}"):
        lagcli.load(_uncoupled(10_000, springs=False))     # with springs: too many YAML items already
