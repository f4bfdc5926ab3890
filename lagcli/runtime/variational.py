"""lagcli's variational integrator in Python (`simulate --method variational`), written once:
the generated Python module carries this file's code verbatim after its imports
(`lagcli.runtime.python_variational`), and lagcli's Python backend runs that copy. Numpy
and the standard library only, no `from __future__` (the text is pasted into another
module). The C runtime states the same algorithm in lagcli/runtime/c/lagcli_variational.c.

The scheme (midpoint discrete Lagrangian, RATTLE-type constraints) and its equations
are in lagcli/derive/discrete.py; docs/simulate.md says why. The model is given as
callables of (t, q, v) -> numpy arrays (the generated module binds its parameters):

    momenta(t, q, v)      (g, f): g = dL/dq' = M q' + a, f = dL/dq + Q'
    jacobian(t, q, v)     (dg/dq, dg/dq', df/dq, df/dq'), each n x n
    holonomic(t, q)       (phi, A, phi_t) of the holonomic rows: d, d x n, d  (d may be 0)
    mass(t, q)            M, n x n
    accelerations(t, q, v)  (q'', lambda) of the exact equations: the predictor

Newton: start from the Taylor predictor q1 = q0 + h q0' + h^2/2 q0'' (and mu = lambda
of the exact equations), stop after the update dx with |dx| <= NEWTON_TOLERANCE
(1 + |x|) (max norms, q and mu each), when the error left is O(|dx|^2): round-off.
NEWTON_MAX_ITERATIONS without that, a singular Jacobian or a non-finite value end the
run (VariationalFailure: the time, and the hint to reduce dt). Nothing depends on a clock.
"""
# --- lagcli's variational integrator (lagcli/runtime/variational.py) ---
import numpy as np

NEWTON_TOLERANCE = 1e-12      # relative size of the last Newton update
NEWTON_MAX_ITERATIONS = 30    # Newton converges quadratically: far fewer when dt suits the motion


class VariationalFailure(ArithmeticError):
    """A step of the variational integrator failed at time `t` for `reason`."""

    def __init__(self, t, reason):
        super().__init__(f"at t = {t:.10g}: {reason}")
        self.t, self.reason = t, reason


class VariationalStats:
    """Counts of a run: steps, Newton iterations (each one evaluation of the momenta
    and of their Jacobian)."""

    def __init__(self):
        self.steps = 0
        self.iterations = 0


def variational_step(f, t, h, q, v, p, stats=None):
    """One step from (q, v, p) at t to t + h: (q1, v1, p1). Raises VariationalFailure."""
    n, t1, half = len(q), t + h, 0.5 * h
    qdd, lam = f.accelerations(t, q, v)
    q1 = q + h * v + half * h * np.asarray(qdd, dtype=float)
    _, A0, _ = f.holonomic(t, q)
    mu = np.array(lam, dtype=float)
    d = len(mu)
    for iteration in range(1, NEWTON_MAX_ITERATIONS + 1):
        qm, vm = 0.5 * (q + q1), (q1 - q) / h
        g, rate = f.momenta(t + half, qm, vm)
        gq, gv, fq, fv = f.jacobian(t + half, qm, vm)
        J = np.zeros((n + d, n + d))
        J[:n, :n] = 0.5 * (gq - half * fq) + (gv - half * fv) / h
        R = np.empty(n + d)
        R[:n] = g - half * rate - p
        if d:
            phi, A1, _ = f.holonomic(t1, q1)
            R[:n] -= half * (A0.T @ mu)
            R[n:] = phi
            J[:n, n:] = -half * A0.T
            J[n:, :n] = A1
        dx = _solve(J, -R, t, "the Newton iteration's Jacobian is singular")
        q1, mu = q1 + dx[:n], mu + dx[n:]
        if stats is not None:
            stats.iterations += 1
        if not (np.all(np.isfinite(q1)) and np.all(np.isfinite(mu))):
            raise VariationalFailure(t, "the Newton iteration diverged (inf/nan); reduce dt")
        if _small(dx[:n], q1) and _small(dx[n:], mu):
            break
    else:
        raise VariationalFailure(t, f"the Newton iteration did not converge in {NEWTON_MAX_ITERATIONS} "
                                 f"iterations (step {h:.6g}); reduce dt")
    rate = f.momenta(t + half, 0.5 * (q + q1), (q1 - q) / h)[1]
    # p1 = g + h/2 f (+ the constraint impulses), written as the momentum balance over the
    # step: a momentum whose force is zero (f_s = 0, no constraint on q_s) is kept exactly
    P = p + h * rate
    if d:
        P = P + half * (A0.T @ mu)
    v1, p1 = _legendre(f, t1, q1, P, t)
    if stats is not None:
        stats.steps += 1
    return q1, v1, p1


def _legendre(f, t1, q1, P, t):
    """(v1, p1) at (t1, q1) from the momentum P before the constraint impulse: M v1 = P - a
    + A^T s with A v1 + phi_t = 0 (the velocity-level constraint), p1 = P + A^T s."""
    n = len(q1)
    a = f.momenta(t1, q1, np.zeros(n))[0]
    M = f.mass(t1, q1)
    _, A, rate = f.holonomic(t1, q1)
    d = len(rate)
    K = np.zeros((n + d, n + d))
    K[:n, :n] = M
    K[:n, n:] = -A.T
    K[n:, :n] = A
    x = _solve(K, np.concatenate((P - a, -np.asarray(rate, dtype=float))), t,
               "the mass matrix (with the constraints) is singular at the new point")
    return x[:n], P + A.T @ x[n:]


def _solve(K, r, t, reason):
    try:
        x = np.linalg.solve(K, r)
    except np.linalg.LinAlgError:
        raise VariationalFailure(t, f"{reason}; reduce dt") from None
    if not np.all(np.isfinite(x)):
        raise VariationalFailure(t, "the Newton iteration diverged (inf/nan); reduce dt")
    return x


def _small(dx, x):
    return not len(dx) or float(np.max(np.abs(dx))) <= NEWTON_TOLERANCE * (1.0 + float(np.max(np.abs(x))))


def variational_rows(f, y0, windows, steps_per_row=1, stats=None):
    """(t, y) at each output time of `windows` (output_time_windows: the first time is 0),
    y = [q..., q'...], taking `steps_per_row` equal steps between consecutive output times."""
    n = len(y0) // 2
    q, v = np.array(y0[:n], dtype=float), np.array(y0[n:], dtype=float)
    p = np.asarray(f.momenta(0.0, q, v)[0], dtype=float)
    t_row = None
    for window in windows:
        for t_next in window:
            if t_row is not None:
                h = (t_next - t_row) / steps_per_row
                for j in range(steps_per_row):
                    q, v, p = variational_step(f, t_row + j * h, h, q, v, p, stats)
            t_row = t_next
            yield t_next, np.concatenate((q, v))
