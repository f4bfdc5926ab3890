"""Reading and validating specs: YAML and TOML agree, locations are right, every
rule of docs/spec.md that the validator owns is enforced, and the bundled specs load.

Bad specs that go through the CLI live in `test_bad_specs.py`; here `load_spec`
is called directly, to look at the `Spec` and at every collected problem.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from lagcli.errors import Loc, SpecError
from lagcli.spec import load_spec
from lagcli.spec.types import Src

ROOT = Path(__file__).resolve().parent.parent
BUNDLED = sorted(p for p in (ROOT / "specs").glob("*") if p.suffix in (".yaml", ".yml", ".toml"))

PLANAR_YAML = r"""
name: cart_pendulum
description: A pendulum hanging from a cart, with everything the format has
coordinates: [x, {name: theta, latex: '\theta'}]
parameters:
  m: 1.0
  l: {value: 0.5, latex: '\ell', description: rod length}
  g: 9.81
  eps: 1e-9
  tiny: 1.0e-9
known:
  f: 0.1*cos(3*t)
definitions:
  s: sin(theta)
gravity: [0, -g]
particles:
  P: {mass: m, position: [x + l*s, -l*cos(theta)]}
bodies:
  rod: {mass: m, inertia: m*l**2/12, position: [x + l*s/2, -l*cos(theta)/2], angle: theta}
forces:
  - {at: P, force: [f, 0]}
  - {point: [x, 0], force: [-x_dot, 0]}
  - {body: rod, torque: -theta_dot/10}
springs:
  - {between: [P, [0, 0]], stiffness: 2*m}
  - {between: [P, rod], stiffness: 1, rest_length: l}
potential: x**2/2
kinetic: 0
generalized_forces:
  theta: -theta_dot/100
constraints:
  - x - f
  - {name: slide, expr: 'x_dot - diff(f, t)'}
initial:
  theta: 0.3
  x_dot: 0
simulate: {t_end: 2.0, dt: 0.01, method: RK45, rtol: 1e-8, atol: 1.0e-10}
"""

PLANAR_TOML = r"""
name = "cart_pendulum"
description = "A pendulum hanging from a cart, with everything the format has"
coordinates = ["x", {name = "theta", latex = '\theta'}]
potential = "x**2/2"
kinetic = 0
constraints = ["x - f", {name = "slide", expr = "x_dot - diff(f, t)"}]
gravity = [0, "-g"]

[parameters]
m = 1.0
l = {value = 0.5, latex = '\ell', description = "rod length"}
g = 9.81
eps = "1e-9"
tiny = 1.0e-9

[known]
f = "0.1*cos(3*t)"

[definitions]
s = "sin(theta)"

[particles.P]
mass = "m"
position = ["x + l*s", "-l*cos(theta)"]

[bodies.rod]
mass = "m"
inertia = "m*l**2/12"
position = ["x + l*s/2", "-l*cos(theta)/2"]
angle = "theta"

[[forces]]
at = "P"
force = ["f", 0]

[[forces]]
point = ["x", 0]
force = ["-x_dot", 0]

[[forces]]
body = "rod"
torque = "-theta_dot/10"

[[springs]]
between = ["P", [0, 0]]
stiffness = "2*m"

[[springs]]
between = ["P", "rod"]
stiffness = 1
rest_length = "l"

[generalized_forces]
theta = "-theta_dot/100"

[initial]
theta = 0.3
x_dot = 0

[simulate]
t_end = 2.0
dt = 0.01
method = "RK45"
rtol = "1e-8"
atol = 1.0e-10
"""

SPATIAL_YAML = """
coordinates: [psi, th, phi]
parameters: {m: 1.0, r: 0.1, A: 0.1, C: 0.2, g: 9.81}
gravity: [0, 0, -g]
bodies:
  disc:
    mass: m
    inertia: [[A, 0, 0], [0, A, 0], [0, 0, C]]
    position: [0, 0, r*cos(th)]
    orientation: [[z, psi], [x, th], [y, phi]]
forces:
  - {body: disc, torque: [0, 0, -psi_dot]}
