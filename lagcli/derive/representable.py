"""What a derivation holds must be a double-precision number (issue 25).

Each number of a spec is bounded as it is parsed (lagcli/model/expr.py: at most 1e300,
nonzero at least 1e-300, at most 1000 exact digits), but the derivation multiplies them:
a mass of 1e299 at a position 1e299 x gives T = 5e896 x'^2, which every output (a
report, generated code, a run) would print as a number no double can hold (inf in C and
numpy). So right after the derivation, T, V, Q', the constraint rows and M are
checked: an infinite, undefined or complex value, or a constant beyond those bounds, is
a located error (exit status 2) naming the quantity and the constant. The location is
the spec item that contributes the constant (a particle, a body, a spring, `kinetic:`,
`potential:`), found only when there is a problem (one element at a time).

F (M q'' = F) is checked when it is first computed (`Derivation.forcing`, on first use),
with the same message: every output that computes in doubles reads F (generated code,
runs, linearize, equilibria...), so each refuses such a spec as before, with the
located exit-2 error every command gives a `LagcliError`; `lagcli check` computes F
to refuse it too. A derive report never computes F: it prints M, V, Q' and what it
rebuilds from them (lagcli/report/display.py) as exact numbers in text, never as
doubles, so a constant of F beyond the double range there (V = 1e299 x^100 printed with
its force -1e301 x^99) is printed exactly, not wrongly; checking F for it would cost
computing F, most of what the report is spared.
"""
from __future__ import annotations

import dataclasses

import sympy as sp

from lagcli.derive.energy import kinetic_parts, potential_energy
from lagcli.errors import Problem, SpecError
from lagcli.model.calculus import TimeDerivative, leaves
from lagcli.model.constants import LARGEST
from lagcli.model.expr import MAX_EXACT_NUMBER_DIGITS, exact_digits

SMALLEST = 1.0 / LARGEST     # a nonzero constant below this would be 0 in double precision
_NOT_FINITE = (sp.zoo, sp.oo, sp.S.NegativeInfinity, sp.nan, sp.I)
_HINT_INFINITE = ("check for a division by zero, e.g. a rolling wheel whose axis is along the surface normal, "
                  "or a root or log of a negative constant")
_HINT_RANGE = ("the derivation multiplies the spec's numbers (a mass of 1e200 at a position 1e200 x gives "
               "5e599 in T): choose units that keep the numbers and their products within 1e-300 .. 1e300")


def refuse_unrepresentable(d) -> None:
    """SpecError naming every quantity of `d` (a Derivation) that is not finite and real
    identically, or holds a constant beyond double precision."""
    if _all_representable(d):
        return
    problems = _problems(d.model, _quantities(d))
    if not problems:           # M is made of T: checked when T passes
        problems = _problems(d.model, _rows("the mass matrix's row of {}", d.mass_matrix, d.model))
    if problems:
        raise SpecError(problems)


def refuse_unrepresentable_forcing(model, F: sp.MatrixBase) -> None:
    """SpecError naming each force F_i of `model`'s equations (F just computed) that holds a
    constant beyond double precision (F is made of T, V and Q', checked before)."""
    problems = _problems(model, _rows("the force F_{} of its equation", F, model))
    if problems:
        raise SpecError(problems)


def _all_representable(d) -> bool:
    """True when no quantity holds a problem: the leaves of all of them, in one walk (T holds
    M's entries: walking each quantity apart walked M twice).
    Each quantity's leaves are among these, so a problem of one is a problem here."""
    values = [value for _, value, _ in _quantities(d)] + [d.mass_matrix]
    leaves = _leaves(values)
    return not any(s in leaves for s in _NOT_FINITE) and out_of_range(None, leaves) is None


def _problems(model, quantities) -> list[Problem]:
    problems = []
    for what, value, loc in quantities:
        leaves = _leaves(value)
        if any(s in leaves for s in _NOT_FINITE):
            worst = next(str(s) for s in _NOT_FINITE if s in leaves)
            problems.append(Problem(loc, f"{what} is infinite, undefined or complex as derived (it holds "
                                         f"{worst})", _HINT_INFINITE))
            continue
        constant = out_of_range(value, leaves)
        if constant is not None:
            problems.append(Problem(_culprit(model, what, loc), f"{what} holds the constant {_short(constant)}, "
                                    f"{_why(constant)}", _HINT_RANGE))
    return problems


