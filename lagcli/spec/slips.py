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
    key, equals, value = source.partition("=")
    if equals and ":" not in key and re.fullmatch(r"\s*[-\w.]+\s*", key):
        return (f"a YAML key and its value are separated by a colon and a space, not '=': "
                f"write '{key.strip()}: {value.strip()}'")
    return ""


def toml_line_hint(text: str, line: int | None) -> str:
    """A hint for a TOML syntax error at 1-based `line`: a unit after a number, an `=` equation
    (in an inline table `{value = 1.0 kg}`, the hint for its values)."""
    lines = text.splitlines()
    source = lines[line - 1] if line is not None and 0 < line <= len(lines) else ""
    key, equals, value = source.partition("=")
    value = value.split("#")[0].strip()
    if value.startswith("{"):
        inner = [part.partition("=") for part in value.strip("{} ").split(",")]
        hints = [expression_syntax_hint(v.strip(), toml=True) for _, eq, v in inner if eq]
        return next((h for h in hints if h and h != EQUATION_HINT), "")
    return expression_syntax_hint(value, toml=True) if equals else ""


_TOML_ARRAY_START = re.compile(r"^\s*[\w.\"'-]+\s*=\s*\[")


def unclosed_toml_array(text: str, line: int) -> int | None:
    """The 1-based line where the array that tomllib found unclosed at `line` was opened: the
    last `key = [` line at or before it whose brackets do not balance (None if not found)."""
    lines = text.splitlines()[:line]
    for number in range(len(lines), 0, -1):
        source = lines[number - 1].split("#")[0]
        if _TOML_ARRAY_START.match(source) and source.count("[") > source.count("]"):
            return number
    return None


def axis_hint(axis: object) -> str:
    """A hint for an `orientation` axis label that is not x, y or z."""
    if isinstance(axis, str) and axis.lower() in ("x", "y", "z") and axis != axis.lower():
        return f"axis labels are lower case: write '{axis.lower()}', not '{axis}'"
    return ""


def misplaced_toml_keys(raw, top_keys: tuple[str, ...]) -> list[Problem]:
    """TOML keys that belong at the top but ended up inside the table above them: after a
    `[table]` header every `key = value` line belongs to that table, so `kinetic = ...`
    written below `[parameters]` becomes a parameter named `kinetic`."""
    return [Problem(raw.loc((table, key), at_key=True),
                    f"'{key}' is inside the table [{table}]; it looks like a top-level key",
                    f"in TOML every key after a [{table}] header belongs to that table: "
                    f"move '{key} = ...' above the first [table] header")
            for table, key in misplaced_toml_pairs(raw, top_keys)]


def misplaced_toml_pairs(raw, top_keys: tuple[str, ...]) -> list[tuple[str, str]]:
    """(table, key) of each key `misplaced_toml_keys` reports."""
    if raw.format != "toml" or not isinstance(raw.data, dict):
        return []
    return [(table, key) for table, value in raw.data.items() if isinstance(value, dict)
            for key in value if key in top_keys and key not in raw.data and key != table]
