"""The validation toolkit behind `schema.py`: record problems at key paths, check shapes.

`Checker.fail` is the one place a problem is recorded; the shape helpers
(`table`, `expr`, `vector`, ...) report what is wrong and return None, so a
caller can go on and collect every problem in one pass. Names, references and
the spec's single dimension are tracked here too and checked at the end.
"""
from __future__ import annotations

import difflib
import keyword
import math
import re
from typing import Any, Callable

from lagcli.errors import Problem
from lagcli.interface import column_clash
from lagcli.interface import reserved_reason as generated_name_reason
from lagcli.spec.format import Table
from lagcli.spec.reader import KeyPath, RawDoc
from lagcli.spec.types import Src, Vector, VectorSrc

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
FUNCTIONS = frozenset("sin cos tan asin acos atan atan2 sinh cosh tanh exp log sqrt abs sign "
                      "min max diff".split())
NAME_HINT = "a name is a letter or '_' followed by letters, digits or '_'"
FLOW_COMMA_HINT = ("in YAML flow style, [a, b] or {k: v, ...}, a comma ends the item: "
                   "quote an expression that contains one, e.g. ['atan2(y, x)', 0]")
_PLURAL = {"particle": "particles", "body": "bodies", "frame": "frames"}


def _unbalanced(value: Any) -> bool:
    return isinstance(value, str) and value.count("(") != value.count(")")


def reserved_reason(name: str, coordinates: set[str]) -> str:
    """Why `name` cannot be declared in a spec, or '' when it can.

    C keywords are fine: generated code refers to every symbol by its array slot
    (y[i], p[j]); spec names appear in C only behind a prefix (`<NAME>_Q_<q>`,
    `<NAME>_P_<p>` index macros), never as identifiers of their own. The names lagcli
    generates (velocities, multipliers, output columns) are `lagcli.interface`'s rules.
    """
    if name in ("t", "pi"):
        return "'t' is time" if name == "t" else "'pi' is the constant pi"
    if name in FUNCTIONS:
        return "it is a function name"
    if keyword.iskeyword(name):
        return "it is a Python keyword"
    if name.startswith("__"):
        return "names starting with '__' are reserved"
    return generated_name_reason(name, coordinates)


def describe(value: Any) -> str:
    """What a raw value is, for messages: 'a boolean', 'a list of 4 items', ..."""
    if isinstance(value, bool):
        return "a boolean"
    if value is None:
        return "nothing (null)"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return f"a list of {len(value)} item{'' if len(value) == 1 else 's'}"
    return "a mapping" if isinstance(value, dict) else f"a {type(value).__name__}"


def closest(word: str, choices: list[str] | tuple[str, ...]) -> str | None:
    close = difflib.get_close_matches(word, list(choices), n=1)
    return close[0] if close else None


def did_you_mean(word: str, choices: list[str] | tuple[str, ...]) -> str:
    close = closest(word, choices)
    return f"did you mean '{close}'?" if close else ""


