"""Line and column numbers for the keys of a TOML spec, which `tomllib` does not give.

tomllib (and tomlkit) keep no source positions for keys, so a small line scanner
supplies them: it follows the `[table]` and `[[array of tables]]` headers and notes
where each `key = value` line starts (dotted keys included) and where the keys of a
one-line inline table `{mass = "m", position = [...]}` stand. Positions only label
messages; the data always comes from tomllib. A mark is kept only for a key path that
tomllib produced, so a line the scanner misreads (inside a multi-line string or array)
cannot invent a key: at worst a message shows the line of a nearby key.
"""
from __future__ import annotations

import re
from typing import Any

_BARE_OR_QUOTED = r"""[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*'"""
_HEADER = re.compile(rf"\s*\[(\[?)\s*((?:{_BARE_OR_QUOTED}|\s|\.)+?)\s*\]\]?\s*(?:#.*)?$")
_KEY = re.compile(rf"\s*((?:{_BARE_OR_QUOTED})(?:\s*\.\s*(?:{_BARE_OR_QUOTED}))*)\s*=")
_INLINE_KEY = re.compile(rf"[{{,]\s*({_BARE_OR_QUOTED})\s*=")
_PART = re.compile(_BARE_OR_QUOTED)


def toml_marks(text: str, data: dict) -> dict[tuple, tuple[int, int]]:
    """{key path: (line, column)} for the keys of `text` found in its parsed `data`."""
    marks: dict[tuple, tuple[int, int]] = {}
    table: tuple = ()
    arrays: dict[tuple, int] = {}
    for number, line in enumerate(text.splitlines(), 1):
        header = _HEADER.match(line)
        if header:
            table = _parts(header[2])
            if header[1]:                                    # [[name]]: the next item of the array
                arrays[table] = arrays.get(table, -1) + 1
                table += (arrays[table],)
            _mark(marks, data, table, number, line.index("[") + 1)
            continue
        key = _KEY.match(line)
        if not key:
            continue
        path = table + _parts(key[1])
        _mark(marks, data, path, number, key.start(1) + 1)
        if isinstance(_lookup(data, path), dict):
            for inner in _INLINE_KEY.finditer(line, key.end()):
                _mark(marks, data, path + _parts(inner[1]), number, inner.start(1) + 1)
    return marks


def _parts(dotted: str) -> tuple:
    return tuple(part[1:-1] if part[0] in "\"'" else part for part in _PART.findall(dotted))


_MISSING = object()


def _lookup(data: Any, path: tuple) -> Any:
    for key in path:
        if isinstance(data, dict) and isinstance(key, str) and key in data:
            data = data[key]
        elif isinstance(data, list) and isinstance(key, int) and key < len(data):
            data = data[key]
        else:
            return _MISSING
    return data


def _mark(marks: dict, data: dict, path: tuple, line: int, column: int) -> None:
    if path and path not in marks and _lookup(data, path) is not _MISSING:
        marks[path] = (line, column)
