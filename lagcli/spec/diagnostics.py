"""`lagcli check` over several files: one verdict per file, shown as text or as JSON records.

Each file is checked on its own: a broken spec does not stop the others. A verdict
holds the summary of a valid spec, or the error that refused it, and the warnings
raised while checking. `records` turns them into plain data for `check --json`
(docs/derive.md, "check --json"): per file `file`, `valid` and `problems`, each problem
with `file, line, column, path, severity, message, hint` (line and column are null
where unknown: TOML values and errors that are not located).
"""
from __future__ import annotations

import json
import warnings
from dataclasses import dataclass
from typing import Callable

from lagcli.errors import LagcliError, Loc, Problem, SpecError, SpecWarning, clip_message
from lagcli.spec.files import STDIN, STDIN_NAME


@dataclass(frozen=True)
class Verdict:
    file: str
    summary: str | None                 # what `check` prints for a valid spec
    error: LagcliError | None           # why it was refused
    warnings: tuple[SpecWarning, ...]   # each once, in the order raised

    @property
    def valid(self) -> bool:
        return self.error is None


def check_file(path: str, summarise: Callable[[str], str]) -> Verdict:
    """`summarise(path)` (the summary of `lagcli check`), its error and its spec warnings."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SpecWarning)
        try:
            summary, error = summarise(path), None
        except LagcliError as exc:
            summary, error = None, exc
    shown: dict[str, SpecWarning] = {}
    for item in caught:
        if not isinstance(item.message, SpecWarning):
            warnings.showwarning(item.message, item.category, item.filename, item.lineno)
        else:
            shown.setdefault(str(item.message), item.message)
    return Verdict(STDIN_NAME if path == STDIN else path, summary, error, tuple(shown.values()))


def records(verdicts: list[Verdict]) -> list[dict]:
    """One entry per file: {"file", "valid", "problems": [problem records]}."""
    return [{"file": v.file, "valid": v.valid,
             "problems": [*(_record(p, "error") for p in _problems(v)),
                          *(_record(w.problem, "warning") for w in v.warnings)]}
            for v in verdicts]


def to_json(verdicts: list[Verdict]) -> str:
    return json.dumps(records(verdicts), indent=2) + "\n"


def _problems(verdict: Verdict) -> list[Problem]:
    if verdict.error is None:
        return []
    if isinstance(verdict.error, SpecError):
        return verdict.error.problems
    return [Problem(Loc(verdict.file), str(verdict.error))]


def _record(problem: Problem, severity: str) -> dict:
    loc = problem.loc
    return {"file": loc.file, "line": loc.line, "column": loc.column, "path": loc.path,
            "severity": severity, "message": clip_message(problem.message), "hint": clip_message(problem.hint)}
