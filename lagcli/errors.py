"""The exceptions lagcli raises on purpose.

The CLI catches `LagcliError` only and maps it to an exit status; anything else
escaping is a bug.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

MAX_ECHO = 200  # characters of user text (a key, an expression) repeated in a message
_QUOTED = re.compile("'[^'\\n]{%d,}'|\"[^\"\\n]{%d,}\"" % (MAX_ECHO + 3, MAX_ECHO + 3))


def clip(text: str, width: int = MAX_ECHO) -> str:
    """`text`, or its first `width` characters and its length when longer."""
    return text if len(text) <= width else f"{text[:width]}... ({len(text)} characters)"


def clip_message(text: str) -> str:
    """A message with each long quoted piece of user text cut to `MAX_ECHO` characters,
    and the whole cut to a few lines' worth: a 50 KB expression is not echoed back."""
    text = _QUOTED.sub(lambda found: found[0][0] + clip(found[0][1:-1]) + found[0][-1], text)
    return clip(text, 4 * MAX_ECHO)


@dataclass(frozen=True)
class Loc:
    """Where a spec item came from: file, 1-based line/column (YAML only) and key path."""

    file: str
    line: int | None = None
    column: int | None = None
    path: str = ""

    def child(self, key: str | int, line: int | None = None, column: int | None = None) -> "Loc":
        sub = f"{self.path}[{key}]" if isinstance(key, int) else (f"{self.path}.{key}" if self.path else key)
        return Loc(self.file, line if line is not None else self.line,
                   column if column is not None else self.column, sub)

    def __str__(self) -> str:
        where = self.file
        if self.line is not None:
            where += f":{self.line}"
            if self.column is not None:
                where += f":{self.column}"
        return f"{where}: {clip(self.path)}" if self.path else where


@dataclass(frozen=True)
class Problem:
    """One diagnostic: a location, what is wrong, and an optional hint."""

    loc: Loc
    message: str
    hint: str = ""

    def __str__(self) -> str:
        text = f"{self.loc}: {clip_message(self.message)}"
        return text + (f"\n  hint: {clip_message(self.hint)}" if self.hint else "")


def in_reading_order(problems: list[Problem]) -> list[Problem]:
    """`problems` as a reader meets them: by file (in order of first mention), then line and
    column; a problem of a whole file (no line) first; ties keep the order they were found."""
    files = {file: k for k, file in enumerate(dict.fromkeys(p.loc.file for p in problems))}
    return sorted(problems, key=lambda p: (files[p.loc.file], p.loc.line or 0, p.loc.column or 0))


class LagcliError(Exception):
    """Base class of every error lagcli reports to users. `exit_code` is what the CLI returns."""

    exit_code = 1

    def render(self) -> str:
        """The message for stderr: `error: ...` (located problems override this)."""
        return f"error: {clip_message(str(self))}"


class SpecError(LagcliError):
    """The spec (or a command-line override) is invalid: raised by reading, validation and
    model building, with every problem found collected in `problems`. Exit status 2."""

    exit_code = 2

    def __init__(self, problems: list[Problem] | Problem):
        self.problems = in_reading_order([problems] if isinstance(problems, Problem) else list(problems))
        super().__init__("\n".join(str(p) for p in self.problems))

    def render(self) -> str:
        """Compiler-style `file:line:col: key.path: message` lines, as editors expect."""
        return str(self)


class UsageError(LagcliError):
    """A bad command-line value (e.g. `--set` of an unknown parameter). Exit status 2."""

    exit_code = 2


class EmitError(LagcliError):
    """Code or document generation failed (a symbol without a slot, a missing template).
    This is a lagcli bug or an unsupported construct. Exit status 1."""


class SimulationError(LagcliError):
    """Integration failed at run time (step size underflow, NaN, singular matrix,
    compiler missing or failing). Exit status 1; partial results are kept."""


class SpecWarning(UserWarning):
    """A spec that is valid but probably not what was meant (a zero mass, a mass matrix
    singular at the initial state, an expression that is not finite there). Issued with
    `warnings.warn`; the CLI prints it on stderr as `file:line:col: key: warning: ...`
    and the command goes on."""

    def __init__(self, problem: Problem):
        self.problem = problem
        super().__init__(str(problem))

    def render(self) -> str:
        loc, hint = self.problem.loc, self.problem.hint
        text = f"{loc}: warning: {clip_message(self.problem.message)}"
        return text + (f"\n  hint: {clip_message(hint)}" if hint else "")


class RunNote(UserWarning):
    """A remark on how a command did its work that asks nothing of the user (a damaged
    cache entry rebuilt, a private build directory used). Issued with `warnings.warn` by
    layers below the CLI; the CLI prints it with its other notes (`lagcli.cli_options.note`:
    not with -q/--quiet); a library user can filter it like any other warning."""


def warn_spec(problem: Problem) -> None:
    """Issue `problem` as a `SpecWarning` (Python's warnings: the CLI shows them; a library
    user can filter them like any other warning)."""
    import warnings

    warnings.warn(SpecWarning(problem), stacklevel=2)
