"""Units (optional) and the dimensional check of a model and its derivation.

Parameters and coordinates may carry a unit (`m: {value: 1.0, unit: kg}`,
`coordinates: [{name: x, unit: m}]`). A unit is an expression of sympy.physics.units
names (`kg`, `m`, `s`, `N`, `N*m`, `kg*m**2`, `m/s^2`, `rad`, `deg`, ...), read by
lagcli's own safe expression parser. When any unit is given, every name without one
is dimensionless (angles are: `rad` is dimensionless), velocities are q/s,
accelerations q/s^2 and t is in seconds, and each spec item must have its physical
dimension (a mass, a length, a force, a torque = force x length, an energy, ...),
each sum's terms the same dimension and each function's argument none. A mismatch is
a `SpecError` naming the item and the offending term.
"""
from __future__ import annotations

import functools
from collections.abc import Iterable

import sympy as sp

from lagcli.errors import Loc, Problem, SpecError
from lagcli.model.expr import Scope, parse

Dim = tuple[tuple[str, sp.Rational], ...]    # sorted (base dimension, power); () is dimensionless
NONE: Dim = ()


@functools.cache
def unit_names() -> dict:
    """name -> sympy Quantity for every unit of sympy.physics.units (imported on first
    use: it takes seconds, and only specs with units need it)."""
    import sympy.physics.units as si_units

    return {name: getattr(si_units, name) for name in sorted(dir(si_units))
            if isinstance(getattr(si_units, name), si_units.Quantity)}


class Mismatch(Exception):
    """A term whose dimension does not fit where it stands."""

    def __init__(self, term: sp.Expr, message: str):
        super().__init__(message)
        self.term, self.message = term, message


# --- dimensions ---------------------------------------------------------------------------

def _dim(mapping: dict) -> Dim:
    return tuple(sorted((str(k), sp.Rational(v)) for k, v in mapping.items() if v != 0))


def times(a: Dim, b: Dim, power: int = 1) -> Dim:
    total = dict(a)
    for name, p in b:
        total[name] = total.get(name, 0) + power * p
    return _dim(total)


def raised(a: Dim, exponent: sp.Rational) -> Dim:
    return _dim({name: p * exponent for name, p in a})


def unit_dimension(text: str, loc: Loc) -> Dim:
    """The dimension of a unit written in the spec (`N*m`, `m/s^2`)."""
    from sympy.physics.units import Dimension
    from sympy.physics.units.systems.si import SI, dimsys_SI

    scope = Scope(dict(unit_names()), sp.Symbol("_time_"))
    try:
        value = parse(text, scope, loc)
    except SpecError as exc:
        raise SpecError([Problem(p.loc, f"unit: {p.message}", "units are sympy.physics.units names, e.g. "
                                 "kg, m, s, N, J, rad, N*m, m/s^2") for p in exc.problems]) from None
    if not _is_product_of_powers(value):
        raise SpecError(Problem(loc, f"unit: {text!r} is not a product of powers of units (a function of a "
                                "unit, or a sum, has no dimension)", "units are sympy.physics.units names, "
                                "multiplied, divided and raised to numeric powers, e.g. N*m or m/s^2"))
    expression = SI.get_dimensional_expr(value)
    return _dim({k.name: v for k, v in dimsys_SI.get_dimensional_dependencies(Dimension(expression)).items()})


def _is_product_of_powers(value: sp.Expr) -> bool:
    if value.is_Mul:
        return all(_is_product_of_powers(factor) for factor in value.args)
    if value.is_Pow:
        return value.exp.is_Rational and _is_product_of_powers(value.base)
    from sympy.physics.units import Quantity

    return value.is_Rational or isinstance(value, Quantity)


BASE_UNITS = {"mass": "kg", "length": "m", "time": "s", "current": "A", "temperature": "K",
              "amount_of_substance": "mol", "luminous_intensity": "cd"}


def describe(dim: Dim) -> str:
    """The dimension in the derived unit the docs use, with its SI base units: `N/m (kg/s**2)`;
    in base units alone when no derived unit is usual (`kg*m/s`), or `dimensionless`."""
    base = base_units(dim)
    derived = DERIVED.get(dim)
    return f"{derived} ({base})" if derived else base


def base_units(dim: Dim) -> str:
    """The dimension in SI base units, `kg*m**2/s**2`, or `dimensionless`."""
    if not dim:
        return "dimensionless"
    order = list(BASE_UNITS)
    dim = sorted(dim, key=lambda item: (order.index(item[0]) if item[0] in order else len(order), item[0]))
    unit = {name: BASE_UNITS.get(name, name) for name, _ in dim}
    up = [f"{unit[n]}**{p}" if p != 1 else unit[n] for n, p in dim if p > 0] or ["1"]
    down = [f"{unit[n]}**{-p}" if p != -1 else unit[n] for n, p in dim if p < 0]
    return "*".join(up) + ("/" + "/".join(down) if down else "")


