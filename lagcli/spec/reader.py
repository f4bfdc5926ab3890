"""Read a spec file (YAML or TOML) into plain data plus source positions.

The result, `RawDoc`, holds the parsed data (dicts, lists, str, int, float, bool,
None), the source text of every scalar (an expression's `Src.text`) and, for
YAML, the 1-based line/column of every key and value. TOML (`tomllib`) gives no
positions: `toml_positions.py` finds the line of each key (a value is located at its key).

A spec is untrusted input: the reader refuses anything but a regular file
(a FIFO or /dev/zero would block or never end), files over 1 MiB, YAML anchors
and aliases (alias bombs), deep nesting, huge node counts, custom YAML tags,
non-string keys and duplicate keys. The bytes come from `files.read_spec_bytes`,
the one way a spec file is read (here and on the warm C path of `simulate`).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from lagcli.errors import Loc, Problem, SpecError
from lagcli.spec.files import MAX_BYTES, STDIN, STDIN_NAME, read_spec_bytes
from lagcli.spec.slips import toml_line_hint, unclosed_toml_array, yaml_scanner_hint

MAX_NODES = 100_000
MAX_DEPTH = 32

KeyPath = tuple[str | int, ...]

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)  # libyaml when available: fast
_TAG = "tag:yaml.org,2002:"
_SCALAR_TAGS = {_TAG + t for t in ("str", "int", "float", "bool", "null", "timestamp")}
_DECIMAL = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_TOML_AT = re.compile(r"^(.*) \(at line (\d+), column (\d+)\)$", re.S)
_TOML_FIRST_LINE = re.compile(r"\s*(\[\[?[A-Za-z0-9_.\"' -]+\]|[A-Za-z0-9_.\"'-]+\s*=(?!=))")


@dataclass(frozen=True)
class RawDoc:
    """A parsed spec document: data, scalar source texts and (YAML only) positions.

    Paths are tuples of mapping keys and list indices, e.g. `("forces", 0, "at")`.
    """

    file: str
    format: str  # "yaml" or "toml"
    data: Any
    texts: dict[KeyPath, str] = field(default_factory=dict)
    marks: dict[KeyPath, tuple[int, int]] = field(default_factory=dict)
    key_marks: dict[KeyPath, tuple[int, int]] = field(default_factory=dict)

    def text(self, path: KeyPath) -> str:
        """The source text of the scalar at `path` (numbers as written in YAML)."""
        return self.texts[path]

    def position(self, path: KeyPath) -> tuple[int, int]:
        """(line, column) for sorting; (0, 0) when unknown (TOML)."""
        loc = self.loc(path)
        return (loc.line or 0, loc.column or 0)

    def loc(self, path: KeyPath, at_key: bool = False) -> Loc:
        """Where `path` is: its key (`at_key`) or value, else its nearest located ancestor."""
        mark = self.key_marks.get(path) if at_key else None
        probe = path
        while mark is None and probe:
            mark = self.marks.get(probe)
            probe = probe[:-1]
        mark = mark or self.marks.get(())
        line, column = mark if mark else (None, None)
        return Loc(self.file, line, column, format_path(path))


def format_path(path: KeyPath) -> str:
    """`("forces", 0, "at")` -> `forces[0].at`, the way `Loc.child` spells it."""
    out = ""
    for key in path:
        out += f"[{key}]" if isinstance(key, int) else (f".{key}" if out else str(key))
    return out


def read_document(path: str | Path, data: bytes | None = None) -> RawDoc:
    """Read and parse the spec at `path` (`-`: standard input, see `looks_like_toml`), or
    its bytes `data` when the caller has read them (`read_spec_bytes`); raise `SpecError`
    for anything unreadable."""
    name = str(path)
    if name == STDIN:
        text = _read_text(name, STDIN_NAME, data)
        return parse_text(STDIN_NAME, text, toml=looks_like_toml(text))
    suffix = Path(name).suffix.lower()
    if suffix not in (".yaml", ".yml", ".toml"):
        raise SpecError(Problem(Loc(name), f"unknown spec format '{suffix or name}'",
                                "a spec file ends in .yaml, .yml or .toml"))
    return parse_text(name, _read_text(name, None, data), toml=suffix == ".toml")


def parse_text(name: str, text: str, toml: bool = False) -> RawDoc:
    """Parse spec `text` (YAML, or TOML), located as `name`; the size limit of a file holds."""
    if len(text.encode()) > MAX_BYTES:
        raise SpecError(Problem(Loc(name), f"spec text is too large (the limit is {MAX_BYTES >> 20} MiB)"))
    raw = _read_toml(name, text) if toml else _read_yaml(name, text)
    _within_budget(raw)
    return raw


MAX_COORDINATES = 1_000   # the budget of one spec: n coordinates cost n^2 mass-matrix entries and more


def _within_budget(raw: RawDoc) -> None:
    """Refuse, before any work and alone, a spec beyond what one spec may cost (docs/robustness.md)."""
    coordinates = raw.data.get("coordinates") if isinstance(raw.data, dict) else None
    if isinstance(coordinates, list) and len(coordinates) > MAX_COORDINATES:
        raise SpecError(Problem(raw.loc(("coordinates",)), f"too many coordinates: {len(coordinates)}, the bound "
                                f"is {MAX_COORDINATES} (the derivation's cost grows with the {len(coordinates)}^2 "
                                "entries of the mass matrix)", "a system this large is beyond lagcli's budget "
                                "for one spec; split it, or reduce it"))


def looks_like_toml(text: str) -> bool:
    """A spec given as text without a file name is TOML when its first line that is not
    blank or a comment is a `[table]` header or a `key = value` line; else YAML."""
    for line in text.splitlines():
        if line.strip() and not line.lstrip().startswith("#"):
            return _TOML_FIRST_LINE.match(line) is not None
    return False


def _read_text(name: str, shown: str | None = None, data: bytes | None = None) -> str:
    data = read_spec_bytes(name) if data is None else data
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise SpecError(Problem(Loc(shown or name), f"spec is not valid UTF-8 (byte {exc.start})")) from None


# --- YAML -------------------------------------------------------------------------------

def _read_yaml(name: str, text: str) -> RawDoc:
    try:
        _screen_events(name, text)
        root = yaml.compose(text, Loader=_Loader)
    except yaml.MarkedYAMLError as exc:
        problem = _yaml_problem(name, exc)
        hint = yaml_scanner_hint(text, problem.loc.line)
        raise SpecError(Problem(problem.loc, problem.message, hint) if hint else problem) from None
    except yaml.YAMLError as exc:  # e.g. a ReaderError: a control character, no line known
        first_line = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise SpecError(Problem(Loc(name), f"invalid YAML: {first_line}")) from None
    if root is None:
        raise SpecError(Problem(Loc(name, 1, 1), "spec is empty"))
    walker = _YamlWalker(name)
    data = walker.walk(root, ())
    if walker.problems:
        raise SpecError(walker.problems)
    return RawDoc(name, "yaml", data, walker.texts, walker.marks, walker.key_marks)


def _screen_events(name: str, text: str) -> None:
    """Refuse anchors/aliases, deep nesting and huge documents before building nodes."""
    depth = count = 0
    for event in yaml.parse(text, Loader=_Loader):
        mark = event.start_mark
        if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None):
            raise SpecError(Problem(_mark_loc(name, mark), "YAML anchors and aliases (&name, *name) "
                                    "are not allowed", "write the value out in full"))
        if isinstance(event, (yaml.ScalarEvent, yaml.CollectionStartEvent)):
            count += 1
        if isinstance(event, yaml.CollectionStartEvent):
            depth += 1
        elif isinstance(event, yaml.CollectionEndEvent):
            depth -= 1
        if depth > MAX_DEPTH or count > MAX_NODES:
            what = "nested too deeply" if depth > MAX_DEPTH else "has too many items"
            raise SpecError(Problem(_mark_loc(name, mark), f"spec {what}"))


def _mark_loc(name: str, mark: Any) -> Loc:
    return Loc(name, mark.line + 1, mark.column + 1) if mark is not None else Loc(name)


def _yaml_problem(name: str, exc: yaml.MarkedYAMLError) -> Problem:
    if "maximum nesting depth" in (exc.problem or ""):  # PyYAML >= 6.0.3 scans ahead past MAX_DEPTH
        return Problem(_mark_loc(name, exc.problem_mark), "spec nested too deeply")
    message = f"invalid YAML: {exc.problem or exc.context or 'cannot parse'}"
    if exc.context and exc.problem:
        where = f" at line {exc.context_mark.line + 1}" if exc.context_mark else ""
        message += f" ({exc.context}{where})"
    if exc.context == "while scanning a simple key" and exc.context_mark is not None:
        return Problem(_mark_loc(name, exc.context_mark), message)  # the key's line: the slip is there
    return Problem(_mark_loc(name, exc.problem_mark or exc.context_mark), message)


class _YamlWalker:
    """Turns a composed YAML node tree into plain data, noting texts and positions."""

    def __init__(self, name: str):
        self.name = name
        self.problems: list[Problem] = []
        self.texts: dict[KeyPath, str] = {}
        self.marks: dict[KeyPath, tuple[int, int]] = {}
        self.key_marks: dict[KeyPath, tuple[int, int]] = {}
        self._constructor = yaml.SafeLoader("")  # only for its scalar constructors

    def fail(self, node: yaml.Node, message: str, hint: str = "", path: KeyPath = ()) -> None:
        loc = _mark_loc(self.name, node.start_mark)
        self.problems.append(Problem(Loc(loc.file, loc.line, loc.column, format_path(path)), message, hint))

    def walk(self, node: yaml.Node, path: KeyPath) -> Any:
        self.marks[path] = (node.start_mark.line + 1, node.start_mark.column + 1)
        if isinstance(node, yaml.MappingNode) and node.tag == _TAG + "map":
            return self._mapping(node, path)
        if isinstance(node, yaml.SequenceNode) and node.tag == _TAG + "seq":
            return [self.walk(item, path + (i,)) for i, item in enumerate(node.value)]
        return self._scalar(node, path)

    def _mapping(self, node: yaml.MappingNode, path: KeyPath) -> dict:
        out: dict[str, Any] = {}
        for key_node, value_node in node.value:
            key = self._key(key_node)
            if key is None:
                continue
            if key in out:
                line = self.key_marks[path + (key,)][0]
                self.fail(key_node, f"duplicate key '{key}' (first given on line {line})")
                continue
            self.key_marks[path + (key,)] = (key_node.start_mark.line + 1, key_node.start_mark.column + 1)
            out[key] = self.walk(value_node, path + (key,))
        return out

    def _key(self, node: yaml.Node) -> str | None:
        if isinstance(node, yaml.ScalarNode) and node.tag == _TAG + "str":
            return node.value
        if isinstance(node, yaml.ScalarNode) and node.tag == _TAG + "merge":
            self.fail(node, "YAML merge keys ('<<') are not allowed")
        elif isinstance(node, yaml.ScalarNode):
            kind = node.tag.rsplit(":", 1)[-1]
            self.fail(node, f"key '{node.value}' is read by YAML as a {kind}, not a name",
                      f"quote it: '{node.value}'")
        else:
            self.fail(node, "a mapping key must be a plain name, not a list or mapping")
        return None

    def _scalar(self, node: yaml.ScalarNode, path: KeyPath) -> Any:
        if not isinstance(node, yaml.ScalarNode) or node.tag not in _SCALAR_TAGS:
            self.fail(node, f"YAML tag '{node.tag}' is not allowed", path=path)
            return None
        if node.tag == _TAG + "timestamp":  # e.g. 2001-12-14: keep it as text
            value: Any = node.value
        else:
            try:
                value = self._constructor.construct_object(node)
            except (ValueError, IndexError, KeyError, TypeError):  # PyYAML on e.g. `!!float ''`
                kind = node.tag.rsplit(":", 1)[-1]
                self.fail(node, f"cannot read {_clip(node.value)!r} as a YAML {kind}"
                          + (": it is too long" if len(node.value) > 4000 else ""),
                          "remove the !!tag, or write a plain number", path)
                return None
        self.texts[path] = _number_text(value, node.value)
        return value


def _clip(text: str, width: int = 40) -> str:
    return text if len(text) <= width else text[:width] + "..."


def _number_text(value: Any, source: str) -> str:
    """A scalar's expression text: the source for strings and plain decimals, else repr."""
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return source if isinstance(value, str) else str(value)
    if isinstance(value, int):
        return str(value)  # 0x10, 1_000, 010 (YAML 1.1 octal) -> decimal
    if isinstance(value, float) and math.isfinite(value) and _DECIMAL.fullmatch(source):
        return source  # keep 1.0e-9 as written
    return repr(value)


