"""Hypothesis strategies for spec texts: valid-ish YAML specs with hostile details.

Shared by tests/test_fuzz.py (a bounded, deterministic run in every test session)
and tools/fuzz_campaign.py (a long run, one subprocess per input).

A spec is built as data first: a random subset of the top-level keys, each value
usually well-formed (expressions of the spec's grammar over the declared names)
and sometimes of the wrong type (frames, rolling, dampers, units, inputs, input laws and
events included). Expressions mix every allowed function and
operator with numbers that are huge, tiny, negative or zero, names that exist
and names that do not, and wrong argument counts. The YAML text is then
sometimes mutated: a YAML tag put in front of a value, or the text cut short.
"""
from __future__ import annotations

import yaml
from hypothesis import strategies as st

FUNCTIONS = ("sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
             "exp", "log", "sqrt", "abs", "sign", "min", "max", "diff")
OPERATORS = ("+", "-", "*", "/", "**", "^")
NAMES = ("x", "y", "x_dot", "y_dot", "t", "pi", "m", "k", "g", "d1", "d2", "f", "nope", "x_ddot")
NUMBERS = ("0", "1", "2", "-1", "0.5", "1e-400", "1e400", "1e308", "1e-320", "1e-300", "10**40",
           "9" * 45, "1e6", "2.5e-7", "1000", "-0.0", "1_000", "0x10")
TAGS = ("!!float ", "!!int ", "!!str ", "!!binary ", "!!bool ", "!!null ", "!!set ",
        "!!python/object/apply:os.system ", "!custom ", "!!timestamp ")

numbers = st.one_of(
    st.sampled_from(NUMBERS),
    st.integers(-10**9, 10**9).map(str),
    st.floats(allow_nan=False, allow_infinity=False).map(repr),
)
leaves = st.one_of(st.sampled_from(NAMES), numbers)


def _combine(inner):
    binary = st.tuples(inner, st.sampled_from(OPERATORS), inner).map(lambda p: f"({p[0]}){p[1]}({p[2]})")
    call = st.tuples(st.sampled_from(FUNCTIONS), st.lists(inner, min_size=0, max_size=3)).map(
        lambda p: f"{p[0]}({', '.join(p[1])})")
    return st.one_of(binary, call, inner.map(lambda e: f"-{e}"), inner.map(lambda e: f"({e})"))


expressions = st.recursive(leaves, _combine, max_leaves=10)

junk = st.one_of(st.none(), st.booleans(), st.just([]), st.just({}), st.floats(),
                 st.lists(st.integers(), max_size=3), st.dictionaries(st.sampled_from(["a", "value"]),
                                                                         st.integers(), max_size=2))


def usually(strategy):
    """`strategy`, or (about one time in twenty) a value of the wrong type."""
    return st.integers(0, 19).flatmap(lambda i: junk if i == 19 else strategy)


vectors = st.lists(expressions, min_size=2, max_size=3)
particle = st.fixed_dictionaries({"mass": usually(expressions), "position": usually(vectors)})
body = st.fixed_dictionaries(
    {"mass": usually(expressions), "inertia": usually(st.one_of(expressions, st.lists(expressions, min_size=3,
                                                                                        max_size=3))),
     "position": usually(vectors)},
    optional={"angle": usually(expressions),
              "frame": st.sampled_from(["A", "C", "N"]),
              "orientation": usually(st.lists(st.tuples(st.sampled_from(["x", "y", "z", "w"]), expressions)
                                              .map(list), min_size=1, max_size=3))})
force = st.one_of(
    st.fixed_dictionaries({"at": st.sampled_from(["P", "Q", "B", "nope"]), "force": usually(vectors)}),
    st.fixed_dictionaries({"point": usually(vectors), "force": usually(vectors)}),
    st.fixed_dictionaries({"body": st.sampled_from(["B", "P"]),
                           "torque": usually(st.one_of(expressions, vectors))}))
spring = st.fixed_dictionaries(
    {"between": usually(st.one_of(st.just(["P", "Q"]), st.just(["P", [0, 0]]), st.just(["B", "nope"]),
                                  st.just(["P", "P"]), st.lists(vectors, min_size=2, max_size=2))),
     "stiffness": usually(expressions)}, optional={"rest_length": usually(expressions)})
damper = st.fixed_dictionaries(
    {"between": usually(st.one_of(st.just(["P", "Q"]), st.just(["P", [0, 0]]), st.just(["P", "P"]),
                                  st.just(["B", [0, 0, 0]]), st.lists(vectors, min_size=2, max_size=2))),
     "damping": usually(expressions)})
UNITS = ("m", "kg", "s", "N", "N/m", "N*s/m", "m/s^2", "J", "rad", "deg", "kg*m^2", "1", "0", "nope",
         "exp(kg)", "sin(m)", "atan2(m, s)", "m**1000", "m**0.5", "kg/0", "m^-2", "(m", "N*m")
units = st.sampled_from(UNITS)
unit_parameters = st.dictionaries(st.sampled_from(["m", "k", "g"]),
                                  st.fixed_dictionaries({"value": usually(expressions)},
                                                        optional={"unit": usually(units)}), max_size=3)
unit_coordinates = st.lists(st.one_of(st.sampled_from(["x", "y"]),
                                      st.fixed_dictionaries({"name": st.sampled_from(["x", "y"])},
                                                            optional={"unit": usually(units)})),
                            min_size=1, max_size=2)
