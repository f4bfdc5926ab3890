"""Physical validation of a model and its derivation: what a spec may not mean.

A spec can be well formed and still describe no real machine. Checked at the
parameters' default values (every command reads the spec, so every command checks):

- masses are positive (negative: an error; zero: a warning);
- a spatial inertia tensor is symmetric and positive semi-definite (errors: the
  report, the code and the physics would disagree), and its principal moments obey
  the triangle inequality I1 <= I2 + I3 (a warning: the equations are still
  consistent); a planar moment is >= 0;
- the mass matrix, restricted to the motions the constraints allow, is regular:
  singular everywhere (a coordinate that carries no inertia) is an error naming the
  coordinate; singular only at the initial state (a gimbal lock, a pole) is a warning;
- the spec's expressions are finite at the initial state (a warning: derive and
  generate are still right, only a simulation from there would fail).

Warnings go through `lagcli.errors.warn_spec`, errors are collected into one `SpecError`.
"""
from __future__ import annotations

import math
import operator
import random
import sys

import sympy as sp
from sympy.matrices.immutable import ImmutableRepMatrix

from lagcli.model.constants import ConstantError, value_at
from lagcli.errors import Loc, Problem, SpecError, warn_spec
from lagcli.model.model_types import Model

TOLERANCE = 1e-9          # relative: an eigenvalue or a moment this far below zero is still zero
SINGULAR = 1e-10          # smallest / largest singular value below this: singular
RANDOM_STATES = 3         # seeded states that decide "singular everywhere"
SEED = 20240611
SMALL_MATRIX = 150        # mass matrices up to this size are told regular without importing numpy


def check_model(model: Model) -> None:
    """Raise `SpecError` for impossible masses and inertias; warn about suspicious ones
    and about expressions that are not finite at the initial state."""
    errors: list[Problem] = []
    values = parameter_values(model)
    memo = _memo_at(values)       # once: finding it compares the values (O(n) for each of n masses)
    for item in (*model.particles, *model.bodies):
        errors += _mass_problems(item, values, memo=memo)
    for body in model.bodies:
        errors += _inertia_problems(body, values, model.dimension)
    if errors:
        raise SpecError(errors)
    for problem in _not_finite_at_start(model, values):
        warn_spec(problem)


def problems_at(derivation, parameters: dict[str, float]) -> list[Problem]:
    """What physical validation says of the spec at other parameter values (`--set`): the
    masses and inertias, and a mass matrix singular at the initial state there (a run could
    not start). Only errors; [] when the values are fine."""
    model = derivation.model
    values = {**parameter_values(model), **{p.symbol: float(parameters[p.symbol.name])
                                            for p in model.parameters if p.symbol.name in parameters}}
    memo = _memo_at(values)
    problems = [p for item in (*model.particles, *model.bodies)
                for p in _mass_problems(item, values, quiet=True, memo=memo)]
    problems += [p for body in model.bodies for p in _inertia_problems(body, values, model.dimension)]
    if problems:
        return problems
    infinite = _not_finite_mass_matrix(derivation, {**values, **initial_values(model)})
    if infinite is not None:
        return [infinite]
    singular = _singular_directions(derivation, {**values, **initial_values(model)})
    if singular:
        names = ", ".join(f"'{name}'" for name in singular)
        where = model.loc(f"coordinates[{[q.name for q in model.q].index(singular[0])}]")
        problems.append(Problem(where, f"the mass matrix is singular at the initial state (along {names}): "
                                "nothing with mass or a moment of inertia moves when it changes",
                                "give the masses and moments of inertia positive values"))
    return problems


def check_mass_matrix(derivation) -> None:
    """Raise `SpecError` when the mass matrix (on the constraints' null space) is singular
    at every state tried; warn when it is singular at the initial state only."""
    model = derivation.model
    start = {**parameter_values(model), **initial_values(model)}
    infinite = _not_finite_mass_matrix(derivation, start)
    if infinite is not None:
        if not _not_finite_at_start(model, parameter_values(model)):   # else check_model said why
            warn_spec(infinite)
        return
    singular = _singular_directions(derivation, start)
    if not singular:
        return
    rng = random.Random(SEED)
    everywhere = all(_singular_directions(derivation, _random_state(model, rng)) for _ in range(RANDOM_STATES))
    names = ", ".join(f"'{name}'" for name in singular)
    where = model.loc(f"coordinates[{[q.name for q in model.q].index(singular[0])}]")
    if everywhere:
        raise SpecError(Problem(where, f"the mass matrix is singular: {names} carries no inertia "
                                "(nothing with mass or a moment of inertia moves when it changes)",
                                "give the moving particle a mass or the body a moment of inertia about "
                                "that axis, or remove the coordinate"))
    warn_spec(Problem(where, f"the mass matrix is singular at the initial state (along {names}); "
                      "a simulation cannot start there", "start from another state (initial: or --init)"))


