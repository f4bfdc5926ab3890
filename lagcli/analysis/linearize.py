"""Linearization about an operating point, on the constraint manifold.

The equations (docs/design.md) are

    R(q, q', q'', lambda, u) = M q'' - F - A^T lambda = 0        (n rows)
    S(q, q', q'')            = A q'' - b              = 0        (m rows, b = -(A' q' + d'))

with inputs u (the spec's `inputs:`, then parameters named by `--input NAME`). Differentiating at
the point, with K = [[M, -A^T], [A, 0]],

    K d[q''; lambda] = -(G_q dq + G_q' dq' + G_u du),     G_x = d[R; S]/dx at (q'', lambda) of the point,

gives the Jacobians of q'' = f(q, q', u) of the augmented equations. The
symbolic Jacobians are taken first (along the common subexpressions:
`jacobians.py`) and evaluated afterwards (no 0/0 at the point, the pitfall sympy's
Linearizer documents), and every solve is numeric.

On the manifold, with independent coordinates q_i (the rest solved from the
holonomic rows phi = 0) and independent speeds u_s = q'_s (the rest from
A q' + d = 0):

    dq  = P dq_i                   P[dep] = -phi_q,dep^-1 phi_q,ind
    dq' = N du_s + W dq            N[dep] = -A_dep^-1 A_ind,  W[dep] = -A_dep^-1 d(A q' + d)/dq

so that, with x = (q_i, u_s),

    A_lin = [[E_i W P,                  E_i N      ],      B_lin = [[0       ],
             [E_s (f_q + f_q' W) P,     E_s f_q' N ]]               [E_s f_u ]]

(E picks rows). The second-order form multiplies the speed rows by Kane's mass
matrix M_s = N^T M N:  M_s du' + C du + K dq_i = B_s du_in, C = G + D split into
its skew (gyroscopic) and symmetric parts.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from lagcli.analysis.jacobians import CompiledJacobians
from lagcli.analysis.operating_point import Partition, Point, choose_partition, describe, on_manifold
from lagcli.errors import UsageError


_SYMMETRY_TOL = 1e-10     # relative size below which a Jacobian's action on a direction is 0


class SingularPoint(UsageError):
    """The equations cannot be solved for q'' (and lambda) at the operating point."""


class CompiledSystem:
    """The derivation's matrices and their symbolic Jacobians, compiled once (sympy's
    lambdify with cse, of expressions lagcli built) and evaluated at points."""

    def __init__(self, d, inputs=()):
        model = d.model
        self.derivation = d
        self.n, self.m = len(model.q), len(d.constraints)
        self.inputs = input_symbols(model, inputs)
        self.holonomic = [j for j, row in enumerate(d.constraints) if row.kind == "holonomic"]
        lam = sp.Matrix(d.multipliers)
        qd, qdd = sp.Matrix(model.qd), sp.Matrix(model.qdd)
        M, F, A, b = (sp.Matrix(x) for x in (d.mass_matrix, d.forcing, d.constraint_matrix, d.constraint_bias))
        R = M * qdd - F - (A.T * lam if self.m else sp.zeros(self.n, 1))
        S = A * qdd - b
        RS = R.col_join(S) if self.m else R
        velocity = A * qd + sp.Matrix([row.d for row in d.constraints]) if self.m else sp.zeros(0, 1)
        phi = sp.Matrix([d.constraints[j].expr for j in self.holonomic])
        self.args = [model.t, *model.q, *model.qd, *model.qdd, *d.multipliers, *model.parameter_symbols,
                     *model.input_symbols]
        jacobians = {"G_q": ("RS", list(model.q)), "G_qd": ("RS", list(model.qd))}
        if self.inputs:
            jacobians["G_u"] = ("RS", list(self.inputs))
        if self.m:
            jacobians["V_q"] = ("velocity", list(model.q))
        self._core = CompiledJacobians(self.args, {"M": M, "F": F, "A": A, "b": b, "RS": RS,
                                                   "velocity": velocity}, jacobians)
        self._constraints = CompiledJacobians(self.args, {
            "phi": phi, "A": A, "d": sp.Matrix([row.d for row in d.constraints]) if self.m else sp.zeros(0, 1),
        }, {"phi_q": ("phi", list(model.q))})

    def _values(self, point: Point, qdd=None, lam=None) -> list[float]:
        model = self.derivation.model
        qdd = np.zeros(self.n) if qdd is None else qdd
        lam = np.zeros(self.m) if lam is None else lam
        return [point.t, *point.q, *point.qd, *qdd, *lam,
                *(point.parameters[p.symbol.name] for p in (*model.parameters, *model.inputs))]

    def mass_matrix(self, point: Point) -> np.ndarray:
        return self._core(self._values(point))["M"].reshape(self.n, self.n)

    # constraint pieces (for the operating point and the partition)
    def phi(self, point: Point) -> np.ndarray:
        return self._constraints(self._values(point))["phi"].reshape(-1)

    def holonomic_jacobian(self, point: Point) -> np.ndarray:
        return self._constraints(self._values(point))["phi_q"]

    def A(self, point: Point) -> np.ndarray:
        return self._constraints(self._values(point))["A"]

    def bias(self, point: Point) -> np.ndarray:
        """d(q, t) of the velocity constraints A q' + d = 0."""
        return self._constraints(self._values(point))["d"].reshape(-1)

    def generic_q_jacobian(self, point: Point) -> np.ndarray | None:
        """d[R; S; A q' + d; phi]/dq at a generic state (deterministic numbers in (0.2, 0.8)
        for t, q, q', q'', lambda; the point's parameters), None where not finite there."""
        model = self.derivation.model
        count = 1 + 3 * self.n + self.m
        generic = 0.2 + 0.6 * np.modf(np.arange(1, count + 1) * 0.6180339887498949)[0]
        values = [*generic, *(point.parameters[p.symbol.name] for p in (*model.parameters, *model.inputs))]
        with np.errstate(all="ignore"):
            core, constraints = self._core(values), self._constraints(values)
        stacked = np.vstack([core["G_q"], core.get("V_q", np.zeros((0, self.n))), constraints["phi_q"]])
        return stacked if np.all(np.isfinite(stacked)) else None

    def accelerations(self, point: Point) -> tuple[np.ndarray, np.ndarray, dict]:
        """(q'', lambda) at the point, and the Jacobians evaluated there."""
        first = self._core(self._values(point))
        K = _augmented(first["M"], first["A"])
        rhs = np.concatenate([first["F"].reshape(-1), first["b"].reshape(-1)])
        try:
            solution = np.linalg.solve(K, rhs)
        except np.linalg.LinAlgError:
            raise SingularPoint("the mass matrix (with the constraint rows) is singular at "
                                f"{describe(self.derivation, point)}\n"
                                "  hint: a coordinate singularity (e.g. theta = 0 of spherical angles) "
                                "or dependent constraints; choose another point") from None
        qdd, lam = solution[:self.n], solution[self.n:]
        second = self._core(self._values(point, qdd, lam))
        second.setdefault("G_u", np.zeros((self.n + self.m, 0)))
        second.setdefault("V_q", np.zeros((0, self.n)))
        return qdd, lam, second