"""


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def problems(tmp_path: Path, text: str, name: str = "spec.yaml") -> list[str]:
    """The problems of an invalid spec, as formatted strings."""
    with pytest.raises(SpecError) as info:
        load_spec(write(tmp_path, name, text))
    assert info.value.exit_code == 2
    return [str(p).replace(str(tmp_path) + "/", "") for p in info.value.problems]


def one_problem(tmp_path: Path, text: str, name: str = "spec.yaml") -> str:
    found = problems(tmp_path, text, name)
    assert len(found) == 1, found
    return found[0]


def without_locations(value):
    """`value` with every Loc reduced to its key path, the spec's file dropped, and
    numeric texts compared by value (YAML keeps `1.0e-9`, TOML writes `1e-09`)."""
    if isinstance(value, Loc):
        return value.path
    if isinstance(value, Src):
        try:
            return float(value.text), without_locations(value.loc)
        except ValueError:
            return value.text, without_locations(value.loc)
    if isinstance(value, tuple):
        return tuple(without_locations(v) for v in value)
    if dataclasses.is_dataclass(value):
        return {f.name: without_locations(getattr(value, f.name))
                for f in dataclasses.fields(value) if f.name != "file"}
    return value


# --- YAML and TOML --------------------------------------------------------------------

def test_yaml_and_toml_give_the_same_spec(tmp_path):
    from_yaml = load_spec(write(tmp_path, "a.yaml", PLANAR_YAML))
    from_toml = load_spec(write(tmp_path, "a.toml", PLANAR_TOML))
    assert without_locations(from_yaml) == without_locations(from_toml)
    assert from_yaml.dimension == 2 and len(from_yaml.forces) == 3


def test_yaml_locations_are_one_based_line_and_column(tmp_path):
    spec = load_spec(write(tmp_path, "a.yaml", PLANAR_YAML))
    mass = spec.particles[0].mass
    assert (mass.text, mass.loc.line, mass.loc.column, mass.loc.path) == ("m", 17, 13, "particles.P.mass")
    assert spec.forces[2].torque[0].loc.path == "forces[2].torque"
    assert spec.coordinates[1].loc.path == "coordinates[1]"


def test_toml_locations_have_the_line_of_their_key(tmp_path):
    # tomllib gives no positions: lagcli/spec/toml_positions.py finds each key's line
    spec = load_spec(write(tmp_path, "a.toml", PLANAR_TOML))
    lines = PLANAR_TOML.splitlines()
    loc = spec.bodies[0].position[1].loc
    assert loc.path == "bodies.rod.position[1]"
    assert lines[loc.line - 1].lstrip().startswith("position") and loc.column == 1
    loc = spec.parameters[1].loc                                   # l = {value = 0.5, ...}
    assert lines[loc.line - 1].startswith("l = {value")
    loc = spec.constraints[1].loc                                  # in a one-line array: the array's line
    assert lines[loc.line - 1].startswith("constraints = ")


def test_numbers_keep_their_source_text(tmp_path):
    spec = load_spec(write(tmp_path, "a.yaml", PLANAR_YAML))
    values = {p.name: p.value.text for p in spec.parameters}
    assert values == {"m": "1.0", "l": "0.5", "g": "9.81", "eps": "1e-9", "tiny": "1.0e-9"}
    assert (spec.simulate.rtol.text, spec.simulate.atol.text) == ("1e-8", "1.0e-10")
    toml = load_spec(write(tmp_path, "a.toml", PLANAR_TOML))
    assert [p.value.text for p in toml.parameters][-1] == "1e-09"  # repr of the float


def test_defaults_and_optional_forms(tmp_path):
    spec = load_spec(write(tmp_path, "a.yaml", PLANAR_YAML))
    assert spec.springs[0].rest_length.text == "0"
    assert spec.springs[0].ends[0] == "P" and [s.text for s in spec.springs[0].ends[1]] == ["0", "0"]
    assert spec.parameters[1].latex == r"\ell" and spec.parameters[1].description == "rod length"
    assert spec.coordinates[1].latex == r"\theta" and spec.coordinates[0].latex is None
    assert [c.name for c in spec.constraints] == [None, "slide"]
    assert spec.simulate.method == "RK45"


def test_spatial_spec(tmp_path):
    spec = load_spec(write(tmp_path, "top.yaml", SPATIAL_YAML))
    disc = spec.bodies[0]
    assert spec.dimension == 3 and spec.name == "top"
    assert len(disc.inertia) == 9 and disc.angle is None
    assert [axis for axis, _ in disc.orientation] == ["z", "x", "y"]
    assert len(spec.forces[0].torque) == 3


@pytest.mark.parametrize("inertia, count", [("[A, A, C]", 3), ("[A, A, C, 0, 0, 0]", 6)])
def test_spatial_inertia_forms(tmp_path, inertia, count):
    text = SPATIAL_YAML.replace("[[A, 0, 0], [0, A, 0], [0, 0, C]]", inertia)
    assert len(load_spec(write(tmp_path, "top.yaml", text)).bodies[0].inertia) == count


@pytest.mark.parametrize("file, name", [("double-pendulum.yaml", "double_pendulum"),
                                        ("2link.yaml", "_2link")])
def test_name_defaults_to_the_sanitised_file_stem(tmp_path, file, name):
    assert load_spec(write(tmp_path, file, "coordinates: [q]\nkinetic: q_dot**2\n")).name == name


def test_kinetic_and_potential_only(tmp_path):
    spec = load_spec(write(tmp_path, "a.yaml", "coordinates: [q]\nkinetic: q_dot**2/2\npotential: q**2/2\n"))
    assert spec.particles == () and spec.dimension == 2 and spec.kinetic.text == "q_dot**2/2"


def test_c_keywords_and_soft_keywords_are_allowed_names(tmp_path):
    text = "coordinates: [int, match]\nparameters: {double: 1, case: 2, _: 3}\nkinetic: 0\n"
    assert [p.name for p in load_spec(write(tmp_path, "a.yaml", text)).parameters] == ["double", "case", "_"]


# --- reader refusals --------------------------------------------------------------------

@pytest.mark.parametrize("text, expected", [
    ("coordinates: [x]\ncoordinates: [y]\n", "spec.yaml:2:1: duplicate key 'coordinates' (first given on line 1)"),
    ("coordinates: [x]\n1: 2\n", "spec.yaml:2:1: key '1' is read by YAML as a int, not a name"),
    ("coordinates: [x]\non: 2\n", "key 'on' is read by YAML as a bool, not a name\n  hint: quote it: 'on'"),
    ("coordinates: [x]\n? [a]\n: 2\n", "spec.yaml:2:3: a mapping key must be a plain name"),
    ("coordinates: [x]\n<<: {kinetic: 0}\n", "spec.yaml:2:1: YAML merge keys ('<<') are not allowed"),
    ("coordinates: !!python/object/apply:os.system [echo]\n", "spec.yaml:1:14: coordinates: YAML tag"),
    ("coordinates: !!set {x}\n", "YAML tag 'tag:yaml.org,2002:set' is not allowed"),
    ("", "spec.yaml:1:1: spec is empty"),
    ("coordinates: [x\x00]\n", "spec.yaml: invalid YAML: unacceptable character #x0000"),
    ("coordinates: [x]\n---\nkinetic: 0\n", "spec.yaml:2:1: invalid YAML: but found another document"),
    ("coordinates: [x]\n  kinetic: 0\n", "spec.yaml:2:3: invalid YAML:"),
])
def test_yaml_reader_refusals(tmp_path, text, expected):
    assert any(expected in p for p in problems(tmp_path, text)), problems(tmp_path, text)


@pytest.mark.parametrize("name, text, expected", [
    ("spec.yaml", "coordinates: [x]\nkinetic: " + "1" * 5000 + "\n", "spec.yaml:2:10: kinetic: cannot read"),
    ("spec.toml", "coordinates = ['x']\nkinetic = " + "1" * 5000 + "\n", "spec.toml: invalid TOML: a number is too long"),
])
def test_overlong_integer(tmp_path, name, text, expected):
    assert one_problem(tmp_path, text, name).startswith(expected)


def test_invalid_utf8(tmp_path):
    path = tmp_path / "spec.yaml"
    path.write_bytes(b"coordinates: [\xff]\n")
    with pytest.raises(SpecError, match="not valid UTF-8"):
        load_spec(path)


@pytest.mark.parametrize("text, expected", [
    ("coordinates = [\"x\"]\nkinetic = true\n", "spec.toml:2:1: kinetic: expected an expression (a number or a string); got a boolean"),
    ("coordinates = [\"x\"]\n[parameters]\nm = 1979-05-27\n", "spec.toml:3:1: parameters.m: expected an expression"),
    ("coordinates = [\"x\"]\n[simulate]\nt_end = 1\n[simulate]\n", "spec.toml:4:10: invalid TOML: Cannot declare"),
    ("coordinates = [\"x\"]\nkinetic = nan\n", "spec.toml:2:1: kinetic: a number must be finite"),
])
def test_toml_refusals(tmp_path, text, expected):
    found = problems(tmp_path, text, "spec.toml")
    assert any(p.startswith(expected) for p in found), found


# --- validation -------------------------------------------------------------------------

def test_every_problem_is_reported_together(tmp_path):
    text = ("coordinates: [x]\nparameters: {t: 1}\nparticles:\n  P: {mass: true, position: [x]}\n"
            "simulate: {dt: -1}\n")
    assert problems(tmp_path, text) == [
        "spec.yaml:2:14: parameters.t: the name 't' is reserved: 't' is time\n  hint: choose another name",
        "spec.yaml:4:13: particles.P.mass: expected an expression (a number or a string); got a boolean\n"
        "  hint: quote it if you mean a name",
        "spec.yaml:4:29: particles.P.position: expected a vector of 2 or 3 expressions; got a list of 1 item",
    ]  # simulate.dt = -1 is the model stage's to report (constant expressions are evaluated there)


@pytest.mark.parametrize("body, expected", [
    ("{mass: M, inertia: I, position: [x, 0]}", "bodies.rod: missing required key 'angle'"),
    ("{mass: M, inertia: [I, I, I], position: [x, 0, 0]}", "bodies.rod: missing required key 'orientation'"),
    ("{mass: M, inertia: [I, I], position: [x, 0, 0], orientation: []}", "bodies.rod.inertia: a spatial body's inertia is"),
    ("{mass: M, inertia: I, position: [x, 0, 0], orientation: [[w, x]]}", "bodies.rod.orientation[0]: a rotation is [axis, angle]"),
    ("{mass: M, inertia: [I], position: [x, 0], angle: x}", "bodies.rod.inertia: a planar body's inertia is one expression"),
    ("{mass: M, inertia: I, position: [x, 0, 0], angle: x}", "bodies.rod.angle: mixes 2-D and 3-D: this is 2-D but bodies.rod.position (line 4) is 3-D"),
])
def test_body_rules(tmp_path, body, expected):
    text = f"coordinates: [x]\nparameters: {{M: 1, I: 1}}\nbodies:\n  rod: {body}\n"
    found = problems(tmp_path, text)
    assert any(expected in p for p in found), found


FORCE_BASE = """coordinates: [x]
parameters: {m: 1}
particles:
  P: {mass: m, position: [x, 0]}
