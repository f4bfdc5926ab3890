"""Command-line values of `simulate`: NAME=VALUE overrides and the run settings.

Everything here is checked before any integration starts, and a bad value is a
`UsageError` (exit status 2) naming the option.  VALUE is a number or a constant
expression of the spec language (`pi/4`, `2*sqrt(2)`); plain numbers are read
with `float` so that the warm C path never imports sympy, anything else goes
through the safe parser `lagcli.model.expr.parse_constant` (never `eval`).
"""
from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field

from lagcli.errors import LagcliError, UsageError
from lagcli.interface import DEFAULT_BAUMGARTE, METHODS, VARIATIONAL, RunSettings

HINT_CUTOFF = 0.5                       # difflib similarity for "did you mean": 'mm' -> 'm1'


@dataclass(frozen=True)
class Request:
    """What the user asked for; None means "the spec's value, else the default"."""

    spec: str
    t_end: float | None = None
    dt: float | None = None
    method: str | None = None
    rtol: float | None = None
    atol: float | None = None
    sets: tuple[str, ...] = ()          # raw "NAME=VALUE" items of --set
    inits: tuple[str, ...] = ()         # raw "NAME=VALUE" items of --init
    backend: str | None = None          # "python" | "c" | None (c when `cc` exists)
    baumgarte: tuple[float, float] | None = None
    inputs: tuple[str, ...] = ()        # raw "NAME=EXPR" items of --input (input laws)
    max_steps: int | None = None        # the step budget (None: `default_max_steps`)
    steps_per_row: int | None = None    # --method variational: steps per output interval


def resolve_settings(request: Request, spec_settings: dict) -> RunSettings:
    """Command line over the spec's `simulate:` block (`spec_settings`, already defaulted)."""
    def pick(key):
        value = getattr(request, key)
        return spec_settings[key] if value is None else value

    alpha, beta = request.baumgarte or DEFAULT_BAUMGARTE
    if request.max_steps is not None and not 1 <= request.max_steps <= 10**15:
        raise UsageError(f"--max-steps: must be a whole number of steps from 1 to 1e15, got {request.max_steps}")
    steps = 1 if request.steps_per_row is None else request.steps_per_row
    s = RunSettings(pick("t_end"), pick("dt"), pick("method"), pick("rtol"), pick("atol"),
                    float(alpha), float(beta), request.max_steps or 0, steps)
    if s.method not in METHODS:
        raise UsageError(f"--method: unknown integration method {s.method!r}"
                         + _hint(s.method, METHODS, "methods"))
    if request.steps_per_row is not None and s.method != VARIATIONAL:
        raise UsageError(f"--steps-per-row: only --method {VARIATIONAL} takes fixed steps "
                         f"(--method {s.method} chooses its own)")
    if not (isinstance(steps, int) and 1 <= steps <= 10**9):
        raise UsageError(f"--steps-per-row: must be a whole number from 1 to 1e9, got {steps!r}")
    for key, low_ok in (("t_end", True), ("dt", False), ("rtol", False), ("atol", False)):
        value = getattr(s, key)
        if not math.isfinite(value) or value < 0 or (value == 0 and not low_ok):
            sign = "non-negative" if low_ok else "positive"
            raise UsageError(f"--{key.replace('_', '-')}: must be a {sign} finite number, got {value!r}")
    if not (math.isfinite(s.alpha) and math.isfinite(s.beta)):
        raise UsageError("--baumgarte: ALPHA and BETA must be finite numbers")
    if s.t_end / s.dt > 1e8:
        raise UsageError(f"--dt: {s.dt!r} gives more than 1e8 output rows up to t_end = {s.t_end!r}")
    return s


def parse_assignments(items: tuple[str, ...], option: str, allowed: list[str],
                      what: str, plural: str, parse=None) -> dict:
    """{"m=2", "x=pi/4"} -> {"m": 2.0, "x": 0.785...}; names must be in `allowed`.
    `parse(text, where)` reads each VALUE (default `parse_value`: a number)."""
    parse = parse or parse_value
    values: dict = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise UsageError(f"{option} {item!r}: expected NAME=VALUE")
        if name not in allowed:
            raise UsageError(f"{option} {item!r}: unknown {what} {name!r}"
                             + _hint(name, allowed, plural))
        values[name] = parse(text, f"{option} {name}")
    return values