MASS = _dim({"mass": 1})
LENGTH = _dim({"length": 1})
TIME = _dim({"time": 1})
ENERGY = _dim({"mass": 1, "length": 2, "time": -2})
FORCE = times(ENERGY, LENGTH, -1)
POWER = times(ENERGY, TIME, -1)
NAMED = {MASS: "a mass", LENGTH: "a length", ENERGY: "an energy or a torque, J = N*m", FORCE: "a force, N",
         POWER: "a power, W", times(LENGTH, TIME, -2): "an acceleration",
         times(MASS, raised(LENGTH, 2)): "a moment of inertia"}


DERIVED = {FORCE: "N", ENERGY: "J = N*m", POWER: "W", times(FORCE, LENGTH, -1): "N/m",
           times(times(FORCE, TIME), LENGTH, -1): "N*s/m", times(ENERGY, TIME): "N*m*s",
           times(FORCE, TIME): "N*s", times(FORCE, raised(LENGTH, 2), -1): "Pa"}


def named(dim: Dim) -> str:
    return f"{NAMED[dim]} ({base_units(dim)})" if dim in NAMED else describe(dim)


# --- the dimension of an expression ---------------------------------------------------------

_DIMENSIONLESS_FUNCTIONS = (sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.sinh, sp.cosh, sp.tanh,
                            sp.exp, sp.log)


def dimension_of(expr: sp.Expr, dims: dict) -> Dim:
    """The dimension of `expr`, its symbols' dimensions in `dims` (absent: dimensionless);
    raises `Mismatch` at the first term that does not fit."""
    if expr.is_Symbol:
        return dims.get(expr, NONE)
    if expr.is_Number or expr.is_NumberSymbol:
        return NONE
    if expr.is_Add:
        return _same(expr.args, dims, "a sum")
    if expr.is_Mul:
        total = NONE
        for factor in expr.args:
            total = times(total, dimension_of(factor, dims))
        return total
    if expr.is_Pow:
        base, exponent = expr.args
        _dimensionless(exponent, dims, "an exponent")
        base_dim = dimension_of(base, dims)
        if base_dim and not exponent.is_Rational:
            raise Mismatch(expr, f"{base} ({describe(base_dim)}) is raised to a power that is not a number")
        return raised(base_dim, exponent) if base_dim else NONE
    if isinstance(expr, (sp.Abs, sp.Min, sp.Max)):
        return _same(expr.args, dims, "min/max")
    if isinstance(expr, sp.atan2):
        _same(expr.args, dims, "atan2")
        return NONE
    if isinstance(expr, sp.sign):
        dimension_of(expr.args[0], dims)
        return NONE
    if isinstance(expr, _DIMENSIONLESS_FUNCTIONS):
        for argument in expr.args:
            _dimensionless(argument, dims, f"the argument of {type(expr).__name__}")
        return NONE
    for argument in expr.args:      # anything else sympy made: at least its parts must be sound
        dimension_of(argument, dims)
    return NONE


def _same(terms: Iterable[sp.Expr], dims: dict, what: str) -> Dim:
    terms = list(terms)
    found = [dimension_of(term, dims) for term in terms]
    majority = max(found, key=found.count)     # the first of the most common: deterministic
    for term, dim in zip(terms, found):
        if dim != majority:
            raise Mismatch(term, f"the term {_show(term)} is {describe(dim)} but the other terms of "
                                 f"{what} are {describe(majority)}")
    return majority


def _dimensionless(expr: sp.Expr, dims: dict, what: str) -> None:
    dim = dimension_of(expr, dims)
    if dim:
        raise Mismatch(expr, f"{what}, {_show(expr)}, is {describe(dim)}; it must be dimensionless")


def _show(expr: sp.Expr) -> str:
    return repr(str(expr))


def expect(expr: sp.Expr, wanted: Dim, dims: dict, loc: Loc, what: str) -> Problem | None:
    """A located problem when `expr` (the spec's `what`) is not of dimension `wanted`,
    naming the first term of it that is not."""
    expr = sp.sympify(expr)
    if expr.is_zero:     # 0 is a zero of every dimension (a generalized force that vanishes)
        return None
    terms = sp.Add.make_args(expr)
    for term in terms:
        try:
            found = dimension_of(term, dims)
        except Mismatch as exc:
            return Problem(loc, f"{what} is not dimensionally consistent: {exc.message}", UNIT_HINT)
        if found != wanted:
            culprit = f"the term {_show(term)} of {_show(expr)}" if len(terms) > 1 else _show(expr)
            return Problem(loc, f"{what} should be {named(wanted)} but {culprit} is {named(found)}", UNIT_HINT)
    return None


UNIT_HINT = ("check the units of the parameters and coordinates it uses (a name without `unit:` is "
             "dimensionless; a torque is a force times a length)")


# --- the checks -----------------------------------------------------------------------------

