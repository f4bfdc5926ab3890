"""Fuzzing: no spec text may crash lagcli; it either works or raises a LagcliError.

A bounded, deterministic slice of tools/fuzz_campaign.py runs in every test
session (`derandomize=True`: the same examples on every machine and run). Each
example goes through the library in-process: read, validate, build the model,
derive and summarise (`lagcli check`). Any other exception fails the test, and
Hypothesis shrinks it to a small spec. Hangs are caught by pytest-timeout on the
test (a guard for the test run only; lagcli itself has no time limits).
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings

from fuzz_specs import expressions, spec_texts
from lagcli.errors import LagcliError

FUZZ = settings(max_examples=150, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def check_text(text: str, directory: Path) -> None:
    """Run `lagcli check` in-process on `text`; a LagcliError is a proper refusal."""
    from lagcli.commands import check_summary

    path = directory / "fuzz.yaml"
    path.write_text(text, encoding="utf-8")
    try:
        check_summary(str(path))
    except LagcliError as exc:
        exc.render()  # the message itself must render


@pytest.fixture(scope="module")
def workdir():
    with tempfile.TemporaryDirectory() as directory:
        yield Path(directory)


@pytest.mark.timeout(1200)
@FUZZ
@given(text=spec_texts())
def test_random_specs_work_or_are_refused(workdir, text):
    check_text(text, workdir)


@pytest.mark.timeout(600)
@settings(FUZZ, max_examples=300)
@given(potential=expressions, value=expressions, row=expressions, force=expressions)
def test_random_expressions_work_or_are_refused(workdir, potential, value, row, force):
    # a fixed, valid frame around random expressions: deeper into the engine more often
    check_text("coordinates: [x, y]\nparameters: {m: 1.0, k: 2.0, g: " + repr(value) + "}\n"
               "particles:\n  P: {mass: m, position: [x, y]}\n"
               f"potential: {potential!r}\ngeneralized_forces: {{y: {force!r}}}\n"
               f"constraints: [{row!r}]\n", workdir)


CORPUS = sorted(p for folder in ("bad", "warn", "fuzz") for p in (Path(__file__).parent / "data" / folder).iterdir()
                if p.suffix in (".yaml", ".toml"))


@pytest.mark.timeout(300)
@pytest.mark.parametrize("case", CORPUS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_check_and_derive_json_refuse_or_work(case):
    # every spec of the corpora (bad, warnings, fuzz findings and issue 25's reproductions):
    # `check` and `derive --json` end with a result or a LagcliError (exit 0 or 2), never
    # another exception (a traceback), and never hang (pytest-timeout guards the test run)
    import warnings

    from lagcli.commands import check_summary, derive_json

    for command in (check_summary, derive_json):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                command(str(case))
            except LagcliError as exc:
                assert exc.exit_code == 2, exc.render()
                exc.render()
