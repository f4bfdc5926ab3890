"""`lagcli schema`: the JSON Schema of spec files agrees with the checker.

The schema is made from the tables the checker uses (lagcli/spec/format.py), so they
cannot disagree on keys; this checks the shapes too, with the `jsonschema` package:
every bundled spec and every complete spec shown in the docs is valid; over the
bad-spec corpus (tests/data/bad) the schema never refuses what the checker accepts,
and refuses every file where the checker found a format error of the kinds a schema
can see (unknown and missing keys, values of the wrong type or shape, names that are
not identifiers, values outside a fixed list). What it cannot see (the meaning of an
expression, references, reserved names, the spec's dimension, rules joining keys) is
listed in docs/spec.md, "Editor support".
"""
from __future__ import annotations

import ast
import json
import re
from pathlib import Path

import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.errors import SpecError
from lagcli.spec import format as fmt
from lagcli.spec.json_schema import json_schema, json_schema_text
from lagcli.spec.reader import read_document
from lagcli.spec.schema import check

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parent.parent
SPECS = sorted(p for p in (ROOT / "specs").rglob("*") if p.suffix in (".yaml", ".yml", ".toml"))
BAD = sorted(p for p in (ROOT / "tests" / "data" / "bad").iterdir() if p.suffix in (".yaml", ".yml", ".toml"))

# Messages of the checker's format errors that a JSON Schema can see (the rest it cannot:
# expressions, references, reserved and duplicate names, dimensions, joined keys).
VISIBLE = re.compile(r"^(unknown key '|expected |empty expression|'[^']*' is not a valid name|"
                     r"a rotation is \[axis, angle\]|a torque is one expression|"
                     r"the wheel's axis \(in body axes\) is x, y or z|unknown integration method|"
                     r"unknown (action|direction) )")
REQUIRED = {key for table in vars(fmt).values() if isinstance(table, fmt.Table) for key in table.required}


def validator():
    return jsonschema.Draft202012Validator(json_schema())


def visible(message: str) -> bool:
    missing = re.match(r"missing required key '(\w+)'", message)
    return bool(VISIBLE.match(message)) or bool(missing and missing[1] in REQUIRED)


def test_schema_is_a_valid_draft_2020_12_schema():
    schema = json_schema()
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    jsonschema.Draft202012Validator.check_schema(schema)


def test_lagcli_schema_prints_it_and_writes_it(tmp_path):
    done = CliRunner().invoke(cli, ["schema"])
    assert done.exit_code == 0 and json.loads(done.output) == json_schema()
    target = tmp_path / "lagcli.schema.json"
    done = CliRunner().invoke(cli, ["schema", "-o", str(target), "-q"])
    assert done.exit_code == 0 and target.read_text() == json_schema_text()


def test_schema_has_every_key_the_checker_allows():
    schema = json_schema()
    assert list(schema["properties"]) == list(fmt.TOP.allowed)
    assert schema["required"] == list(fmt.TOP.required)
    for table in (t for t in vars(fmt).values() if isinstance(t, fmt.Table) and t is not fmt.TOP):
        entry = schema["$defs"][table.name]
        assert list(entry["properties"]) == list(table.allowed), table.name
        assert entry["additionalProperties"] is False


def test_the_checker_takes_every_key_table_from_the_format():
    """No key list written in a checker module: `table(...)` is given a format Table."""
    for path in sorted((ROOT / "lagcli" / "spec").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "table":
                assert len(node.args) == 3 and not isinstance(node.args[2], (ast.Tuple, ast.List)), \
                    f"{path.name}:{node.lineno}: declare the table in lagcli/spec/format.py"


@pytest.mark.parametrize("path", SPECS, ids=lambda p: str(p.relative_to(ROOT / "specs")))
def test_every_bundled_spec_is_valid(path):
    errors = [e.message for e in validator().iter_errors(read_document(path).data)]
    assert not errors, errors


def test_every_spec_in_the_docs_is_valid(tmp_path):
    from test_docs_examples import spec_blocks

    for where, lang, text in spec_blocks():
        spec = tmp_path / f"example.{lang}"
        spec.write_text(text, encoding="utf-8")
        errors = [e.message for e in validator().iter_errors(read_document(spec).data)]
        assert not errors, f"{where}: {errors}"


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.name)
def test_schema_and_checker_agree_on_bad_specs(path):
    try:
        raw = read_document(path)
    except SpecError:
        pytest.skip("refused by the reader (syntax, limits): no data for a schema")
    _, problems = check(raw)
    errors = [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator().iter_errors(raw.data)]
    if errors:
        assert problems, f"the schema refuses what the checker accepts: {errors}"
    seen = [str(p) for p in problems if visible(p.message)]
    if seen:
        assert errors, f"the checker found format errors the schema accepts: {seen}"


# --- mutations of bundled specs: every key removed, an unknown one added, every value
# replaced by values of other types; the two verdicts compared on each -----------------

MUTANT_SPECS = ("cart_pole.yaml", "rolling_disc_frames.yaml", "heavy_symmetric_top.yaml",
                "ex6_9_two_wheels_axle.yaml", "chaplygin_sled.yaml", "atwood.yaml", "sphere_on_turntable.yaml",
                "hybrid/rimless_wheel.yaml", "hybrid/bouncing_ball.yaml", "hybrid/cart_pole_lqr.yaml")
REPLACEMENTS = (True, None, [], {}, "", " ", 1.5, ["a"], ["a", "b"], [[1]], {"zz": 1}, "1x", "x")


def paths(data, path=()):
    yield path
    if isinstance(data, dict):
        for key, value in data.items():
            yield from paths(value, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from paths(value, path + (i,))


def mutants(data):
    """(what, mutated copy) for each removal, addition and replacement."""
    import copy

    def at(root, path):
        for key in path:
            root = root[key]
        return root

    for path in paths(data):
        target = at(data, path)
        if isinstance(target, dict):
            added = copy.deepcopy(data)
            at(added, path)["zzz_unknown"] = 1
            yield f"{path} + zzz_unknown", added
        if not path:
            continue
        for value in REPLACEMENTS:
            changed = copy.deepcopy(data)
            at(changed, path[:-1])[path[-1]] = value
            yield f"{path} = {value!r}", changed
        if isinstance(path[-1], str):
            removed = copy.deepcopy(data)
            del at(removed, path[:-1])[path[-1]]
            yield f"{path} removed", removed


@pytest.mark.parametrize("name", MUTANT_SPECS)
def test_schema_and_checker_agree_on_mutated_specs(name):
    from lagcli.spec.reader import RawDoc

    raw = read_document(ROOT / "specs" / name)
    check_schema = validator()
    disagreements = []
    for what, data in mutants(raw.data):
        texts = {path: str(value) for path in paths(data) for value in [_at(data, path)]
                 if not isinstance(value, (dict, list))}
        _, problems = check(RawDoc(raw.file, raw.format, data, texts))
        refused = next(check_schema.iter_errors(data), None) is not None
        seen = [p.message for p in problems if visible(p.message)]
        if refused and not problems:
            disagreements.append(f"{what}: only the schema refuses it")
        elif seen and not refused:
            disagreements.append(f"{what}: the schema accepts {seen}")
    assert not disagreements, "\n".join(disagreements[:20])


def _at(root, path):
    for key in path:
        root = root[key]
    return root