# --- values -----------------------------------------------------------------------------

def parameter_values(model: Model) -> dict:
    """The parameters' and inputs' default values (inputs are held there by `simulate`)."""
    return {p.symbol: float(p.value) for p in (*model.parameters, *model.inputs)}


def initial_values(model: Model) -> dict:
    """t = 0 and the spec's `initial:` state (a value not given is 0)."""
    values = {model.t: 0.0}
    for symbol in (*model.q, *model.qd):
        values[symbol] = float(model.initial.get(symbol.name, 0.0))
    values.update({a: 0.0 for a in model.qdd})
    return values


def _random_state(model: Model, rng: random.Random) -> dict:
    values = parameter_values(model)
    for symbol in (model.t, *model.q, *model.qd):
        values[symbol] = rng.uniform(-1.0, 1.0)
    return values


def _real(expr: sp.Expr, values: dict, memo: dict | None = None) -> float | None:
    """`expr` at `values` as a finite real; None when it is not one there. Evaluated in
    double precision node by node (`constants.value_at`): a tower like exp(exp(exp(x)))
    overflows instead of sending mpmath after millions of digits. `memo`: `_memo_at(values)`
    when the caller has it (finding it compares the values)."""
    try:
        return value_at(sp.sympify(expr), values, _memo_at(values) if memo is None else memo)
    except (ConstantError, TypeError, ValueError, ArithmeticError):   # complex, undefined, overflow
        return None


_LAST_MEMO: list = [None, {}]     # (the values, the value of every subexpression there)


def _memo_at(values: dict) -> dict:
    """The values of the subexpressions evaluated at `values` so far: the checks evaluate
    the mass matrix's entries more than once at the initial state, and its entries share
    their parts (a chain's dot products). One point is remembered, by its contents."""
    key = tuple(values.items())
    if _LAST_MEMO[0] != key:
        _LAST_MEMO[:] = [key, {}]
    return _LAST_MEMO[1]


_LAST_VALUES: list = [None, None, {}]     # (a matrix, the values, `_nonzero_values` of it there)


def _nonzero_values(matrix, values: dict) -> dict:
    """(i, j) -> the nonzero entry M_ij at `values` (None: not a finite real there). The last
    matrix's are remembered (kept alive here, so known by identity) at one point, by its
    contents: `check_mass_matrix` asks for M's at the initial state twice (is it finite,
    is it clearly regular), which looked up each of its n^2 entries again."""
    point = tuple(values.items())
    if _LAST_VALUES[0] is matrix and _LAST_VALUES[1] == point:
        return dict(_LAST_VALUES[2])
    memo = _memo_at(values)
    found = {key: _real(expr, values, memo) for key, expr in matrix.todok().items()}
    if isinstance(matrix, ImmutableRepMatrix):      # its entries stay what they are
        _LAST_VALUES[:] = [matrix, point, found]
    return dict(found)


def _matrix(matrix, values: dict) -> np.ndarray | None:
    import numpy as np    # here, not at the top: most derives never need it (`_clearly_regular`)

    memo = _memo_at(values)
    entries = [_real(e, values, memo) for e in matrix]
    if any(e is None for e in entries):
        return None
    return np.array(entries, dtype=float).reshape(matrix.shape)


# --- masses and inertias ----------------------------------------------------------------

def _mass_problems(item, values: dict, quiet: bool = False, memo: dict | None = None) -> list[Problem]:
    """Errors for a mass that is not finite or negative; a zero mass is a warning (not
    `quiet`: at other parameter values only what it does to the mass matrix counts).
    `memo`: `_memo_at(values)`, when the caller has it."""
    where = item.loc.child("mass") if item.loc else Loc("", path="mass")
    mass = _real(item.mass, values, memo)
    if mass is None:
        return [Problem(where, f"the mass of '{item.name}' is not a finite real number at the "
                        "parameters' values", "check the parameters it uses")]
    if mass < 0:
        return [Problem(where, f"the mass of '{item.name}' is negative ({mass:g})", "a mass is positive")]
    if mass == 0 and not quiet:
        warn_spec(Problem(where, f"the mass of '{item.name}' is zero: it adds nothing to T or V",
                          "give it a positive mass, or leave it out"))
    return []