# --- TOML -------------------------------------------------------------------------------

def _read_toml(name: str, text: str) -> RawDoc:
    # Imported on use: a YAML spec (the usual one) needs neither tomllib nor the key
    # scanner (~5 ms of every command's start when imported at the top).
    import tomllib

    from lagcli.spec.toml_positions import toml_marks

    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(_toml_problem(name, str(exc), text)) from None
    except RecursionError:
        raise SpecError(Problem(Loc(name), "spec nested too deeply")) from None
    except ValueError:  # an integer over Python's 4300-digit limit
        raise SpecError(Problem(Loc(name), "invalid TOML: a number is too long")) from None
    texts: dict[KeyPath, str] = {}
    _toml_texts(name, data, (), texts)
    marks = toml_marks(text, data)
    return RawDoc(name, "toml", data, texts, marks, dict(marks))


def _toml_problem(name: str, message: str, text: str) -> Problem:
    found = _TOML_AT.match(message)
    what, loc = (found[1], Loc(name, int(found[2]), int(found[3]))) if found else (message, Loc(name))
    if what == "Unclosed array" and loc.line:   # tomllib reads on to where the array could no longer go on
        opened = unclosed_toml_array(text, loc.line)
        if opened:
            return Problem(Loc(name, opened, 1), f"invalid TOML: Unclosed array (opened on line {opened})",
                           "close the array with ']' before the next key or [table]")
    hint = ("an expression is a quoted string in TOML: potential = \"k*x**2/2\""
            if what == "Invalid value" else toml_line_hint(text, loc.line))
    return Problem(loc, f"invalid TOML: {what}", hint)


def _toml_texts(name: str, value: Any, path: KeyPath, texts: dict[KeyPath, str]) -> None:
    if len(path) > MAX_DEPTH:
        raise SpecError(Problem(Loc(name, path=format_path(path)), "spec nested too deeply"))
    if isinstance(value, dict):
        for key, item in value.items():
            _toml_texts(name, item, path + (key,), texts)
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _toml_texts(name, item, path + (i,), texts)
    elif isinstance(value, float):
        texts[path] = repr(value)
    else:
        texts[path] = str(value)
