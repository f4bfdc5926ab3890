"""Consistent initial states of constrained systems.

The state starts as the spec's `initial:` values overridden by `--init`
(anything not given is 0).  For constrained systems it must satisfy, at t0,

    phi_j(q, t0) = 0                 (holonomic rows)
    sum_k a_jk q'_k + d_j = 0        (every row; holonomic ones differentiated)

to 1e-8.  When it does not, the quantities the user did *not* give are solved for:

- dependent coordinates: scipy's trust-region least squares (`least_squares`,
  method "trf": any number of unknowns) on the holonomic rows, first from the
  given values (0 for missing ones), then
  from deterministic nearby starts (the unknowns shifted down, then up, by
  0.1 (1 + |q|), then a few seeded random shifts) — so a Cartesian pendulum with
  only x given hangs down (y < 0) rather than standing up;
- dependent velocities: the least-norm correction that makes A q' + d = 0, over
  the velocities not given (which start from 0).

When every coordinate (velocity) has a value, the ones in `soft` — the spec's
`initial:` values that `--init` did not override — are solved for instead,
starting from their given values: `--init x=0.5` on a Cartesian pendulum moves y
back onto the rod and projects the spec's (x', y') onto the rod's tangent (the
smallest change to the given velocities, not a reset to 0); and after `--set l=2`,
which leaves every value of the spec's state given, its `initial:` values are
moved onto the new constraints the same way.

What was solved, from which given values and with which changed parameters, is
reported in `notes` (shown on stderr).  When nothing may be solved for, or the
solve fails, a `UsageError` (exit status 2) names each violated constraint and its
residual, and its hint names what the user gave (`Sources`).
"""
from __future__ import annotations

from dataclasses import dataclass

from lagcli.errors import UsageError


@dataclass(frozen=True)
class InitialState:
    values: tuple[float, ...]          # [q..., q'...]
    notes: tuple[str, ...] = ()        # "solved for dependent coordinates: y = -0.8 ..."


@dataclass(frozen=True)
class Sources:
    """How the caller names the origins of values, for notes and hints (the command
    line's by default; the Python API passes its own argument names)."""

    override: str = "--init"           # values given for this run
    spec: str = "initial:"             # the spec's `initial:` values
    parameter: str = "--set"           # parameter values changed for this run


def initial_state(d, given: dict[str, float], params: dict[str, float], t0: float = 0.0,
                  soft=(), sources: Sources = Sources()) -> InitialState:
    """The state [q, q'] from `given` (name -> value), made consistent with the constraints.

    `d` is the Derivation, `params` every parameter's value by name, `soft` the given
    names that may still be solved for when nothing else can be (the spec's `initial:`
    values the caller did not override).
    """
    model = d.model
    values = tuple(float(given.get(s.name, 0.0)) for s in model.q + model.qd)
    if not d.constraints:
        return InitialState(values)
    from lagcli.analysis.constraint_solve import consistent_state   # numpy and scipy: only here

    return InitialState(*consistent_state(d, given, params, t0, Origin(d, given, params, soft, sources)))


class Origin:
    """Where each value came from: `sources.override` (given, not soft), `sources.spec`
    (soft) and the parameters that differ from the spec's (`sources.parameter`)."""

    def __init__(self, d, given, params, soft, sources: Sources):
        self.sources = sources
        self.given, self.soft = set(given), set(soft)
        self.changed = [(p.symbol.name, params[p.symbol.name]) for p in d.model.parameters
                        if params[p.symbol.name] != p.value]

    def overridden(self) -> bool:
        """Whether the run changed anything of the spec's (values given for it, parameters)."""
        return bool(self.given - self.soft or self.changed)

    def source(self, name: str) -> str:
        return self.sources.spec if name in self.soft else self.sources.override

    def note(self, what: str, symbols, free, values) -> str:
        """'initial state: solved for dependent coordinates: y = -1.9 from x (initial:)
        with l = 2 (--set)'."""
        solved = ", ".join(f"{symbols[k]} = {values[k]:.12g}" for k in free)
        held = [s.name for k, s in enumerate(symbols) if k not in free and s.name in self.given]
        text = f"initial state: solved for dependent {what}: {solved}"
        if held:
            text += " from " + ", ".join(f"{n} ({self.source(n)})" for n in held)
        if any(symbols[k].name in self.soft for k in free):
            text += f", changing the spec's {self.sources.spec} values as little as possible"
        return text + self._with()

    def _with(self) -> str:
        if not self.changed:
            return ""
        values = ", ".join(f"{name} = {value:.12g}" for name, value in self.changed)
        return f", with {values} ({self.sources.parameter})"

    def hint(self) -> str:
        """Name what the user gave, and what to give instead."""
        overrides = sorted(self.given - self.soft)
        said = []
        if overrides:
            said.append(f"{self.sources.override} gave {', '.join(overrides)}")
        if self.changed:
            said.append(f"{self.sources.parameter} gave {', '.join(n for n, _ in self.changed)}")
        if not said:
            return (f"  hint: correct the spec's {self.sources.spec} values, or leave out the ones the rows "
                    "determine (they are solved for)")
        said = "; ".join(said) + "; "
        return (f"  hint: {said}give fewer coordinates/velocities with {self.sources.override} "
                "(the others are solved for), or a consistent state")


def spec_initial_state(d) -> tuple[InitialState, bool]:
    """The spec's own `initial:` state (missing values 0, default parameters) made
    consistent as `simulate` does, and True; when that is impossible, the state as
    given with a note saying so, and False. What generated code embeds as its
    default initial state (`lagcli.targets.about.interface`)."""
    model = d.model
    given = dict(model.initial)
    own = Sources(override=Sources.spec)   # every value given is the spec's: "(initial:)", never "(--init)"
    try:
        return initial_state(d, given, {p.symbol.name: p.value for p in model.parameters}, sources=own), True
    except UsageError:
        values = tuple(float(given.get(s.name, 0.0)) for s in model.q + model.qd)
        return InitialState(values, ("initial state: inconsistent with the constraints; used as given",)), False