inputs_block = st.one_of(st.lists(st.sampled_from(["F", "u", "x", "m"]), max_size=2),
                         st.dictionaries(st.sampled_from(["F", "u"]),
                                         st.one_of(expressions, st.fixed_dictionaries(
                                             {"value": usually(expressions)}, optional={"unit": usually(units)})),
                                         max_size=2))
AXES = ("x", "y", "z", "w")
frames_block = st.dictionaries(
    st.sampled_from(["A", "C"]),
    st.fixed_dictionaries({"rotations": usually(st.lists(st.tuples(st.sampled_from(AXES), expressions).map(list),
                                                         min_size=1, max_size=3))},
                          optional={"parent": st.sampled_from(["A", "C", "N"])}), max_size=2)
rolling_item = st.fixed_dictionaries(
    {"body": st.sampled_from(["B", "P", "nope"])},
    optional={"wheel": usually(st.fixed_dictionaries({"radius": usually(expressions),
                                                      "axis": st.sampled_from(AXES)})),
              "contact": usually(st.lists(expressions, min_size=3, max_size=3)),
              "surface": usually(st.fixed_dictionaries({}, optional={
                  "normal": usually(st.lists(expressions, min_size=3, max_size=3)),
                  "height": usually(expressions), "angular_velocity": usually(expressions)}))})
simulate_block = st.one_of(
    st.dictionaries(st.sampled_from(["t_end", "dt", "method", "rtol", "atol"]),
                    usually(st.one_of(expressions, st.sampled_from(["RK45", "Radau", "nope"])))),
    st.fixed_dictionaries({"inputs": usually(st.dictionaries(st.sampled_from(["F", "u", "x"]), usually(expressions),
                                                             max_size=2))}))
event = st.fixed_dictionaries(
    {"when": usually(expressions), "action": usually(st.sampled_from(["impact", "reset", "stop", "nope"]))},
    optional={"name": st.sampled_from(["hit", "x", "stop"]),
              "direction": st.sampled_from(["falling", "rising", "either", "up"]),
              "restitution": usually(expressions),
              "reset": usually(st.dictionaries(st.sampled_from(["x", "x_dot", "y_dot", "m"]), usually(expressions),
                                               max_size=2))})

spec_data = st.fixed_dictionaries({
    "coordinates": usually(st.one_of(st.sampled_from([["x", "y"], ["x"], ["y", "x"]]),
                                     st.lists(st.sampled_from(["x", "y", "t", "sin", "m"]), min_size=1, max_size=3))),
}, optional={
    "parameters": usually(st.dictionaries(st.sampled_from(["m", "k", "g"]), usually(expressions), max_size=3)),
    "known": usually(st.dictionaries(st.just("f"), usually(expressions), max_size=1)),
    "definitions": usually(st.dictionaries(st.sampled_from(["d1", "d2"]), usually(expressions), max_size=2)),
    "particles": usually(st.dictionaries(st.sampled_from(["P", "Q"]), usually(particle), max_size=2)),
    "bodies": usually(st.dictionaries(st.just("B"), usually(body), max_size=1)),
    "forces": usually(st.lists(usually(force), max_size=2)),
    "springs": usually(st.lists(usually(spring), max_size=2)),
    "gravity": usually(vectors),
    "potential": usually(expressions),
    "kinetic": usually(expressions),
    "generalized_forces": usually(st.dictionaries(st.sampled_from(["x", "y", "z"]), usually(expressions),
                                                  max_size=2)),
    "constraints": usually(st.lists(usually(expressions), max_size=2)),
    "initial": usually(st.dictionaries(st.sampled_from(["x", "y", "x_dot", "q"]), usually(expressions),
                                       max_size=3)),
    "simulate": usually(simulate_block),
    "dampers": usually(st.lists(usually(damper), max_size=2)),
    "dissipation": usually(expressions),
    "inputs": usually(inputs_block),
    "frames": usually(frames_block),
    "rolling": usually(st.lists(usually(rolling_item), max_size=2)),
    "events": usually(st.lists(usually(event), max_size=2)),
})
# the same, in the units dialect: coordinates and parameters with `unit:`
unit_spec_data = st.tuples(spec_data, unit_coordinates, unit_parameters).map(
    lambda p: {**p[0], "coordinates": p[1], **({"parameters": p[2]} if p[2] else {})})


class _Dumper(yaml.SafeDumper):
    def ignore_aliases(self, data):  # a value drawn twice is written twice, not as &anchor/*alias
        return True


@st.composite
def spec_texts(draw) -> str:
    """The YAML text of a random spec (see the module docstring)."""
    text = yaml.dump(draw(st.one_of(spec_data, unit_spec_data)), Dumper=_Dumper, sort_keys=False, default_flow_style=None, width=10_000)
    mutation = draw(st.sampled_from(["none"] * 10 + ["tag", "cut"]))
    if mutation == "tag" and ": " in text:
        places = [i + 2 for i in range(len(text)) if text.startswith(": ", i)]
        at = draw(st.sampled_from(places))
        text = text[:at] + draw(st.sampled_from(TAGS)) + text[at:]
    elif mutation == "cut" and text:
        text = text[:draw(st.integers(0, len(text) - 1))]
    return text
