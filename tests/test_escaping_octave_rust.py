"""The MATLAB/Octave and Rust escapes of lagcli/render/escape.py against their grammars,
with the random hostile text of test_escaping.py (the literals are also evaluated by
octave-cli in test_codegen_octave.py and by rustc in test_codegen_rust.py)."""
from __future__ import annotations

import re

from hypothesis import given

from lagcli.render import escape

from test_escaping import EXAMPLES, hostile_text

RUST_ESCAPE = re.compile(r'\\(\\|"|u\{([0-9a-f]+)\})')


def rust_string_value(literal: str) -> str:
    """The value of a Rust string literal made of escapes and printable ASCII only."""
    assert literal[0] == literal[-1] == '"'
    body = literal[1:-1]
    assert re.fullmatch(r'(?:[ !#-\[\]-~]|\\\\|\\"|\\u\{[0-9a-f]+\})*', body), literal
    return RUST_ESCAPE.sub(lambda m: chr(int(m.group(2), 16)) if m.group(2) else m.group(1), body)


@EXAMPLES
@given(hostile_text)
def test_rust_string_round_trips(text):
    expected = "".join("\ufffd" if 0xD800 <= ord(ch) <= 0xDFFF else ch for ch in text)
    assert rust_string_value(escape.rust_string(text)) == expected


@EXAMPLES
@given(hostile_text)
def test_rust_comment_is_one_plain_line_comment(text):
    line = "// " + escape.rust_comment(text)
    assert "\n" not in line and "\r" not in line and line.isprintable()
    assert not line.startswith(("///", "//!")), line     # not a doc comment (an attribute)


@EXAMPLES
@given(hostile_text)
def test_octave_comment_is_one_line_that_opens_no_block(text):
    line = "% " + escape.octave_comment(text)
    assert "\n" not in line and "\r" not in line and line.isprintable()
    assert line.strip() not in ("%{", "%}", "#{", "#}")


def octave_string_value(expression: str) -> bytes:
    """The UTF-8 bytes of an octave_string expression (its grammar: quoted ASCII runs and
    native2unicode(uint8([...]), 'UTF-8') runs, concatenated)."""
    parts = re.findall(r"'((?:[^'\n]|'')*)'|native2unicode\(uint8\(\[([0-9 ]*)\]\), 'UTF-8'\)", expression)
    rebuilt = [f"'{q}'" if not b else f"native2unicode(uint8([{b}]), 'UTF-8')" for q, b in parts]
    assert expression in (rebuilt[0] if len(rebuilt) == 1 else None, "[" + ", ".join(rebuilt) + "]"), expression
    return b"".join(q.replace("''", "'").encode() if not b else bytes(map(int, b.split())) for q, b in parts)


@EXAMPLES
@given(hostile_text)
def test_octave_string_round_trips(text):
    value = octave_string_value(escape.octave_string(text))
    assert value == text.encode("utf-8", "replace")
    assert escape.octave_string(text).isascii()