def gyroscopic_part(C: np.ndarray) -> np.ndarray:
    """G = (C - C^T) / 2: the skew (gyroscopic) part of the velocity matrix C = G + D."""
    return (C - C.T) / 2


def damping_part(C: np.ndarray) -> np.ndarray:
    """D = (C + C^T) / 2: the symmetric (damping) part of C."""
    return (C + C.T) / 2


def input_symbols(model, parameters=()) -> tuple[sp.Symbol, ...]:
    """The inputs u of B: the spec's `inputs:` in spec order, then the parameters named
    by `--input` (a declared input named again is not repeated)."""
    params = {p.symbol.name: p.symbol for p in model.parameters}
    declared = {u.name for u in model.input_symbols}
    unknown = [name for name in parameters if name not in params and name not in declared]
    if unknown:
        from lagcli.run.options import _hint
        raise UsageError(f"--input {unknown[0]!r}: not an input or a parameter"
                         + _hint(unknown[0], [*declared, *params], "inputs and parameters"))
    extra = [params[name] for name in dict.fromkeys(parameters) if name not in declared]
    return (*model.input_symbols, *extra)


def _augmented(M: np.ndarray, A: np.ndarray) -> np.ndarray:
    m = A.shape[0]
    return np.block([[M, -A.T], [A, np.zeros((m, m))]]) if m else M


