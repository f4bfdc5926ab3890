"""The frozen result of `derive(model)`: everything later stages need, as sympy objects.

Sign conventions (lecture notes, section 6.7), for coordinates q (n), multipliers
lambda (m = d + g constraint rows):

    d/dt(dL/dq'_i) - dL/dq_i - Q'_i = sum_j lambda_j a_ji            (equations)
    sum_k a_jk q'_k + d_j = 0                                         (constraints)

Explicit (matrix) form, with T = 1/2 q'^T M q' + a^T q' + T0:

    M q'' + c(q, q') + M_t q' + gamma q' + a_t - dT0/dq + dV/dq = Q' + A^T lambda
    c_i = sum_jl 1/2 (dM_ij/dq_l + dM_il/dq_j - dM_jl/dq_i) q'_j q'_l
    gamma_ij = da_i/dq_j - da_j/dq_i                                   (skew-symmetric)

so `forcing` F = Q' - c - M_t q' - gamma q' - a_t + dT0/dq - dV/dq and the
augmented system is

    [ M  -A^T ] [ q''    ]   [ F                  ]
    [ A   0   ] [ lambda ] = [ -(A' q' + d')      ]      (`constraint_bias`)
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import sympy as sp

from lagcli.errors import Loc
from lagcli.model.model_types import Model


@dataclass(frozen=True)
class ConstraintRow:
    label: str | None          # the user's `name:` if given
    multiplier: sp.Symbol      # lambda_<j> or lambda_<name>
    kind: str                  # "holonomic" | "nonholonomic"
    expr: sp.Expr              # as written: phi(q, t) or the velocity expression
    a: tuple[sp.Expr, ...]     # a_jk, k over coordinates
    d: sp.Expr                 # d_j
    integrable: bool | None    # nonholonomic rows: True when it is holonomic in disguise
    loc: Loc | None


@dataclass(frozen=True)
class Equation:
    coordinate: sp.Symbol
    lhs: sp.Expr               # d/dt(dL/dq'_i) - dL/dq_i - Q'_i
    rhs: sp.Expr               # sum_j lambda_j a_ji (0 without constraints)


@dataclass(frozen=True)
class Conserved:
    name: str                  # "p_<q>", "jacobi", "energy"
    kind: str                  # "momentum" | "jacobi" | "energy"
    expr: sp.Expr


@dataclass(frozen=True)
class Derivation:
    model: "Model"
    # energies
    T: sp.Expr
    T2: sp.Expr
    T1: sp.Expr
    T0: sp.Expr
    V: sp.Expr
    L: sp.Expr
    mass_matrix: sp.ImmutableMatrix          # n x n
    t1_coefficients: sp.ImmutableMatrix      # n x 1, the a_i of T1 = a . q'
    # forces (F, the equations and the total generalized forces: computed on first use, below)
    nonconservative_forces: sp.ImmutableMatrix  # n x 1, Q'_j (applied forces not in V)
    # constraints
    constraints: tuple[ConstraintRow, ...]
    constraint_matrix: sp.ImmutableMatrix    # A, m x n (0 x n when unconstrained)
    constraint_bias: sp.ImmutableMatrix      # -(A' q' + d'), m x 1
    multipliers: tuple[sp.Symbol, ...]
    generalized_constraint_forces: sp.ImmutableMatrix   # C_j = sum_k lambda_k a_kj
    particle_constraint_forces: dict         # particle name -> R_i = m r_i'' - F_i (in q, q', q'', lambda)
    # invariants
    energy: sp.Expr                          # T + V
    ignorable: tuple[sp.Symbol, ...]
    conserved: tuple[Conserved, ...]
    jacobi_integral: sp.Expr | None
    energy_is_jacobi: bool
    scleronomic: bool
    no_jacobi_reason: str | None = None      # why there is no Jacobi integral, in words
    events: tuple = ()                       # lagcli.derive.event_functions.EventFunction per spec event
    input_laws: tuple = ()                   # (input symbol, law) substituted into F: the closed loop

    # F and what is made of it are computed on first use: a report rebuilds what it prints
    # from M, a, T0, V and Q' (lagcli/report/display.py) and never reads them, and F is a
    # quarter of the derivation's time at 40 links. They depend on the fields above only.
    @functools.cached_property
    def _potential_gradient(self) -> list[sp.Expr]:
        """dV/dq, in F and in the generalized forces."""
        from lagcli.derive.forcing import potential_gradient

        return potential_gradient(self.model, self.V)

    @functools.cached_property
    def _open_loop_forcing(self) -> sp.ImmutableMatrix:
        """F with the inputs as symbols, refused when a constant is beyond double precision."""
        from lagcli.derive.forcing import forcing
        from lagcli.derive.representable import refuse_unrepresentable_forcing

        F = forcing(self.model, self.nonconservative_forces, self._potential_gradient)
        refuse_unrepresentable_forcing(self.model, F)
        return F

    @functools.cached_property
    def forcing(self) -> sp.ImmutableMatrix:
        """F, so that M q'' = F + A^T lambda (n x 1); `input_laws` substituted (closed_loop.py)."""
        F = self._open_loop_forcing
        return sp.ImmutableMatrix(F.xreplace(dict(self.input_laws))) if self.input_laws else F

    @functools.cached_property
    def equations(self) -> tuple[Equation, ...]:
        """M q'' - F = A^T lambda, one per coordinate (F with the inputs as symbols)."""
        from lagcli.derive.forcing import equation_lhs

        lhs = equation_lhs(self.mass_matrix, self._open_loop_forcing, self.model.qdd)
        return tuple(Equation(q, lhs_i, C) for q, lhs_i, C
                     in zip(self.model.q, lhs, self.generalized_constraint_forces))

    @functools.cached_property
    def generalized_forces(self) -> sp.ImmutableMatrix:
        """n x 1, the total Q_j by virtual work: Q' - dV/dq."""
        from lagcli.derive.forcing import total_generalized_forces

        return total_generalized_forces(self.nonconservative_forces, self._potential_gradient)

    # Whether Q' has a potential is for reports only: searched on first use (it may integrate).
    @functools.cached_property
    def _force_potential(self) -> tuple[bool, sp.Expr | None]:
        from lagcli.derive.forces import find_potential

        return find_potential(self.model, self.nonconservative_forces)

    @property
    def forces_conservative(self) -> bool:
        """Q' is derivable from a potential V'(q) (symmetric Jacobian, no q', no t)."""
        return self._force_potential[0]

    @property
    def force_potential(self) -> sp.Expr | None:
        """That V' (Q' = -dV'/dq), when found in closed form."""
        return self._force_potential[1]

    # The explicit form's named terms (for reports) are computed on first use: they
    # need every dM/dq_l (n^3 derivatives), which numerics never do (see forcing.py).
    @functools.cached_property
    def _explicit(self):
        from lagcli.derive.explicit import explicit_form

        return explicit_form(self.model, self.mass_matrix, self.t1_coefficients, self.T0, self.V)

    @property
    def velocity_terms(self) -> sp.ImmutableMatrix:
        """c(q, q'): the terms quadratic in q'."""
        return self._explicit.velocity_terms

    @property
    def mass_rate_terms(self) -> sp.ImmutableMatrix:
        """M_t q'."""
        return self._explicit.mass_rate_terms

    @property
    def gyroscopic_matrix(self) -> sp.ImmutableMatrix:
        """gamma_ij = da_i/dq_j - da_j/dq_i."""
        return self._explicit.gyroscopic_matrix

    @property
    def t1_rate_terms(self) -> sp.ImmutableMatrix:
        """a_t."""
        return self._explicit.t1_rate_terms

    @property
    def position_terms(self) -> sp.ImmutableMatrix:
        """dV/dq - dT0/dq."""
        return self._explicit.position_terms

    @property
    def augmented_matrix(self) -> sp.ImmutableMatrix:
        """[[M, -A^T], [A, 0]]: unknowns (q'', lambda)."""
        A, m = self.constraint_matrix, len(self.constraints)
        top = self.mass_matrix.row_join(-A.T)
        return sp.ImmutableMatrix(top.col_join(A.row_join(sp.zeros(m, m))))

    @property
    def augmented_rhs(self) -> sp.ImmutableMatrix:
        """[F; -(A' q' + d')]."""
        return sp.ImmutableMatrix(self.forcing.col_join(self.constraint_bias))

    @property
    def n(self) -> int:
        return len(self.model.q)

    @property
    def n_holonomic(self) -> int:
        return sum(1 for c in self.constraints if c.kind == "holonomic")

    @property
    def n_nonholonomic(self) -> int:
        return sum(1 for c in self.constraints if c.kind == "nonholonomic")

    @property
    def dof(self) -> int:
        return self.n - len(self.constraints)
