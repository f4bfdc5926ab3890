"""Independent oracles for the derivation, built with sympy.physics.mechanics.

Used only by the `test_oracle_*.py` tests. Each builder sets a system up from
scratch (frames, points, particles, rigid bodies, loads) without looking at
lagcli, with generalized speeds chosen as u_i = q_i' so that Kane's equations
are Lagrange's equations row by row:

    M(q) u' = F(q, u)          (KanesMethod.mass_matrix / .forcing)

With dependent speeds (rolling disc) the oracle's rows are the independent
dynamic equations followed by the differentiated velocity constraints, so
u' = M^-1 F is still the full acceleration vector.

`Oracle.plain(expr)` rewrites an oracle expression in lagcli's naming: q(t) ->
`q`, q' and u -> `q_dot`, q'' and u' -> `q_ddot`, parameters by name, as
Symbol(name, real=True). `to_model(expr, model)` then swaps those for the
model's own symbols (looked up with `model.symbol`), so comparisons never rely
on two independently created symbols being equal.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me


@dataclass
class Oracle:
    """A system built with sympy.physics.mechanics, plus its name map to lagcli names."""

    names: list[str]                 # coordinate names, lagcli order
    q: list                          # dynamicsymbols q_i(t), same order as `names`
    u: list                          # generalized speeds u_i = q_i', same order
    params: dict                     # parameter name -> oracle Symbol
    mass_matrix: sp.Matrix           # rows/columns ordered like `u`
    forcing: sp.Matrix
    extras: dict = field(default_factory=dict)   # named oracle quantities (energy, momenta ...)

    def plain(self, expr):
        """`expr` with dynamic symbols replaced by plain real symbols in lagcli's naming."""
        t = me.dynamicsymbols._t
        repl = {}
        for name, qi, ui in zip(self.names, self.q, self.u):
            repl[ui.diff(t)] = sp.Symbol(f"{name}_ddot", real=True)
            repl[qi.diff(t, 2)] = sp.Symbol(f"{name}_ddot", real=True)
            repl[ui] = sp.Symbol(f"{name}_dot", real=True)
            repl[qi.diff(t)] = sp.Symbol(f"{name}_dot", real=True)
        for name, qi in zip(self.names, self.q):
            repl[qi] = sp.Symbol(name, real=True)
        out = me.msubs(sp.sympify(expr), repl)
        return out.xreplace({s: sp.Symbol(n, real=True) for n, s in self.params.items()})


def to_model(expr, model):
    """Swap the plain symbols of an `Oracle.plain` expression for `model`'s symbols."""
    expr = sp.sympify(expr)
    return expr.xreplace({s: model.symbol(s.name) for s in expr.free_symbols})


def state_symbols(model):
    """Argument list [t, q..., q_dot..., q_ddot..., parameters...] used by `lambdify_model`."""
    return [model.t, *model.q, *model.qd, *model.qdd, *model.parameter_symbols]


def lambdify_model(model, *exprs):
    """One numeric function f(q, qd, p, qdd=0, t=0) -> tuple of float arrays, one per
    expression (matrices keep their shape)."""
    args = state_symbols(model)
    fn = sp.lambdify(args, [sp.Matrix(e) if isinstance(e, sp.MatrixBase) else e for e in exprs],
                     modules="numpy", cse=True)

    def call(q, qd, p, qdd=None, t=0.0):
        qdd = np.zeros(len(model.q)) if qdd is None else qdd
        return tuple(np.array(v, dtype=float) for v in fn(t, *q, *qd, *qdd, *p))

    return call


def lambdify_oracle(oracle, model, *exprs):
    """Like `lambdify_model` for oracle expressions (converted with `plain` + `to_model`)."""
    return lambdify_model(model, *(to_model(oracle.plain(e), model) for e in exprs))


def time_derivative(expr, model):
    """Total time derivative of a model expression in t, q, q_dot (q_ddot appears)."""
    return sp.diff(expr, model.t) + sum(
        sp.diff(expr, q) * qd + sp.diff(expr, qd) * qdd
        for q, qd, qdd in zip(model.q, model.qd, model.qdd))


def param_values(model, rng=None, spread=0.5):
    """Parameter values in model order: the spec defaults, optionally scaled by random
    factors in [1 - spread, 1 + spread] so no coincidence hides a wrong term."""
    base = np.array([p.value for p in model.parameters], dtype=float)
    if rng is None:
        return base
    return base * rng.uniform(1 - spread, 1 + spread, size=base.size)