@dataclass(frozen=True)
class LinearModel:
    """dx' = A dx + B du about `point`, x = (independent coordinates, independent speeds)."""

    point: Point
    coordinates: tuple[str, ...]
    speeds: tuple[str, ...]
    inputs: tuple[str, ...]
    A: np.ndarray
    B: np.ndarray
    M: np.ndarray            # Kane's mass matrix of the independent speeds, N^T M N
    C: np.ndarray            # speeds x speeds
    K: np.ndarray            # speeds x independent coordinates
    B2: np.ndarray           # speeds x inputs (second-order form's input matrix)
    speed_rates: np.ndarray  # u_s' at the point: 0 at an equilibrium or steady motion
    dependent: tuple[str, ...]
    energy_conserved: bool   # the Jacobi integral h = T2 - T0 + V exists (derivation)
    coordinate_rates: np.ndarray = field(default_factory=lambda: np.zeros(0))   # q_i' at the point (empty: 0)
    invariant: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))    # `invariant_directions`
    generic_A: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))    # `generic_state_matrix`

    @property
    def states(self) -> tuple[str, ...]:
        return self.coordinates + self.speeds

    @property
    def gyroscopic(self) -> np.ndarray:
        return gyroscopic_part(self.C)

    @property
    def damping(self) -> np.ndarray:
        return damping_part(self.C)

    @property
    def square_stiffness(self) -> np.ndarray | None:
        """K's columns for the coordinates whose rates are the speeds (None when some speed
        is not the rate of an independent coordinate)."""
        names = [s.removesuffix("_dot") for s in self.speeds]
        if not all(name in self.coordinates for name in names):
            return None
        return self.K[:, [self.coordinates.index(name) for name in names]]


def linearize(system: CompiledSystem, point: Point, independent=()) -> LinearModel:
    """The linear model of `system` about `point` (dependent values solved for first)."""
    d = system.derivation
    names = ([s.name for s in d.model.q], [s.name for s in d.model.qd])
    partition = choose_partition(d, system, replace(point, q=point.start), independent)
    point = on_manifold(system, point, partition, names)
    qdd, lam, J = system.accelerations(point)
    K = _augmented(J["M"], J["A"])
    n = system.n
    f_q = -np.linalg.solve(K, J["G_q"])[:n]
    f_qd = -np.linalg.solve(K, J["G_qd"])[:n]
    f_u = -np.linalg.solve(K, J["G_u"])[:n] if system.inputs else np.zeros((n, 0))
    P, N, W = _tangent(system, point, partition, J)
    ci, si = list(partition.coordinates), list(partition.speeds)
    A_lin = np.block([[(W @ P)[ci], N[ci]], [((f_q + f_qd @ W) @ P)[si], (f_qd @ N)[si]]])
    B_lin = np.vstack([np.zeros((len(ci), f_u.shape[1])), f_u[si]])
    M_s = N.T @ J["M"] @ N
    return LinearModel(
        point=point,
        coordinates=tuple(names[0][k] for k in ci), speeds=tuple(names[1][k] for k in si),
        inputs=tuple(s.name for s in system.inputs), A=A_lin, B=B_lin,
        M=M_s, C=-M_s @ A_lin[len(ci):, len(ci):], K=-M_s @ A_lin[len(ci):, :len(ci)], B2=M_s @ f_u[si],
        speed_rates=qdd[si],
        dependent=tuple([names[0][k] for k in partition.dependent_coordinates]
                        + [names[1][k] for k in partition.dependent_speeds]),
        energy_conserved=_jacobi_conserved_at(d, point),
        coordinate_rates=point.qd[ci],
        invariant=invariant_directions(system, point, P, A_lin[:, :len(ci)]),
        generic_A=generic_state_matrix(system, point, partition),
    )


GENERIC_FACTORS = 0.3      # parameters scaled by 1 + up to this (deterministic, distinct per parameter)


