"""Line numbers of TOML keys (lagcli/spec/toml_positions.py; tomllib gives none)."""
from __future__ import annotations

import tomllib

from lagcli.spec.toml_positions import toml_marks

TEXT = '''coordinates = ["x"]
a.b = 1                       # a dotted key
"quoted key" = 2

[[forces]]
at = "P"
force = ["F", 0]

[[forces]]
at = "Q"

[particles.P]
mass = "m"
inner = {position = ["x", 0], mass = "m"}
text = """
fake = 3
"""
'''


def test_keys_are_found_on_their_lines():
    marks = toml_marks(TEXT, tomllib.loads(TEXT))
    assert marks[("coordinates",)] == (1, 1)
    assert marks[("a", "b")] == (2, 1)
    assert marks[("quoted key",)] == (3, 1)
    assert marks[("forces", 0)] == (5, 1) and marks[("forces", 0, "force")] == (7, 1)
    assert marks[("forces", 1, "at")] == (10, 1)
    assert marks[("particles", "P", "mass")] == (13, 1)
    assert marks[("particles", "P", "inner", "mass")] == (14, 31)


def test_a_key_inside_a_multi_line_string_is_not_invented():
    marks = toml_marks(TEXT, tomllib.loads(TEXT))
    assert ("particles", "P", "fake") not in marks and ("fake",) not in marks