@dataclass(frozen=True)
class Overrides:
    """What `--set` and `--init` (or the API's dicts) change for a run."""

    values: dict = field(default_factory=dict)     # parameters and inputs: {name: value}
    initial: dict = field(default_factory=dict)    # coordinates and velocities: {name: value}


SET_WHAT = ("--set", "parameter or input", "parameters and inputs")
INIT_WHAT = ("--init", "coordinate or velocity", "coordinates and velocities")


def parse_overrides(layout, sets=(), inits=()) -> Overrides:
    """THE parser of `--set NAME=VALUE` (a parameter or an input) and `--init NAME=VALUE`
    (a coordinate or a velocity) of every command that runs or analyses a system:
    simulate, sweep, animate, linearize, equilibria. Names are checked against
    `layout` (a lagcli.interface.Layout); a name given to the other option is told so."""
    values = _assignments(tuple(sets), SET_WHAT, [*layout.parameter_names, *layout.input_names],
                          layout.state_names, "--init")
    initial = _assignments(tuple(inits), INIT_WHAT, list(layout.state_names),
                           (*layout.parameter_names, *layout.input_names), "--set")
    return Overrides(values, initial)


def _assignments(items, what, allowed, other_names, other_option) -> dict:
    option, name_of, plural = what
    for item in items:
        name = item.partition("=")[0].strip()
        if name in other_names and "=" in item:
            raise UsageError(f"{option} {item!r}: {name!r} is not a {name_of}\n"
                             f"  hint: give it with {other_option} {item.strip()}")
    return parse_assignments(items, option, allowed, name_of, plural)


def parse_range(item: str, option: str, smallest: int = 1, largest: int | None = None,
                example: str = "theta1=-3:3:101") -> tuple[str, float, float, int]:
    """`NAME=START:STOP:COUNT` (`--grid`, `--sweep`) -> (name, start, stop, count), with
    START and STOP numbers or constant expressions and smallest <= COUNT <= largest."""
    name, sep, rest = item.partition("=")
    parts = rest.split(":")
    if not sep or not name.strip() or len(parts) != 3:
        raise UsageError(f"{option} {item!r}: expected NAME=START:STOP:COUNT, e.g. {example}")
    name = name.strip()
    start, stop = (parse_value(p, f"{option} {name}") for p in parts[:2])
    try:
        count = int(parts[2])
    except ValueError:
        count = smallest - 1
    if count < smallest or (largest is not None and count > largest):
        bounds = f"from {smallest} to {largest}" if largest is not None else f">= {smallest}"
        raise UsageError(f"{option} {item!r}: COUNT must be a whole number {bounds}, got {parts[2]!r}")
    return name, start, stop, count


def parse_value(text: str, where: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = None
    if value is None:
        from lagcli.errors import Loc   # the safe parser imports sympy: only for expressions
        from lagcli.model.expr import parse_constant
        try:
            value = parse_constant(text.strip(), Loc("<command line>"))
        except LagcliError as exc:
            reason = str(exc).splitlines()[0].removeprefix("<command line>: ")
            raise UsageError(f"{where}: {text!r} is not a number or a constant expression ({reason})\n"
                             "  hint: VALUE may use numbers, pi, + - * / ** and functions like "
                             "sqrt, sin, exp") from None
    if not math.isfinite(value):
        raise UsageError(f"{where}: {text!r} is not a finite number")
    return value


def _hint(name: str, allowed, plural: str) -> str:
    guess = closest_name(name, allowed)
    listing = ", ".join(allowed) if allowed else "(none)"
    did_you_mean = f"did you mean {guess!r}? " if guess else ""
    return f"\n  hint: {did_you_mean}{plural} are: {listing}"


def closest_name(name: str, allowed) -> str | None:
    """The allowed name `name` was probably meant to be: the same letters in another case
    (`K` for `k`), else the closest by difflib, letter case ignored (`MM` for `m`)."""
    by_lower = {}
    for choice in allowed:
        by_lower.setdefault(choice.lower(), choice)
    if name.lower() in by_lower:
        return by_lower[name.lower()]
    guess = difflib.get_close_matches(name.lower(), list(by_lower), n=1, cutoff=HINT_CUTOFF)
    return by_lower[guess[0]] if guess else None
