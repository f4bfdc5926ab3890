"""The numeric right-hand side of Hamilton's equations (unconstrained systems).

The symbolic form (momenta, H, q'(p), p') is `lagcli.derive.hamilton_form`; here
y = [q, p] -> [q', p'] solves M q' = p - a at each call, never a symbolic inverse.
"""
from __future__ import annotations

import numpy as np
import sympy as sp


class HamiltonRhs:
    """y = [q, p] -> [q', p'] (numeric; sympy's lambdify of lagcli-built expressions)."""

    def __init__(self, d, parameters: dict):
        model = d.model
        values = {p.symbol: sp.Float(parameters.get(p.symbol.name, p.value), 30)
                  for p in (*model.parameters, *model.inputs)}
        M, a = sp.Matrix(d.mass_matrix).xreplace(values), sp.Matrix(d.t1_coefficients).xreplace(values)
        L = d.L.xreplace(values)
        force = sp.Matrix([L.diff(q) for q in model.q]) + sp.Matrix(d.nonconservative_forces).xreplace(values)
        args = [model.t, list(model.q), list(model.qd)]
        self._M = sp.lambdify(args, M, modules="numpy", cse=True)
        self._a = sp.lambdify(args, a, modules="numpy", cse=True)
        self._force = sp.lambdify(args, force, modules="numpy", cse=True)
        self._H = sp.lambdify(args, (d.T2 - d.T0 + d.V).xreplace(values), modules="numpy", cse=True)
        self.n = len(model.q)

    def velocities(self, t, q, p) -> np.ndarray:
        zero = np.zeros(self.n)
        M = np.asarray(self._M(t, q, zero), dtype=float).reshape(self.n, self.n)
        a = np.asarray(self._a(t, q, zero), dtype=float).reshape(self.n)
        return np.linalg.solve(M, p - a)

    def __call__(self, t, y) -> np.ndarray:
        q, p = y[:self.n], y[self.n:]
        qd = self.velocities(t, q, p)
        return np.concatenate([qd, np.asarray(self._force(t, q, qd), dtype=float).reshape(self.n)])

    def hamiltonian(self, t, y) -> float:
        """H = T2 - T0 + V at q' = q'(q, p)."""
        q, p = y[:self.n], y[self.n:]
        return float(self._H(t, q, self.velocities(t, q, p)))