def symbol_dimensions(model) -> dict:
    """symbol -> dimension for t, the coordinates (and their velocities, accelerations) and
    the parameters; empty when the spec gives no unit at all (then nothing is checked)."""
    if not model.units:
        return {}
    problems, dims = [], {model.t: TIME}
    for name, (text, loc) in model.units.items():
        try:
            dims[name] = unit_dimension(text, loc)
        except SpecError as exc:
            problems += exc.problems
    if problems:
        raise SpecError(problems)
    out = {model.t: TIME}
    for q, qd, qdd in zip(model.q, model.qd, model.qdd):
        d = dims.get(q.name, NONE)
        out.update({q: d, qd: times(d, TIME, -1), qdd: times(d, TIME, -2)})
    out.update({p.symbol: dims.get(p.symbol.name, NONE) for p in (*model.parameters, *model.inputs)})
    return out


def check_model_units(model) -> None:
    """Raise `SpecError` naming every spec item whose dimension is wrong (units given only)."""
    dims = symbol_dimensions(model)
    if not dims:
        return
    problems = [p for p in _model_items(model, dims) if p is not None]
    if problems:
        raise SpecError(problems)


def check_derivation_units(derivation) -> None:
    """`check`: every term of T and V, each generalized force and each equation of motion."""
    model = derivation.model
    dims = symbol_dimensions(model)
    if not dims:
        return
    problems = [expect(derivation.T, ENERGY, dims, model.loc("kinetic"), "the kinetic energy T"),
                expect(derivation.V, ENERGY, dims, model.loc("potential"), "the potential energy V")]
    for i, q in enumerate(model.q):
        per_q = times(ENERGY, dims[q], -1)
        where = model.loc(f"coordinates[{i}]")
        problems.append(expect(derivation.generalized_forces[i], per_q, dims, where,
                               f"the generalized force Q_{q.name}"))
        problems.append(expect(derivation.equations[i].lhs, per_q, dims, where,
                               f"the equation of motion of {q.name}"))
    problems = [p for p in problems if p is not None]
    if problems:
        raise SpecError(problems)


def _model_items(model, dims: dict):
    """(problem or None) for every spec item with a physical dimension."""
    def check(expr, wanted, loc, what):
        expr = sp.sympify(expr)
        return None if expr.is_Number else expect(expr, wanted, dims, loc or Loc(model.source), what)

    acceleration = times(LENGTH, TIME, -2)
    for p in model.particles:
        yield check(p.mass, MASS, p.loc, f"the mass of '{p.name}'")
        yield from (check(c, LENGTH, p.loc, f"the position of '{p.name}'") for c in p.position)
    for b in model.bodies:
        yield check(b.mass, MASS, b.loc, f"the mass of '{b.name}'")
        yield from (check(c, LENGTH, b.loc, f"the position of '{b.name}'") for c in b.position)
        yield from (check(c, times(MASS, raised(LENGTH, 2)), b.loc, f"the inertia of '{b.name}'")
                    for c in b.inertia)
        yield from (check(a, NONE, b.loc, f"a rotation angle of '{b.name}'") for _, a in b.rotations)
    if model.gravity is not None:
        yield from (check(g, acceleration, model.loc(f"gravity[{i}]"), "gravity") for i, g in enumerate(model.gravity))
    for f in model.forces:
        yield from (check(c, FORCE, f.loc.child("force") if f.loc else None, "the force")
                    for c in (f.force if f.force is not None else ()))
        yield from (check(c, ENERGY, f.loc.child("torque") if f.loc else None, "the torque (a force times a length)")
                    for c in (f.torque if f.torque is not None else ()))
    for s in model.springs:
        yield check(s.stiffness, times(FORCE, LENGTH, -1), s.loc, "a spring's stiffness")
        yield check(s.rest_length, LENGTH, s.loc, "a spring's rest length")
        yield from (check(c, LENGTH, s.loc, "a spring's end") for c in (*s.end_a, *s.end_b))
    for d in model.dampers:
        yield check(d.damping, times(times(FORCE, TIME), LENGTH, -1), d.loc, "a damper's damping")
        yield from (check(c, LENGTH, d.loc, "a damper's end") for c in (*d.end_a, *d.end_b))
    yield check(model.potential, ENERGY, model.loc("potential"), "the potential")
    yield check(model.kinetic, ENERGY, model.loc("kinetic"), "the kinetic energy")
    yield check(model.dissipation, POWER, model.loc("dissipation"), "the dissipation function")
    for q, Q in zip(model.q, model.generalized_forces):
        yield check(Q, times(ENERGY, dims[q], -1), model.loc(f"generalized_forces.{q.name}"),
                    f"the generalized force on {q.name}")
    for c in model.constraints:
        try:
            dimension_of(c.expr, dims)
        except Mismatch as exc:
            yield Problem(c.loc or Loc(model.source), f"the constraint is not dimensionally consistent: "
                          f"{exc.message}", UNIT_HINT)