class Checker:
    """Problem collection plus shape, name, reference and dimension checks on a `RawDoc`."""

    def __init__(self, raw: RawDoc):
        self.raw = raw
        self.problems: list[Problem] = []
        self.names: dict[str, tuple[str, KeyPath]] = {}  # name -> (kind, where declared)
        self.coordinate_names: set[str] = set()
        self.dims: list[tuple[int, KeyPath]] = []
        self.refs: list[tuple[KeyPath, str, tuple[str, ...]]] = []

    # --- recording ---------------------------------------------------------------------

    def fail(self, path: KeyPath, message: str, hint: str = "", at_key: bool = False) -> None:
        """Record that the item at `path` (its key when `at_key`) is wrong."""
        self.problems.append(Problem(self.raw.loc(path, at_key), message, hint))

    def where(self, path: KeyPath) -> str:
        """A short reference to another place, for messages: `gravity (line 4)`."""
        loc = self.raw.loc(path)
        return f"{loc.path} (line {loc.line})" if loc.line else loc.path

    # --- shapes --------------------------------------------------------------------------

    def table(self, path: KeyPath, value: Any, shape: Table) -> dict | None:
        """A mapping with only the keys of `shape` (did-you-mean otherwise) and all its required
        ones; `shape` is a table of lagcli/spec/format.py, which `lagcli schema` reads too."""
        allowed, required = shape.allowed, shape.required
        if not isinstance(value, dict):
            self.fail(path, f"expected a mapping with keys {', '.join(allowed)}; got {describe(value)}")
            return None
        suggested = set()
        for key in value:
            if key not in allowed:
                close = closest(key, allowed)
                suggested.add(close)
                hint = f"did you mean '{close}'?" if close else "allowed keys are: " + ", ".join(allowed)
                hint = FLOW_COMMA_HINT if _unbalanced(key) else hint
                self.fail(path + (key,), f"unknown key '{key}'", hint, at_key=True)
        for key in required:
            if key not in value and key not in suggested:  # a typo of it was reported already
                self.fail(path, f"missing required key '{key}'")
        return value

    def expr(self, path: KeyPath, value: Any) -> Src | None:
        """An expression: a string or a finite number (never a boolean, null or list)."""
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            hint = "quote it if you mean a name" if isinstance(value, bool) else ""
            self.fail(path, f"expected an expression (a number or a string); got {describe(value)}", hint)
            return None
        if isinstance(value, float) and not math.isfinite(value):
            self.fail(path, "a number must be finite")
            return None
        text = self.raw.text(path).strip()
        if not text:
            self.fail(path, "empty expression")
            return None
        return Src(text, self.raw.loc(path))

    def vector(self, path: KeyPath, value: Any) -> Vector | None:
        """A list of 2 or 3 expressions; its length counts towards the spec's dimension.
        A string is one vector expression (3-D, lagcli/model/vectors.py)."""
        if isinstance(value, str):
            src = self.expr(path, value)
            self.note_dim(3, path)
            return (VectorSrc(src.text, src.loc),) if src else None
        if isinstance(value, list) and any(_unbalanced(v) for v in value):
            self.fail(path, "a component has unbalanced parentheses: was an expression split at a comma?",
                      FLOW_COMMA_HINT)
            return None
        if not isinstance(value, list) or len(value) not in (2, 3):
            self.fail(path, f"expected a vector of 2 or 3 expressions; got {describe(value)}")
            return None
        items = [self.expr(path + (i,), v) for i, v in enumerate(value)]
        if any(item is None for item in items):
            return None
        self.note_dim(len(items), path)
        return tuple(items)  # type: ignore[arg-type]

    def string(self, path: KeyPath, value: Any, what: str = "a string") -> str | None:
        if isinstance(value, str):
            return value
        self.fail(path, f"expected {what}; got {describe(value)}")
        return None

    def optional_string(self, table: dict, path: KeyPath, key: str) -> str | None:
        return self.string(path + (key,), table[key]) if key in table else None

    def identifier(self, path: KeyPath, value: Any, at_key: bool = False) -> str | None:
        name = self.string(path, value, "a name")
        if name is not None and not IDENTIFIER.fullmatch(name):
            self.fail(path, f"'{name}' is not a valid name", NAME_HINT, at_key)
            return None
        return name

    def mapping_items(self, top: dict, key: str, build: Callable[[str, KeyPath, Any], Any]) -> tuple:
        """Build each `name: value` entry of section `key`; an absent or empty section is ()."""
        value = top.get(key)
        if value is None:
            return ()
        if not isinstance(value, dict):
            self.fail((key,), f"expected a mapping of name: value; got {describe(value)}")
            return ()
        built = [build(name, (key, name), item) for name, item in value.items()]
        return tuple(item for item in built if item is not None)

    def list_items(self, top: dict, key: str, build: Callable[[KeyPath, Any], Any]) -> tuple:
        """Build each entry of list section `key`; an absent or empty section is ()."""
        value = top.get(key)
        if value is None:
            return ()
        if not isinstance(value, list):
            self.fail((key,), f"expected a list; got {describe(value)}")
            return ()
        built = [build((key, i), item) for i, item in enumerate(value)]
        return tuple(item for item in built if item is not None)

    # --- names and references ----------------------------------------------------------

    def declare(self, name: str, kind: str, path: KeyPath, at_key: bool = True) -> None:
        """Declare a spec-wide name (coordinate, parameter, particle, ...)."""
        if not IDENTIFIER.fullmatch(name):
            self.fail(path, f"'{name}' is not a valid name", NAME_HINT, at_key)
            return
        reason = reserved_reason(name, self.coordinate_names)
        if kind == "coordinate":
            reason = reason or column_clash(name, self.coordinate_names)
        if reason:
            self.fail(path, f"the name '{name}' is reserved: {reason}", "choose another name", at_key)
        if name in self.names:
            first_kind, first_path = self.names[name]
            self.fail(path, f"duplicate name '{name}': already a {first_kind} at {self.where(first_path)}",
                      "names must be unique across coordinates, parameters, inputs, known, definitions, "
                      "particles and bodies", at_key)
        else:
            self.names[name] = (kind, path)

    def reference(self, path: KeyPath, value: Any, kinds: tuple[str, ...]) -> str | None:
        """A name that must be declared as one of `kinds`; checked by `check_references`."""
        name = self.string(path, value, "a name")
        if name is not None:
            self.refs.append((path, name, kinds))
        return name

    def check_references(self) -> None:
        for path, name, kinds in self.refs:
            kind = self.names.get(name, ("", ()))[0]
            if kind in kinds:
                continue
            defined = [n for n, (k, _) in self.names.items() if k in kinds]
            shown = [k for k in kinds if any(self.names[n][0] == k for n in defined)] or list(kinds)
            label = " or ".join(shown)
            message = f"'{name}' is a {kind}, not a {label}" if kind else f"unknown {label} '{name}'"
            listing = (f"defined {' and '.join(_PLURAL[k] for k in shown)} are: {', '.join(defined)}"
                       if defined else f"no {' or '.join(_PLURAL[k] for k in kinds)} are defined")
            self.fail(path, message, " ".join(filter(None, (did_you_mean(name, defined), listing))))

    # --- dimension -----------------------------------------------------------------------

    def note_dim(self, dim: int, path: KeyPath) -> None:
        self.dims.append((dim, path))

    def dimension(self) -> int:
        """The spec's one dimension (2 when nothing says); a mix is reported once."""
        if not self.dims:
            return 2
        dims = sorted(self.dims, key=lambda item: self.raw.position(item[1]))  # file order
        first_dim, first_path = dims[0]
        for dim, path in dims[1:]:
            if dim != first_dim:
                self.fail(path, f"mixes 2-D and 3-D: this is {dim}-D but {self.where(first_path)} "
                          f"is {first_dim}-D", "one spec uses one dimension: every vector has "
                          "2 components (planar) or every vector has 3 (spatial)")
                break
        return first_dim