def _inertia_problems(body, values: dict, dimension: int) -> list[Problem]:
    where = body.loc.child("inertia") if body.loc else Loc("", path="inertia")
    tensor = _matrix(body.inertia, values)
    if tensor is None:
        return [Problem(where, f"the inertia of '{body.name}' is not finite and real at the "
                        "parameters' values", "check the parameters it uses")]
    if dimension == 2:
        moment = tensor[2, 2]
        return [] if moment >= 0 else [Problem(where, f"the moment of inertia of '{body.name}' is "
                                               f"negative ({moment:g})", "a moment of inertia is >= 0")]
    return _tensor_problems(body.name, tensor, where)


def _tensor_problems(name: str, tensor: np.ndarray, where: Loc) -> list[Problem]:
    import numpy as np

    scale = max(1.0, float(np.abs(tensor).max()))
    asymmetric = [(i, j) for i in range(3) for j in range(i + 1, 3)
                  if abs(tensor[i, j] - tensor[j, i]) > TOLERANCE * scale]
    if asymmetric:
        i, j = asymmetric[0]
        axes = "xyz"
        return [Problem(where, f"the inertia tensor of '{name}' is not symmetric: I{axes[i]}{axes[j]} = "
                        f"{tensor[i, j]:g} but I{axes[j]}{axes[i]} = {tensor[j, i]:g}",
                        "an inertia tensor is symmetric: give 3 principal moments, the 6 values "
                        "[Ixx, Iyy, Izz, Ixy, Iyz, Izx], or a symmetric 3x3 list")]
    moments = np.linalg.eigvalsh(tensor)
    if moments[0] < -TOLERANCE * scale:
        return [Problem(where, f"the inertia tensor of '{name}' is not positive semi-definite "
                        f"(principal moments {_listing(moments)})",
                        "every principal moment of inertia of a real body is >= 0")]
    largest, others = moments[2], moments[0] + moments[1]
    if largest > others + TOLERANCE * scale:   # the equations stay consistent: a warning
        warn_spec(Problem(where, f"the inertia tensor of '{name}' is not that of a real body: the principal "
                          f"moments {_listing(moments)} break the triangle inequality "
                          f"({largest:g} > {moments[0]:g} + {moments[1]:g})",
                          "for a real body each principal moment is at most the sum of the other two"))
    return []


def _listing(values) -> str:
    return ", ".join(f"{v:.6g}" for v in values)


# --- the initial state ------------------------------------------------------------------

def _not_finite_at_start(model: Model, values: dict) -> list[Problem]:
    """The spec items with an expression that is not finite at the initial state."""
    state = {**values, **initial_values(model)}
    source = model.source
    items = [(f"position of '{p.name}'", p.position, p.loc) for p in model.particles]
    items += [(f"position of '{b.name}'", b.position, b.loc) for b in model.bodies]
    items += [(f"orientation of '{b.name}'", [a for _, a in b.rotations], b.loc) for b in model.bodies]
    items += [("force", [*(f.force if f.force is not None else []), *(f.torque if f.torque is not None else [])],
               f.loc) for f in model.forces]
    items += [("constraint", [c.expr], c.loc) for c in model.constraints]
    items += [("potential", [model.potential], model.loc("potential")),
              ("kinetic", [model.kinetic], model.loc("kinetic")),
              ("dissipation", [model.dissipation], model.loc("dissipation"))]
    items += [(f"generalized force on '{q.name}'", [Q], model.loc(f"generalized_forces.{q.name}"))
              for q, Q in zip(model.q, model.generalized_forces)]
    problems, memo = [], _memo_at(state)
    for what, exprs, loc in items:
        if any(_real(e, state, memo) is None for e in exprs):
            problems.append(Problem(loc or Loc(source), f"the {what} cannot be evaluated at the initial "
                                    "state (not a finite number there)",
                                    "a simulation cannot start there: choose another initial: state, "
                                    "or check for a division by zero or a log/sqrt of a negative number"))
    return problems


