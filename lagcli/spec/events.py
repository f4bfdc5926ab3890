"""The spec's hybrid keys: `events:` and the input laws of `simulate: inputs:`.

    simulate:
      inputs: {F: "-k1*x - k2*x_dot"}     # a law per input: t, q, q', parameters, definitions
    events:
      - name: floor                       # optional; default event_<k> (1-based)
        when: y                           # g(t, q, q'); the event is where g crosses zero
        direction: falling                # falling (default) | rising | either
        action: impact                    # impact | reset | stop
        restitution: e                    # impact: a constant expression in [0, 1]
        rest: true                        # impact: hold g = 0 while it pushes (default false)
      - {name: step, when: theta + alpha, action: reset, reset: {theta: theta + 2*alpha}}

Shapes, names and references are checked here; what the expressions may depend on
(an impact's `when` no velocities, a law no accelerations) is checked when they are
parsed (lagcli/model/hybrid_model.py).
"""
from __future__ import annotations

from typing import Any

from lagcli.interface import contact_force_name
from lagcli.spec.checker import did_you_mean
from lagcli.spec.format import ACTIONS, DIRECTIONS, EVENT
from lagcli.spec.reader import KeyPath
from lagcli.spec.types import Event, Named


def events_field(checker, top: dict) -> tuple[Event, ...]:
    """The `Spec` field `events` of the top-level table `top`."""
    names: set[str] = set()
    events = checker.list_items(top, "events", lambda path, value: _event(checker, path, value, names))
    return events


def input_laws(checker, path: KeyPath, value: Any) -> tuple[Named, ...]:
    """`simulate: inputs:`: a mapping input name -> law (an expression)."""
    if not isinstance(value, dict):
        checker.fail(path, "expected a mapping input name: law, e.g. inputs: {F: '-k*x'}")
        return ()
    inputs = sorted(n for n, (kind, _) in checker.names.items() if kind == "input")
    laws = []
    for name, law in value.items():
        if name not in inputs:
            hint = did_you_mean(name, inputs) or (f"declared inputs are: {', '.join(inputs)}" if inputs
                                                  else "declare it in the spec's inputs: first")
            checker.fail(path + (name,), f"'{name}' is not an input", hint, at_key=True)
            continue
        src = checker.expr(path + (name,), law)
        if src is not None:
            laws.append(Named(name, src, checker.raw.loc(path + (name,), at_key=True)))
    return tuple(laws)


def _event(checker, path: KeyPath, value: Any, names: set[str]) -> Event | None:
    table = checker.table(path, value, EVENT)
    if table is None:
        return None
    name = checker.identifier(path + ("name",), table["name"]) if "name" in table else f"event_{path[-1] + 1}"
    if name is not None and name in names:
        checker.fail(path + ("name",), f"duplicate event name '{name}'", "each event needs its own name")
    names.add(name)
    direction = _choice(checker, path + ("direction",), table.get("direction", DIRECTIONS[0]), DIRECTIONS,
                        "direction")
    action = (_choice(checker, path + ("action",), table["action"], ACTIONS, "action") if "action" in table
              else None)
    when = checker.expr(path + ("when",), table["when"]) if "when" in table else None
    restitution = _restitution(checker, path, table, action)
    reset = _reset(checker, path, table, action)
    rest = _rest(checker, path, table, action)
    if rest and name is not None and contact_force_name(name) in checker.coordinate_names:
        checker.fail(path + ("name",), f"a coordinate is called '{contact_force_name(name)}', the column of this "
                     "event's contact force (rest: true)", "rename the event or the coordinate")
    if None in (name, direction, action, when, reset, rest):
        return None
    return Event(name, when, direction, action, restitution, reset, checker.raw.loc(path), rest)


def _rest(checker, path: KeyPath, table: dict, action: str | None) -> bool | None:
    """`rest: true`: hold the impact's contact g = 0 as a constraint while it pushes (lagcli/run/contact.py)."""
    value = table.get("rest", False)
    if not isinstance(value, bool):
        checker.fail(path + ("rest",), f"expected true or false; got {value!r}")
        return None
    if value and action not in ("impact", None):
        checker.fail(path + ("rest",), f"'rest' belongs to an impact, not a {action}",
                     "a contact can rest only where an impact closes it")
        return None
    return value


def _choice(checker, path: KeyPath, value: Any, choices: tuple[str, ...], what: str) -> str | None:
    if value in choices:
        return value
    hint = did_you_mean(str(value), choices) or f"choose one of: {', '.join(choices)}"
    checker.fail(path, f"unknown {what} {value!r}: an event's {what} is one of {', '.join(choices)}", hint)
    return None


def _restitution(checker, path: KeyPath, table: dict, action: str | None):
    if action != "impact":
        if "restitution" in table and action is not None:
            checker.fail(path + ("restitution",), f"'restitution' belongs to an impact, not a {action}",
                         "use action: impact, or remove it")
        return None
    if "restitution" not in table:
        checker.fail(path, "an impact needs its 'restitution' (0: plastic .. 1: elastic)")
        return None
    return checker.expr(path + ("restitution",), table["restitution"])


def _reset(checker, path: KeyPath, table: dict, action: str | None) -> tuple[Named, ...] | None:
    if action != "reset":
        if "reset" in table and action is not None:
            checker.fail(path + ("reset",), f"'reset' belongs to action: reset, not {action}")
        return ()
    value = table.get("reset")
    if not isinstance(value, dict) or not value:
        checker.fail(path + ("reset",) if "reset" in table else path,
                     "a reset needs 'reset': a mapping state: new value (e.g. {theta: theta + 2*alpha})")
        return None
    states = sorted(checker.state_names())
    items = []
    for name, item in value.items():
        where = path + ("reset", name)
        if name not in states:
            hint = did_you_mean(name, states) or f"states are: {', '.join(states)}"
            checker.fail(where, f"'{name}' is not a state (a coordinate or <q>_dot) to reset", hint, at_key=True)
            continue
        src = checker.expr(where, item)
        if src is not None:
            items.append(Named(name, src, checker.raw.loc(where, at_key=True)))
    return tuple(items)
