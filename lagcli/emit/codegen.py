"""The language-independent half of code generation: expressions, CSE, slots, printers.

Every generated module evaluates the same groups of expressions of a `Derivation`
(`collect`), all reduced by ONE `sympy.cse` call (`eliminate`), so a temporary is
shared by every function that needs it; each function then computes only the
temporaries its outputs depend on (`Reduced.block`).

Symbols print as array slots, never as their spec names (so a parameter called
`register` or `y0` cannot break the output):

    t                      time
    y[i]                   q_i for i < n, q'_(i-n) for n <= i < 2n
    p[j]                   parameter j in spec order
    x0, x1, ...            CSE temporaries (sympy Dummies, named by position)

`SlotPrinter` is the mixin each language's printer subclass starts from: it prints
a symbol through its slot and raises `EmitError` for a symbol without one; the
language module calls `check_slots` on every expression before printing anything.
Numbers print as exact decimal literals (17 significant digits for floats, 21 for
constants like pi), small integer powers as products.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import PurePath

import sympy as sp
from sympy.printing.codeprinter import PrintMethodNotImplementedError

from lagcli.calculus import TooSlow, time_limit
from lagcli.derive.result import Derivation
from lagcli.errors import EmitError

CONSTANT_DIGITS = 21          # pi, E, ... as literals: 3.14159265358979323846
MAX_PRODUCT_POWER = 4         # x**k, 2 <= |k| <= 4, prints as x*x*...; larger via pow
CSE_OPTIMIZATIONS = "basic"   # sympy.cse's: fewer operations for N = 2 and 8 links (docs/codegen.md)
TIDY_MAX_OPS = 80             # trigsimp only expressions this small (bench/codegen.py: cost vs gain)
COLLECT_MAX_OPS = 5000        # expand + collect only expressions this small
TIDY_SECONDS = 2.0            # per tidy step; past it the expression stays as it was
TRIGSIMP_FUNCTIONS = (sp.sin, sp.cos)   # trigsimp only expressions calling nothing else
PRINTABLE = (sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.atan2, sp.sinh, sp.cosh,
             sp.tanh, sp.exp, sp.log, sp.Abs, sp.sign, sp.Min, sp.Max)


@dataclass(frozen=True)
class Outputs:
    """Every expression a generated module evaluates, grouped by use (flat, row-major).

    mass_matrix          n*n   M (upper triangle mirrored: exactly symmetric)
    forcing              n     F, with M q'' = F + A^T lambda
    constraint_matrix    m*n   A
    constraint_bias      m     b = -(A' q' + d')
    constraint_velocity  m     A q' + d        (Baumgarte damping, residual)
    constraint_position  h     phi_j of the holonomic rows (Baumgarte, residual)
    invariants           k     energy T + V, the Jacobi integral (when it exists),
                               p_<q> for each ignorable coordinate
    """

    mass_matrix: tuple
    forcing: tuple
    constraint_matrix: tuple
    constraint_bias: tuple
    constraint_velocity: tuple
    constraint_position: tuple
    invariants: tuple
    invariant_names: tuple[str, ...]
    holonomic_rows: tuple[int, ...]   # row index j of each constraint_position entry

    def groups(self) -> dict[str, tuple]:
        return {name: getattr(self, name) for name in GROUPS}


GROUPS = ("mass_matrix", "forcing", "constraint_matrix", "constraint_bias",
          "constraint_velocity", "constraint_position", "invariants")


def collect(d: Derivation, tidy: bool = True) -> Outputs:
    """The expressions of `d` that generated code evaluates (see `Outputs`), each small
    one simplified when that lowers its operation count (`tidy_expression`)."""
    outputs = _collect(d)
    if not tidy:
        return outputs
    cache: dict = {}
    return replace(outputs, **{name: tuple(tidy_expression(e, d.model.qd, cache) for e in exprs)
                               for name, exprs in outputs.groups().items()})


def tidy_expression(expr, velocities=(), cache: dict | None = None) -> sp.Expr:
    """The cheapest (sympy.count_ops) of: expr; expr expanded and collected over the
    `velocities`, each coefficient collected over its function calls (the physical
    grouping of F = sum c_jk q'_j q'_k + c_j q'_j + c_0); and `factor_terms(trigsimp(.))`
    of the better of these two when it has at most TIDY_MAX_OPS operations and calls
    only sin and cos (`trigsimp_safe`). A candidate may not call a function expr does
    not already call: a new cos(q1 - q2) costs more at run time than the
    multiplications it saves. Each step gets TIDY_SECONDS (`lagcli.calculus.time_limit`);
    one that runs out leaves the expression as it was (tidying is only an optimisation:
    sympy's trigsimp can grind for minutes on tanh, Max or sign terms)."""
    expr = sp.sympify(expr)
    if cache is not None and expr in cache:
        return cache[expr]
    result = expr
    if not expr.is_Atom and sp.count_ops(expr) <= COLLECT_MAX_OPS:
        calls = expr.atoms(sp.Function)
        result = _cheaper(expr, _limited(_collected, expr, list(velocities)), calls)
        if sp.count_ops(result) <= TIDY_MAX_OPS and trigsimp_safe(result):
            simplified = _limited(lambda e: sp.factor_terms(sp.trigsimp(e)), result)
            result = _cheaper(result, simplified, calls)
    if cache is not None:
        cache[expr] = result
    return result


def trigsimp_safe(expr) -> bool:
    """True when expr is built from numbers, symbols, +, * and powers, and calls only
    sin and cos: what trigsimp is meant for (and fast on)."""
    for node in sp.preorder_traversal(expr):
        if node.is_Atom or node.is_Add or node.is_Mul or isinstance(node, TRIGSIMP_FUNCTIONS):
            continue
        if node.is_Pow and node.exp.is_Rational:
            continue
        return False
    return True


def _limited(step, expr, *args):
    """step(expr, *args) within TIDY_SECONDS, else expr unchanged."""
    try:
        with time_limit(TIDY_SECONDS):
            return step(expr, *args)
    except TooSlow:
        return expr


def _collected(expr, velocities: list) -> sp.Expr:
    def by_calls(coefficient):
        calls = sorted(coefficient.atoms(sp.Function), key=sp.default_sort_key)
        return sp.factor_terms(sp.collect(coefficient, calls))

    return sp.collect(sp.expand(expr), velocities, func=by_calls)


def _cheaper(current, candidate, calls) -> sp.Expr:
    """candidate when it has fewer operations and calls only known functions among `calls`."""
    found = candidate.atoms(sp.Function)
    if found <= calls and all(isinstance(f, PRINTABLE) for f in found) \
            and sp.count_ops(candidate) < sp.count_ops(current):
        return candidate
    return current


def _collect(d: Derivation) -> Outputs:
    n, qd = d.n, d.model.qd
    M = d.mass_matrix
    mass = tuple(M[min(i, j), max(i, j)] for i in range(n) for j in range(n))
    rows = d.constraints
    velocity = tuple(sum((a * v for a, v in zip(r.a, qd)), sp.S.Zero) + r.d for r in rows)
    holonomic = tuple(j for j, r in enumerate(rows) if r.kind == "holonomic")
    names, invariants = invariant_columns(d)
    return Outputs(
        mass_matrix=mass,
        forcing=tuple(d.forcing),
        constraint_matrix=tuple(d.constraint_matrix),
        constraint_bias=tuple(d.constraint_bias),
        constraint_velocity=velocity,
        constraint_position=tuple(rows[j].expr for j in holonomic),
        invariants=invariants,
        invariant_names=names,
        holonomic_rows=holonomic,
    )


def invariant_columns(d: Derivation) -> tuple[tuple[str, ...], tuple]:
    """The CSV invariant columns with an expression, in CSV order: energy, jacobi, p_<q>."""
    names, exprs = ["energy"], [d.energy]
    if d.jacobi_integral is not None:
        names.append("jacobi")
        exprs.append(d.jacobi_integral)
    momenta = {c.name: c.expr for c in d.conserved if c.kind == "momentum"}
    for q in d.ignorable:
        names.append(f"p_{q.name}")
        exprs.append(momenta[f"p_{q.name}"])
    return tuple(names), tuple(exprs)


@dataclass(frozen=True)
class Reduced:
    """The result of one CSE over all groups: temporaries in dependency order and the
    reduced expressions of every group."""

    temporaries: tuple[tuple[sp.Symbol, sp.Expr], ...]
    groups: dict

    def block(self, names, exclude=frozenset()) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """The temporaries (in order) that the groups `names` need, minus `exclude`."""
        needed = set()
        for name in names:
            for expr in self.groups[name]:
                needed |= expr.free_symbols
        chosen = []
        for symbol, value in reversed(self.temporaries):
            if symbol in needed:
                chosen.append((symbol, value))
                needed |= value.free_symbols
        return tuple(pair for pair in reversed(chosen) if pair[0] not in exclude)

    def operation_count(self, names) -> int:
        """Operations (sympy.count_ops) to evaluate the groups `names`, temporaries included."""
        temps = self.block(names)
        exprs = [value for _, value in temps] + [e for name in names for e in self.groups[name]]
        return int(sum(sp.count_ops(e) for e in exprs))


def eliminate(outputs: Outputs, optimizations=CSE_OPTIMIZATIONS) -> Reduced:
    """ONE `sympy.cse` over every group of `outputs`."""
    groups = outputs.groups()
    flat = [sp.sympify(e) for name in GROUPS for e in groups[name]]
    temporaries, reduced = sp.cse(flat, symbols=sp.numbered_symbols("x", cls=sp.Dummy),
                                  optimizations=optimizations, order="canonical")
    result, start = {}, 0
    for name in GROUPS:
        size = len(groups[name])
        result[name] = tuple(reduced[start:start + size])
        start += size
    return Reduced(tuple(temporaries), result)


def slots(d: Derivation, reduced: Reduced) -> dict:
    """symbol -> code: t, y[i] for q and q', p[j] for parameters, x<k> for temporaries."""
    model = d.model
    table = {model.t: "t"}
    for i, symbol in enumerate(model.q + model.qd):
        table[symbol] = f"y[{i}]"
    for j, symbol in enumerate(model.parameter_symbols):
        table[symbol] = f"p[{j}]"
    for k, (symbol, _) in enumerate(reduced.temporaries):
        table[symbol] = f"x{k}"
    return table


def check_slots(exprs, table: dict) -> None:
    """Raise EmitError when an expression has a symbol that has no slot."""
    missing = set()
    for expr in exprs:
        missing |= {s for s in sp.sympify(expr).free_symbols if s not in table}
    if missing:
        names = ", ".join(sorted(str(s) for s in missing))
        raise EmitError(f"cannot generate code: no array slot for symbol(s) {names} "
                        "(only t, coordinates, velocities and parameters may appear)")


class SlotPrinter:
    """Mixin for a sympy code printer: symbols print as their slot, strictly.

    A subclass sets `sqrt_function` and `power_format` and lists this mixin first.
    """

    sqrt_function = "sqrt"
    power_format = "{base}**{exp}"

    def __init__(self, table: dict, settings: dict | None = None):
        super().__init__({"strict": True, **(settings or {})})
        self.slots = table

    def code(self, expr) -> str:
        try:
            return self._print(sp.sympify(expr))
        except PrintMethodNotImplementedError as exc:
            raise EmitError(f"cannot generate code for {expr}: {exc}") from exc

    def _print_Symbol(self, expr):
        try:
            return self.slots[expr]
        except KeyError:
            raise EmitError(f"cannot generate code: no array slot for symbol {expr}") from None

    _print_Dummy = _print_Symbol

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_NumberSymbol(self, expr):
        return str(sp.Float(expr.evalf(CONSTANT_DIGITS), CONSTANT_DIGITS))

    _print_Pi = _print_Exp1 = _print_EulerGamma = _print_GoldenRatio = _print_NumberSymbol
    _print_Catalan = _print_TribonacciConstant = _print_NumberSymbol

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.base, expr.exp
        if exp.is_Integer and 2 <= abs(int(exp)) <= MAX_PRODUCT_POWER:
            factor = self._power_operand(base)
            product = "*".join([factor] * abs(int(exp)))
            return f"({product})" if exp > 0 else f"(1.0/({product}))"
        if exp == -1:
            return f"(1.0/{self._power_operand(base)})"
        if exp == sp.S.Half:
            return f"{self.sqrt_name()}({self._print(base)})"
        if exp == -sp.S.Half:
            return f"(1.0/{self.sqrt_name()}({self._print(base)}))"
        return self.power_format.format(
            base=self._power_operand(base), exp=self._power_operand(exp))

    def sqrt_name(self) -> str:
        return self.sqrt_function

    def _power_operand(self, expr) -> str:
        """`expr` printed as an operand of * or pow: bare when it is a symbol, a
        non-negative number or a function call; parenthesised otherwise."""
        text = self._print(expr)
        bare = (expr.is_Symbol or isinstance(expr, sp.Function) or isinstance(expr, sp.NumberSymbol)
                or ((expr.is_Integer or expr.is_Float) and expr.is_nonnegative))
        return text if bare else f"({text})"


@dataclass(frozen=True)
class Interface:
    """What a generated file says about itself, as plain values (names in spec order)."""

    name: str
    spec_file: str                       # file name only: the bytes do not depend on the cwd
    version: str
    description: str
    coordinates: tuple[str, ...]
    state: tuple[str, ...]
    parameters: tuple[tuple[str, float], ...]
    multipliers: tuple[str, ...]
    invariants: tuple[str, ...]          # CSV invariant columns, constraint_residual included
    initial: tuple[float, ...]           # full state, made consistent with the constraints
    initial_notes: tuple[str, ...]
    settings: tuple[tuple[str, object], ...]
    baumgarte: tuple[float, float]


def interface(d: Derivation, outputs: Outputs) -> Interface:
    from lagcli import __version__
    from lagcli.simulate.options import DEFAULT_BAUMGARTE

    model = d.model
    s = model.settings
    initial, notes = consistent_initial_state(d)
    columns = outputs.invariant_names + (("constraint_residual",) if d.constraints else ())
    return Interface(
        name=model.name,
        spec_file=comment_safe(PurePath(model.source).name),
        version=__version__,
        description=comment_safe(" ".join(str(model.description or "").split())),
        coordinates=tuple(s.name for s in model.q),
        state=tuple(s.name for s in model.q + model.qd),
        parameters=tuple((p.symbol.name, float(p.value)) for p in model.parameters),
        multipliers=tuple(m.name for m in d.multipliers),
        invariants=columns,
        initial=initial,
        initial_notes=tuple(comment_safe(n) for n in notes),
        settings=(("t_end", float(s.t_end)), ("dt", float(s.dt)), ("method", s.method),
                  ("rtol", float(s.rtol)), ("atol", float(s.atol))),
        baumgarte=tuple(float(v) for v in DEFAULT_BAUMGARTE),
    )


def consistent_initial_state(d: Derivation) -> tuple[tuple[float, ...], tuple[str, ...]]:
    """The spec's `initial:` state (missing values 0), with dependent coordinates and
    velocities solved for as `simulate` does; as given when that is impossible."""
    from lagcli.errors import UsageError
    from lagcli.simulate.initial import initial_state

    model = d.model
    given = dict(model.initial)
    try:
        start = initial_state(d, given, {p.symbol.name: p.value for p in model.parameters})
    except UsageError:
        names = [s.name for s in model.q + model.qd]
        return tuple(float(given.get(n, 0.0)) for n in names), (
            "initial state: inconsistent with the constraints; used as given",)
    return tuple(float(v) for v in start.values), tuple(start.notes)


def comment_safe(text: str) -> str:
    """One line that cannot end a C comment or a Python string, nor splice C lines
    (no backslash, no trigraph)."""
    text = " ".join(str(text).split()).replace("*/", "* /").replace("\\", "/")
    return text.replace("??", "? ?").replace('"' * 3, "'" * 3)


@dataclass(frozen=True)
class Block:
    """One function body, printed: temporaries (name, code) in order, then the printed
    expressions of each group; `negated[name]` holds the printed negatives."""

    symbols: frozenset                   # the temporaries computed here
    temporaries: tuple[tuple[str, str], ...]
    values: dict
    negated: dict


def print_block(reduced: Reduced, printer: SlotPrinter, names, exclude: Block | None = None,
                negated=()) -> Block:
    """Print the groups `names` and the temporaries they need (minus those of `exclude`)."""
    skip = exclude.symbols if exclude is not None else frozenset()
    temps = reduced.block(names, skip)
    check_slots([v for _, v in temps] + [e for name in names for e in reduced.groups[name]],
                printer.slots)
    return Block(
        symbols=frozenset(s for s, _ in temps),
        temporaries=tuple((printer.slots[s], printer.code(v)) for s, v in temps),
        values={name: tuple(printer.code(e) for e in reduced.groups[name]) for name in names},
        negated={name: tuple(printer.code(-e) for e in reduced.groups[name]) for name in negated},
    )