def generic_state_matrix(system: CompiledSystem, point: Point, partition) -> np.ndarray:
    """A at the same point with every nonzero parameter scaled by its own factor in
    (1, 1 + GENERIC_FACTORS) (a zero stays zero): an entry of A that is zero here but not
    there is zero by a coincidence of the parameters' values (the bead on the hoop at
    Omega^2 = g/R exactly, where the stiffness vanishes), not by the structure of the
    equations (a cart's position, on which nothing depends, for any values). Unconstrained
    systems only (scaled parameters move a constraint manifold off the point); empty when
    not finite there or not made."""
    if system.m:
        return np.zeros((0, 0))
    model = system.derivation.model
    names = [p.symbol.name for p in (*model.parameters, *model.inputs)]
    factors = 1 + GENERIC_FACTORS * np.modf(np.arange(1, len(names) + 1) * 0.6180339887498949)[0]
    scaled = replace(point, parameters={**point.parameters, **{
        name: point.parameters[name] * f for name, f in zip(names, factors)}})
    try:
        with np.errstate(all="ignore"):
            _, _, J = system.accelerations(scaled)
            K = _augmented(J["M"], J["A"])
            f_q, f_qd = (-np.linalg.solve(K, J[name])[:system.n] for name in ("G_q", "G_qd"))
    except (np.linalg.LinAlgError, ValueError, ZeroDivisionError, SingularPoint):
        return np.zeros((0, 0))
    ci, si = list(partition.coordinates), list(partition.speeds)
    identity = np.eye(system.n)
    A = np.block([[np.zeros((len(ci), len(ci))), identity[ci][:, si]], [f_q[si][:, ci], f_qd[si][:, si]]])
    return A if np.all(np.isfinite(A)) else np.zeros((0, 0))


def invariant_directions(system: CompiledSystem, point: Point, P: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """Directions v of the independent coordinates (columns, orthonormal) along which
    nothing in the equations changes: A's coordinate `columns` ignore v at the point, and
    the q-Jacobians of M, F, A, b, the velocity rows and phi annihilate P v at a generic
    point too (a symmetry of the model, not a coincidence of this point: the crane's
    trolley and load moving together)."""
    from scipy.linalg import null_space

    if not columns.shape[1]:
        return np.zeros((0, 0))
    scale = max(1.0, float(np.max(np.abs(columns), initial=0.0)))
    candidates = null_space(columns / scale, rcond=_SYMMETRY_TOL)
    if not candidates.shape[1]:
        return candidates
    jacobian = system.generic_q_jacobian(point)
    if jacobian is None:
        return np.zeros((columns.shape[1], 0))
    image = jacobian @ (P @ candidates)
    size = max(1.0, float(np.max(np.abs(jacobian), initial=0.0)))
    if np.max(np.abs(image), initial=0.0) <= _SYMMETRY_TOL * size:
        return candidates
    return candidates @ null_space(image / size, rcond=_SYMMETRY_TOL)


def _jacobi_conserved_at(d, point: Point) -> bool:
    """h = T2 - T0 + V is conserved at the point's parameter values: decided from the
    values, not the spec's structure (dampers set to 0 with --at leave Q' = 0)."""
    if d.jacobi_integral is not None:
        return True
    if d.no_jacobi_reason != "the non-conservative forces Q' are not zero" or not d.scleronomic:
        return False
    from lagcli.model.calculus import numerically_zero

    values = {p.symbol: sp.Float(point.parameters[p.symbol.name])
              for p in (*d.model.parameters, *d.model.inputs) if p.symbol.name in point.parameters}
    return numerically_zero([Q.xreplace(values) for Q in d.nonconservative_forces])


def _tangent(system: CompiledSystem, point: Point, partition: Partition, J: dict):
    """P, N, W of the module docstring, at the point."""
    n = system.n
    ci, cd = list(partition.coordinates), list(partition.dependent_coordinates)
    si, sd = list(partition.speeds), list(partition.dependent_speeds)
    P = np.zeros((n, len(ci)))
    P[ci, range(len(ci))] = 1.0
    N = np.zeros((n, len(si)))
    N[si, range(len(si))] = 1.0
    W = np.zeros((n, n))
    if cd:
        phi_q = system.holonomic_jacobian(point)
        P[cd] = -np.linalg.solve(phi_q[:, cd], phi_q[:, ci])
    if sd:
        A = J["A"]
        N[sd] = -np.linalg.solve(A[:, sd], A[:, si])
        W[sd] = -np.linalg.solve(A[:, sd], J["V_q"])
    return P, N, W