def out_of_range(value, leaves: set | None = None) -> sp.Number | None:
    """The first constant of `value` (an expression or matrix; `leaves`: its `_leaves`) that
    no double holds as it is: beyond LARGEST, nonzero below SMALLEST, or an exact number of
    too many digits."""
    leaves = _leaves(value) if leaves is None else leaves
    for number in sorted((leaf for leaf in leaves if isinstance(leaf, sp.Number)), key=sp.default_sort_key):
        if number == 0 or not number.is_finite:
            continue
        if abs(number) > LARGEST or abs(number) < SMALLEST or _digits(number) > MAX_EXACT_NUMBER_DIGITS:
            return number
    return None


def _leaves(value) -> set:
    """The atoms of an expression or matrix (what `atoms()` finds), each subtree object
    visited once (`calculus.leaves`): T and F of a chain share their sums, and walking them
    as trees (`has`, `atoms`) was most of this check's time."""
    return leaves(*_flat(value))


def _flat(value) -> list:
    """The expressions of an expression, a matrix (its nonzero entries: the zeros of a
    1000-coordinate M are 10^6 entries, and 0 is never a problem) or a list of those."""
    if isinstance(value, sp.MatrixBase):
        return list(value.values())
    if isinstance(value, list):
        return [e for v in value for e in _flat(v)]
    return [value]


def _quantities(d):
    """(what, value, where) of T, V, Q' and the constraint rows."""
    model = d.model
    yield "the kinetic energy T", d.T, model.loc("kinetic")
    yield "the potential energy V", d.V, model.loc("potential")
    for i, (q, Q) in enumerate(zip(model.q, d.nonconservative_forces)):
        yield f"the non-conservative force Q'_{q.name}", Q, model.loc(f"coordinates[{i}]")
    for row, spec in zip(d.constraints, model.constraints):
        yield (f"the constraint row '{row.label or row.multiplier.name}'", sp.Matrix([row.expr, row.d, *row.a]),
               spec.loc or model.loc("constraints"))


def _rows(what: str, matrix, model):
    """(what, row, where) of a matrix (M or F), row by row when it holds a problem."""
    if out_of_range(matrix) is not None:      # rare: only then row by row, for the location
        yield from ((what.format(q.name), matrix.row(i), model.loc(f"coordinates[{i}]"))
                    for i, q in enumerate(model.q))


def _culprit(model, what: str, where):
    """The particle, body or spring whose own T or V holds the constant (else `where`)."""
    alone = dict(particles=(), bodies=(), springs=(), kinetic=sp.S.Zero, potential=sp.S.Zero)
    elements = [(p.loc, dataclasses.replace(model, **{**alone, "particles": (p,)})) for p in model.particles]
    elements += [(b.loc, dataclasses.replace(model, **{**alone, "bodies": (b,)})) for b in model.bodies]
    if "kinetic" in what:
        D = TimeDerivative(model.t, model.q, model.qd, model.qdd)
        found = (loc for loc, one in elements if out_of_range(sp.Matrix([*kinetic_parts(one, D)[0]])) is not None)
    elif "potential" in what:
        elements += [(s.loc, dataclasses.replace(model, **{**alone, "springs": (s,)})) for s in model.springs]
        found = (loc for loc, one in elements if out_of_range(potential_energy(one)) is not None)
    else:
        return where
    return next((loc for loc in found if loc is not None), where)


def _digits(number: sp.Number) -> int:
    return exact_digits(number) if number.is_Rational else 0


def _short(number: sp.Number) -> str:
    return str(sp.Float(number, 3))


def _why(number: sp.Number) -> str:
    if abs(number) > LARGEST:
        return f"beyond {LARGEST:g} (infinite in double precision, in generated code and runs)"
    if abs(number) < SMALLEST:
        return f"below {SMALLEST:g} (0 in double precision: a term would vanish from generated code and runs)"
    return f"an exact number of more than {MAX_EXACT_NUMBER_DIGITS} digits"