# --- the mass matrix --------------------------------------------------------------------

def _singular_directions(derivation, values: dict) -> list[str]:
    """The coordinates along which the mass matrix, restricted to the velocities the
    constraints allow, has no inertia at `values`; [] when it is regular there (or
    cannot be evaluated: that is reported elsewhere)."""
    if not derivation.constraints and _clearly_regular(derivation.mass_matrix, values):
        return []
    import numpy as np

    M = _matrix(derivation.mass_matrix, values)
    if M is None:
        return []
    A = _matrix(derivation.constraint_matrix, values) if derivation.constraints else np.zeros((0, len(M)))
    if A is None or not (np.all(np.isfinite(M)) and np.all(np.isfinite(A))):
        return []
    allowed = _null_space(A) if A.size else np.eye(len(M))
    if allowed.shape[1] == 0:
        return []
    reduced = allowed.T @ M @ allowed
    s, vectors = np.linalg.eigh((reduced + reduced.T) / 2)
    scale = max(float(np.abs(M).max()), 1e-300)
    if s[0] > SINGULAR * scale:
        return []
    direction = allowed @ vectors[:, 0]
    big = np.abs(direction) > 0.1 * np.abs(direction).max()
    return [q.name for q, b in zip(derivation.model.q, big) if b]


def _not_finite_mass_matrix(derivation, values: dict) -> Problem | None:
    """The problem of a mass matrix with an entry that is not a finite double at `values`
    (parameters of 1e299 multiplied: m s^2 = 1e897), located at its row's coordinate."""
    model = derivation.model
    rows = [i for (i, _), value in _nonzero_values(derivation.mass_matrix, values).items() if value is None]
    if not rows:
        return None
    i = min(rows)
    return Problem(model.loc(f"coordinates[{i}]"), f"the mass matrix's row of {model.q[i].name} is not a finite "
                   "number at the initial state (an entry is infinite or undefined there, e.g. products of "
                   "parameters beyond 1e300)", "a simulation cannot start there: choose units that keep "
                   "the parameters' products within the double range, or another initial state")


def _clearly_regular(matrix, values: dict) -> bool:
    """True when the symmetric `matrix` at `values` is positive definite with its smallest
    eigenvalue above SINGULAR times its largest entry: M - SINGULAR*scale*I has a Cholesky
    factor. Only the nonzero entries are evaluated (a system of many uncoupled coordinates
    has n of n^2). Up to SMALL_MATRIX rows factored in plain Python floats (numpy's import
    was a tenth of a 40-link `derive`, and the only use of numpy there), beyond with numpy
    (the factorization is n^3/6 multiplications). False also when it cannot tell (then
    numpy's eigenvalues decide)."""
    entries = _nonzero_values(matrix, values)
    if any(entry is None for entry in entries.values()):
        return False
    n = matrix.shape[0]
    scale = max((abs(e) for e in entries.values()), default=0.0)
    if scale == 0:
        return False
    shifted = [[0.0] * n for _ in range(n)]
    for (i, j), entry in entries.items():
        shifted[i][j] = entry
    for k in range(n):
        shifted[k][k] -= SINGULAR * scale
    if n <= SMALL_MATRIX:
        return _has_cholesky_factor(shifted)
    import numpy as np

    try:
        np.linalg.cholesky(np.array(shifted))
    except ValueError:     # numpy's LinAlgError is a ValueError
        return False
    return True


def _has_cholesky_factor(a: list[list[float]]) -> bool:
    """The symmetric `a` = L L^T with every pivot of L at least the double's epsilon (as
    mpmath's `cholesky` requires), by the Cholesky-Banachiewicz rows."""
    n = len(a)
    L = [[0.0] * n for _ in range(n)]
    for j in range(n):
        row = L[j]
        pivot = a[j][j] - sum(x * x for x in row[:j])
        if not pivot >= sys.float_info.epsilon:       # also NaN
            return False
        row[j] = math.sqrt(pivot)
        for i in range(j + 1, n):
            L[i][j] = (a[i][j] - sum(map(operator.mul, L[i][:j], row[:j]))) / row[j]
    return True


def _null_space(A: np.ndarray) -> np.ndarray:
    import numpy as np

    _, s, vt = np.linalg.svd(A)
    rank = int((s > SINGULAR * max(1.0, s.max(initial=0.0))).sum())
    return vt[rank:].T
