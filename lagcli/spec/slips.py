"""Hints for the common slips of spec writing, recognised from the text where reading failed.

Each function looks at text that already failed (an expression that is not valid
syntax, a YAML line the scanner refused, a TOML table) and says what was probably
meant; '' when nothing is recognised. Only hints: the error itself is raised where
the problem was found.
"""
from __future__ import annotations

import re

from lagcli.errors import Problem

_LONE_EQUALS = re.compile(r"(?<![=<>!])=(?!=)")
_NUMBER_THEN_WORD = re.compile(r"^\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s+([A-Za-z][A-Za-z0-9_*/^ ]*)\s*$")

EQUATION_HINT = ("a constraint or expression is one expression that equals zero: write lhs - rhs, "
                 "e.g. 'x**2 + y**2 - l**2' for x**2 + y**2 = l**2")


def expression_syntax_hint(text: str, toml: bool = False) -> str:
    """A hint for an expression that is not valid syntax (spelt for a TOML file when `toml`)."""
    if _LONE_EQUALS.search(text) or "==" in text:
        return EQUATION_HINT
    unit = _NUMBER_THEN_WORD.match(text)
    if unit:
        number = text.split()[0]
        name = unit[1].strip()
        table = f'{{value = {number}, unit = "{name}"}}' if toml else f"{{value: {number}, unit: {name}}}"
        return f"a unit is not written after the number: write {table} (see 'Units' in docs/spec.md)"
    return ""


def yaml_scanner_hint(text: str, line: int | None) -> str:
    """A hint for a YAML scanner error at 1-based `line` of `text`."""
    lines = text.splitlines()
    source = lines[line - 1] if line is not None and 0 < line <= len(lines) else ""
    if "\t" in source[:len(source) - len(source.lstrip())]:
        return "YAML indentation must be spaces, not tabs: replace the tab characters at the start of the line"
    return ""


def toml_line_hint(text: str, line: int | None) -> str:
    """A hint for a TOML syntax error at 1-based `line`: a unit after a number, an `=` equation."""
    lines = text.splitlines()
    source = lines[line - 1] if line is not None and 0 < line <= len(lines) else ""
    key, equals, value = source.partition("=")
    return expression_syntax_hint(value.split("#")[0].strip(), toml=True) if equals else ""


def axis_hint(axis: object) -> str:
    """A hint for an `orientation` axis label that is not x, y or z."""
    if isinstance(axis, str) and axis.lower() in ("x", "y", "z") and axis != axis.lower():
        return f"axis labels are lower case: write '{axis.lower()}', not '{axis}'"
    return ""


def misplaced_toml_keys(raw, top_keys: tuple[str, ...]) -> list[Problem]:
    """TOML keys that belong at the top but ended up inside the table above them: after a
    `[table]` header every `key = value` line belongs to that table, so `kinetic = ...`
    written below `[parameters]` becomes a parameter named `kinetic`."""
    if raw.format != "toml" or not isinstance(raw.data, dict):
        return []
    problems = []
    for table, value in raw.data.items():
        if not isinstance(value, dict):
            continue
        for key in value:
            if key in top_keys and key not in raw.data and key != table:
                problems.append(Problem(raw.loc((table, key), at_key=True),
                                        f"'{key}' is inside the table [{table}]; it looks like a top-level key",
                                        f"in TOML every key after a [{table}] header belongs to that table: "
                                        f"move '{key} = ...' above the first [table] header"))
    return problems
