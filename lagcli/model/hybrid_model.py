"""Input laws and events, parsed with the safe parser and checked (spec -> Model).

What each expression may use:

    law u = f(...)          t, q, q', parameters, known functions, definitions
                            (no accelerations, no multipliers, no inputs)
    impact `when`           g(t, q): no velocities (a gap; G = dg/dq)
    reset/stop `when`       g(t, q, q')
    reset values            t, q, q' of the state just before the event
    restitution             parameters only, and in [0, 1] at their values

A law given at run time (`--input F=EXPR`, `System.simulate(inputs={"F": "..."})`) is
parsed by `parse_law` with the same scope and checks.
"""
from __future__ import annotations

import sympy as sp

from lagcli.model.calculus import TimeDerivative
from lagcli.errors import Loc, Problem, SpecError
from lagcli.model.expr import Scope, parse
from lagcli.interface import multiplier_name
from lagcli.model.model_types import EventSpec, InputLaw, Model
from lagcli.spec.types import Src


def hybrid_fields(builder) -> dict:
    """The Model fields `laws` and `events` (problems recorded on `builder`)."""
    scope = builder.scope
    saved = dict(scope.names)
    scope.names.update(_placeholders(builder.spec.constraints, builder.qdd))
    try:
        checks = _Checks(builder)
        laws = tuple(InputLaw(sp.Symbol(law.name, real=True), builder.expr(law.expr, check=checks.law), law.loc)
                     for law in builder.spec.simulate.inputs)
        events = tuple(_event(builder, checks, e) for e in builder.spec.events)
    finally:
        scope.names = saved
    return dict(laws=laws, events=events)


def parse_law(model: Model, name: str, text: str, where: str) -> InputLaw:
    """A law given at run time for input `name`, e.g. `--input F=-k*x` (`where` names it)."""
    names = {"pi": sp.pi, **{s.name: s for s in (*model.q, *model.qd, *model.parameter_symbols,
                                                  *model.input_symbols)}}
    names.update(dict(model.known))
    names.update(dict(model.definitions))
    names.update(_placeholders((), model.qdd))
    D = TimeDerivative(model.t, model.q, model.qd, model.qdd)
    loc = Loc(where)
    value = parse(text, Scope(names, model.t, D), loc)
    _law_check(model.input_symbols, model.qdd, value, Src(text, loc))
    return InputLaw(model.symbol(name), value, loc)


class _Checks:
    def __init__(self, builder):
        self.b = builder

    def law(self, value: sp.Expr, src: Src) -> None:
        _law_check(self.b.u, self.b.qdd, value, src)

    def gap(self, value: sp.Expr, src: Src) -> None:
        self.state(value, src)
        used = value.free_symbols & set(self.b.qd)
        if used:
            raise SpecError(Problem(src.loc, f"an impact's 'when' is a gap g(t, q): {src.text!r} uses the "
                                    f"velocities {_names(used)}", "an impact needs a position condition "
                                    "(G = dg/dq is the direction of the impulse); use action: reset or "
                                    "stop for a condition on velocities"))
        if not value.free_symbols & set(self.b.q):
            raise SpecError(Problem(src.loc, f"an impact's 'when' is a gap g(t, q): {src.text!r} uses no "
                                    "coordinate, so G = dg/dq = 0 gives the impulse no direction",
                                    "write the gap in the coordinates (e.g. y for a floor at y = 0); "
                                    "use action: reset or stop for a condition on t alone"))

    def state(self, value: sp.Expr, src: Src) -> None:
        """t, q, q' and parameters only."""
        _law_check(self.b.u, self.b.qdd, value, src, "an event")

    def constant(self, value: sp.Expr, src: Src) -> None:
        """A restitution: numbers and parameters (no t, state or input)."""
        self.b.no_inputs(value, src)
        used = value.free_symbols & self.b.moving
        if used:
            raise SpecError(Problem(src.loc, f"a restitution is a constant: {src.text!r} uses {_names(used)}",
                                    "use numbers and parameters (e.g. restitution: e with e a parameter)"))


def _law_check(inputs, qdd, value: sp.Expr, src: Src, what: str = "an input law") -> None:
    bad = [s for s in value.free_symbols if s.name.startswith("lambda_")]
    if bad:
        raise SpecError(Problem(src.loc, f"{what} cannot use the multiplier(s) {_names(bad)}: "
                                f"{src.text!r}", "a multiplier is a result of the motion, not a state"))
    used = value.free_symbols & set(qdd)
    if used:
        raise SpecError(Problem(src.loc, f"{what} cannot use accelerations: {src.text!r} uses {_names(used)}",
                                "use t, coordinates, velocities, parameters and definitions"))
    used = value.free_symbols & set(inputs)
    if used:
        raise SpecError(Problem(src.loc, f"{what} cannot use the input(s) {_names(used)}: {src.text!r}",
                                "write the law of that input into this expression instead"))


def _event(builder, checks: _Checks, e) -> EventSpec:
    when = builder.expr(e.when, check=checks.gap if e.action == "impact" else checks.state)
    restitution = None
    if e.restitution is not None:
        restitution = builder.expr(e.restitution, check=checks.constant)
        _in_unit_interval(builder, restitution, e.restitution)
    reset = tuple((item.name, builder.expr(item.expr, check=checks.state)) for item in e.reset)
    return EventSpec(e.name, when, e.direction, e.action, restitution, reset, e.loc, e.rest)


def _in_unit_interval(builder, value: sp.Expr, src: Src) -> None:
    if value.free_symbols - set(builder.parameter_values):
        return                                   # already reported as not constant
    number = float(value.subs(builder.parameter_values))
    if not 0.0 <= number <= 1.0:
        builder.problems.append(Problem(src.loc, f"restitution {src.text!r} = {number:g} is outside [0, 1]",
                                        "0 is a plastic impact, 1 an elastic one"))


def _placeholders(constraints, qdd) -> dict:
    """Names a law or event must not use but may write: accelerations and multipliers
    (so the message says why, rather than 'unknown name')."""
    names = {s.name: s for s in qdd}
    for j, c in enumerate(constraints, start=1):
        for label in {None, c.name}:
            name = multiplier_name(j, label)
            names[name] = sp.Symbol(name, real=True)
    return names


def _names(symbols) -> str:
    return ", ".join(sorted(map(str, symbols)))