bodies:
  rod: {mass: m, inertia: m, position: [x, 1], angle: x}
forces:
  - %s
"""


@pytest.mark.parametrize("force, expected", [
    ("{force: [1, 0]}", "forces[0]: give exactly one of 'at', 'point' or 'body' (found none)"),
    ("{at: P}", "forces[0]: give a 'force', a 'torque' or both"),
    ("{body: rod, force: [1, 0]}", "forces[0].force: 'body:' takes a torque only"),
    ("{point: [0, 0], torque: 1}", "forces[0].torque: a torque acts on a body, not at a point"),
    ("{at: P, torque: 1}", "forces[0].at: 'P' is a particle, not a body"),
    ("{body: P, torque: 1}", "forces[0].body: 'P' is a particle, not a body"),
    ("{body: rod, torque: [1, 2]}", "forces[0].torque: a torque is one expression (planar) or [Tx, Ty, Tz]"),
    ("{body: rod, torque: [1, 2, 3]}", "forces[0].torque: mixes 2-D and 3-D"),
    ("{at: rdo, force: [1, 0]}", "forces[0].at: unknown particle or body 'rdo'\n  hint: did you mean 'rod'? "
                                 "defined particles and bodies are: P, rod"),
])
def test_force_rules(tmp_path, force, expected):
    found = problems(tmp_path, FORCE_BASE % force)
    assert any(expected in p for p in found), found


def test_force_and_torque_at_a_body(tmp_path):
    spec = load_spec(write(tmp_path, "a.yaml", FORCE_BASE % "{at: rod, force: [1, 0], torque: 2}"))
    assert spec.forces[0].at == "rod" and spec.forces[0].torque[0].text == "2"


@pytest.mark.parametrize("spring, expected", [
    ("{between: [P, Q], stiffness: 1}", "springs[0].between[1]: unknown particle or body 'Q'"),
    ("{between: [P], stiffness: 1}", "springs[0].between: expected [end, end]"),
    ("{between: [P, rod]}", "springs[0]: missing required key 'stiffness'"),
])
def test_spring_rules(tmp_path, spring, expected):
    text = (FORCE_BASE % "{at: P, force: [1, 0]}") + f"springs:\n  - {spring}\n"
    found = problems(tmp_path, text)
    assert any(expected in p for p in found), found


@pytest.mark.parametrize("text, expected", [
    ("coordinates: [x]\ngeneralized_forces: {y: 1}\n", "generalized_forces.y: 'y' is not a coordinate"),
    ("coordinates: [x]\ninitial: {x_ddot: 1}\n", "initial.x_ddot: 'x_ddot' is not a coordinate or velocity"),
    ("coordinates: [x]\nconstraints: [{name: c, expr: x}, {name: c, expr: x}]\n",
     "constraints[1].name: duplicate constraint name 'c'"),
    ("coordinates: [x]\nconstraints: [{name: 1c, expr: x}]\n", "constraints[0].name: '1c' is not a valid name"),
    ("coordinates: [x]\nconstraints: [[x]]\n", "constraints[0]: expected an expression"),
    ("coordinates: [x]\nsimulate: {method: dop853}\n", "hint: did you mean 'DOP853'?"),
    ("coordinates: [x]\nsimulate: {tend: 1}\n", "simulate.tend: unknown key 'tend'\n  hint: did you mean 't_end'?"),
    ("coordinates: [x]\nname: my-spec\n", "name: 'my-spec' is not a valid name"),
    ("coordinates: []\n", "coordinates: expected a non-empty list of coordinate names"),
    ("kinetic: 0\n", "spec.yaml:1:1: missing required key 'coordinates'"),
    ("- x\n", "expected a mapping with keys name, description, coordinates"),
    ("coordinates: [x]\npotential:\n", "potential: expected an expression (a number or a string); got nothing (null)"),
    ("coordinates: [x]\npotential: ' '\n", "potential: empty expression"),
    ("coordinates: [x]\npotential: [x]\n", "potential: expected an expression (a number or a string); got a list"),
    ("coordinates: [x]\npotential: .inf\n", "potential: a number must be finite"),
    ("coordinates: [x, y]\ngravity: [atan2(y, x), 0]\n", "gravity: a component has unbalanced parentheses"),
    ("coordinates: [x]\nconstraints: [{name: c, expr: atan2(x, 1)}]\n", "hint: in YAML flow style"),
])
def test_section_rules(tmp_path, text, expected):
    found = problems(tmp_path, text)
    assert any(expected in p for p in found), found


@pytest.mark.parametrize("name, reason", [
    ("pi", "'pi' is the constant pi"), ("exp", "it is a function name"), ("None", "it is a Python keyword"),
    ("__x", "names starting with '__' are reserved"), ("lambda_1", "'lambda_...' names are the constraint multipliers"),
    ("q_ddot", "it is the acceleration of coordinate 'q'"),
])
def test_reserved_names(tmp_path, name, reason):
    text = f"coordinates: [q]\ndefinitions:\n  {name}: q\n"
    assert f"the name '{name}' is reserved: {reason}" in one_problem(tmp_path, text)


@pytest.mark.parametrize("section", ["parameters: {rod: 1}", "known: {rod: t}", "definitions: {rod: 1}",
                                     "particles: {rod: {mass: 1, position: [0, 0]}}"])
def test_names_are_unique_across_sections(tmp_path, section):
    text = f"coordinates: [q]\n{section}\nbodies:\n  rod: {{mass: 1, inertia: 1, position: [q, 0], angle: q}}\n"
    assert "bodies.rod: duplicate name 'rod': already a" in one_problem(tmp_path, text)


def test_empty_sections_are_allowed(tmp_path):
    spec = load_spec(write(tmp_path, "a.yaml", "coordinates: [q]\nparameters:\nforces:\nkinetic: 0\n"))
    assert spec.parameters == () and spec.forces == ()


# --- bundled specs ------------------------------------------------------------------------

@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.name)
def test_bundled_spec_loads(path):
    spec = load_spec(path)
    assert spec.coordinates


# --- docs -----------------------------------------------------------------------------------

def test_spec_reference_examples_load(tmp_path):
    """The complete examples in docs/spec.md (the first YAML block, the TOML block) are valid."""
    import re

    text = (ROOT / "docs" / "spec.md").read_text()
    yaml_block = re.search(r"```yaml\n(.*?)```", text, re.S)[1]
    toml_block = re.search(r"```toml\n(.*?)```", text, re.S)[1]
    assert load_spec(write(tmp_path, "doc.yaml", yaml_block)).name == "oscillating_support"
    assert load_spec(write(tmp_path, "doc.toml", toml_block)).particles[0].name == "P"