def assert_close(actual, expected, rtol=1e-10, what=""):
    """Relative comparison scaled by the largest entry of `expected` (and 1e-300)."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    scale = max(np.max(np.abs(expected)), 1e-300)
    err = np.max(np.abs(actual - expected)) / scale
    assert err <= rtol, f"{what}: relative error {err:.3e}\n lagcli: {actual}\n oracle: {expected}"


# --------------------------------------------------------------------------- builders


def _speeds(names):
    q = me.dynamicsymbols(" ".join(names))
    u = me.dynamicsymbols(" ".join(f"u_{n}" for n in names))
    q, u = (list(q), list(u)) if len(names) > 1 else ([q], [u])
    kd = [qi.diff() - ui for qi, ui in zip(q, u)]
    return q, u, kd


def _qdot_to_u(q, u):
    return {qi.diff(): ui for qi, ui in zip(q, u)}


def planar_chain_kane(n):
    """N point masses on massless rods, absolute angles q_i from the downward vertical,
    gravity -g N.y: KanesMethod with u_i = q_i'."""
    names = [f"theta{i}" for i in range(1, n + 1)]
    q, u, kd = _speeds(names)
    g = sp.Symbol("g")
    masses = sp.symbols(f"m1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    N = me.ReferenceFrame("N")
    prev = me.Point("O")
    prev.set_vel(N, 0)
    particles, loads, height = [], [], 0
    potential = 0
    for i in range(n):
        rod = lengths[i] * (sp.sin(q[i]) * N.x - sp.cos(q[i]) * N.y)
        P = prev.locatenew(f"P{i + 1}", rod)
        P.set_vel(N, prev.vel(N) + rod.dt(N).subs(_qdot_to_u(q, u)))
        particles.append(me.Particle(f"B{i + 1}", P, masses[i]))
        loads.append((P, -masses[i] * g * N.y))
        height += rod.dot(N.y)
        potential += masses[i] * g * height
        prev = P
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations(particles, loads)
    params = {s.name: s for s in (*masses, *lengths, g)}
    energy = sum(p.kinetic_energy(N) for p in particles) + potential
    return Oracle(names, q, u, params, kane.mass_matrix, kane.forcing,
                  extras={"energy": energy, "kane": kane})


def double_pendulum_lagrange():
    """Double pendulum (point masses m1, m2, rods l1, l2, absolute angles) with
    LagrangesMethod: L = T - V written from particle kinetic and potential energies."""
    names = ["theta1", "theta2"]
    q = list(me.dynamicsymbols("theta1 theta2"))
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P1 = O.locatenew("P1", l1 * (sp.sin(q[0]) * N.x - sp.cos(q[0]) * N.y))
    P2 = P1.locatenew("P2", l2 * (sp.sin(q[1]) * N.x - sp.cos(q[1]) * N.y))
    P1.set_vel(N, P1.pos_from(O).dt(N))
    P2.set_vel(N, P2.pos_from(O).dt(N))
    B1, B2 = me.Particle("B1", P1, m1), me.Particle("B2", P2, m2)
    B1.potential_energy = m1 * g * P1.pos_from(O).dot(N.y)
    B2.potential_energy = m2 * g * P2.pos_from(O).dot(N.y)
    L = me.Lagrangian(N, B1, B2)
    lm = me.LagrangesMethod(L, q)
    eom = lm.form_lagranges_equations()
    qd = [qi.diff() for qi in q]
    energy = B1.kinetic_energy(N) + B2.kinetic_energy(N) + B1.potential_energy + B2.potential_energy
    return Oracle(names, q, qd, {s.name: s for s in (m1, m2, l1, l2, g)},
                  lm.mass_matrix, lm.forcing, extras={"eom": eom, "energy": energy})


def heavy_top_kane():
    """Heavy symmetric top, tip fixed at O, body frame B = N rotated body-fixed 'ZXZ' by
    (psi, theta, phi), CM at h B.z, central inertia (A, A, C) in B, gravity -m g N.z."""
    names = ["psi", "theta", "phi"]
    q, u, kd = _speeds(names)
    m, h, A, C, g = sp.symbols("m h A C g")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Body", q, "ZXZ")
    B.set_ang_vel(N, B.ang_vel_in(N).subs(_qdot_to_u(q, u)))
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", h * B.z)
    G.v2pt_theory(O, N, B)
    top = me.RigidBody("top", G, B, m, (me.inertia(B, A, A, C), G))
    kane = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    kane.kanes_equations([top], [(G, -m * g * N.z)])
    H_O = top.angular_momentum(O, N)
    energy = top.kinetic_energy(N) + m * g * G.pos_from(O).dot(N.z)
    back = {ui: qi.diff() for qi, ui in zip(q, u)}
    return Oracle(names, q, u, {s.name: s for s in (m, h, A, C, g)},
                  kane.mass_matrix, kane.forcing,
                  extras={"p_psi": H_O.dot(N.z), "p_phi": H_O.dot(B.z), "energy": energy,
                          "cm": [G.pos_from(O).dot(e) for e in (N.x, N.y, N.z)],
                          "omega": B.ang_vel_in(N).xreplace(back), "N": N})


def rolling_disc_kane():
    """Thin disc rolling without slipping, KanesMethod with dependent speeds.

    q = (x, y, psi, theta, phi), u_i = q_i'. Frames: A = N rotated Rz(psi) Rx(theta)
    (yaw, lean), disc frame B = A rotated Ry(phi) (spin about the symmetry axis B.y).
    CM at x N.x + y N.y + r cos(theta) N.z; contact point C = CM - r A.z, fixed in B.
    Velocity constraints: v_C . N.x = v_C . N.y = 0 (v_C by the two-point theorem);
    independent speeds (u_psi, u_theta, u_phi), dependent (u_x, u_y). The velocity
    constraints are NOT substituted into T (that gives wrong heading and spin
    equations); Kane's method with dependent speeds handles them correctly.
    Extras for a Newton-Euler check of the contact force: CM position, C - G and
    dH_G/dt in N components.
    """
    names = ["x", "y", "psi", "theta", "phi"]
    q, u, kd = _speeds(names)
    x, y, psi, theta, phi = q
    m, r, g = sp.symbols("m r g")
    qd_u = _qdot_to_u(q, u)
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Body", [psi, theta, 0], "ZXY")
    B = A.orientnew("B", "Axis", [phi, A.y])
    B.set_ang_vel(N, B.ang_vel_in(N).subs(qd_u))
    O = me.Point("O")
    O.set_vel(N, 0)
    G = O.locatenew("G", x * N.x + y * N.y + r * sp.cos(theta) * N.z)
    G.set_vel(N, G.pos_from(O).dt(N).subs(qd_u))
    Cp = G.locatenew("C", -r * A.z)
    Cp.v2pt_theory(G, N, B)
    v_contact = [Cp.vel(N).dot(N.x), Cp.vel(N).dot(N.y), Cp.vel(N).dot(N.z)]
    disc = me.RigidBody("disc", G, B, m,
                        (me.inertia(B, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4), G))
    kane = me.KanesMethod(N, q_ind=q, u_ind=u[2:], u_dependent=u[:2], kd_eqs=kd,
                          velocity_constraints=v_contact[:2])
    kane.kanes_equations([disc], [(G, -m * g * N.z)])
    # reorder rows/columns from Kane's (u_ind + u_dep) to the coordinate order
    order = [list(kane.u).index(ui) for ui in u]
    M = kane.mass_matrix[:, order]
    energy = disc.kinetic_energy(N) + m * g * G.pos_from(O).dot(N.z)
    back = {ui: qi.diff() for qi, ui in zip(q, u)}
    H_rate = disc.angular_momentum(G, N).dt(N)      # dH_G/dt, in u, u' and q'
    return Oracle(names, q, u, {s.name: s for s in (m, r, g)}, M, kane.forcing,
                  extras={"v_contact": [v.xreplace(back) for v in v_contact],
                          "energy": energy,
                          "cm": [G.pos_from(O).dot(e) for e in (N.x, N.y, N.z)],
                          "r_GC": [Cp.pos_from(G).dot(e) for e in (N.x, N.y, N.z)],
                          "H_G_rate": [H_rate.dot(e) for e in (N.x, N.y, N.z)]})


def solve_augmented(d):
    """(q'', lambda) solving [[M, -A^T], [A, 0]] [q''; lambda] = [F; b] symbolically (small systems)."""
    M = sp.Matrix(d.mass_matrix)
    A = sp.Matrix(d.constraint_matrix)
    K = M.row_join(-A.T).col_join(A.row_join(sp.zeros(A.rows, A.rows)))
    rhs = sp.Matrix(d.forcing).col_join(sp.Matrix(d.constraint_bias))
    sol = K.LUsolve(rhs)
    return sol[: M.rows, :], sol[M.rows:, :]


def spec_fixtures(spec_path, build_oracle):
    """Module-scoped `model`, `derivation` and `oracle` fixtures for one bundled spec:
    assign them at module level, `model, derivation, oracle = spec_fixtures(...)`."""
    import pytest

    @pytest.fixture(scope="module")
    def model():
        from lagcli.derive.pipeline import load_model
        return load_model(spec_path)

    @pytest.fixture(scope="module")
    def derivation(model):
        from lagcli.derive import derive
        return derive(model)

    @pytest.fixture(scope="module")
    def oracle():
        return build_oracle()

    return model, derivation, oracle
