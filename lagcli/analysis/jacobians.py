"""Matrices and their exact Jacobians, compiled to one numpy function.

Differentiating the large expressions of a spatial multibody system entry by
entry (sympy's `Matrix.jacobian`) repeats the same subexpressions in every
derivative and walks every tree again for each variable: for an 8-coordinate
bicycle that is minutes. Instead the expressions are first reduced to a chain
of common subexpressions (sympy's `cse`)

    t_k = e_k(args, t_1 .. t_k-1),         outputs r_i = e_i(args, t_...)

and differentiated symbolically along that chain (forward mode):

    dt_k/dz = de_k/dz + sum_j de_k/dt_j dt_j/dz

Every derivative taken is of one small e_k, every result is a new short
assignment, and the whole is still exact symbolic differentiation: numbers come
in only when the compiled function is called. The assignments are handed to
sympy's `lambdify` as its common subexpressions.

When every function in the expressions is analytic (no abs, sign, min, max, atan2,
Heaviside: `_NOT_ANALYTIC`), the Jacobians are instead taken by the complex step
(Squire and Trapp 1998; Martins, Sturdza and Alonso 2003): with z real,

    df/dz_k = Im f(z + i h e_k) / h + O(h^2),     h = 1e-30,

which has no subtractive cancellation, so it is exact to rounding like the symbolic
chain, and needs only f compiled: the bicycle's linearization compiles in a fraction
of the time (bench/README.md, "The page"). A point costs one real evaluation and one
complex one per variable (milliseconds; a sweep's hundred points stay cheap).
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from lagcli.model.calculus import almost_everywhere

_NOT_ANALYTIC = (sp.Abs, sp.sign, sp.Heaviside, sp.DiracDelta, sp.Min, sp.Max, sp.atan2, sp.floor,
                 sp.ceiling, sp.Piecewise, sp.re, sp.im, sp.arg, sp.conjugate)
_STEP = 1e-30          # the complex step



class CompiledJacobians:
    """`outputs` (name -> Matrix) and `jacobians` (name -> (output name, variables)),
    evaluated together: `self(values)` -> {name: ndarray}; `values` in `args` order."""

    def __init__(self, args, outputs: dict, jacobians: dict):
        outputs = {name: sp.Matrix(m) for name, m in outputs.items()}
        flat = [e for m in outputs.values() for e in m]
        self.steps = None
        if not any(e.has(*_NOT_ANALYTIC) for e in flat):
            self._by_complex_step(args, outputs, jacobians, flat)
            return
        temps = sp.numbered_symbols("_t")
        assignments, reduced = sp.cse(flat, symbols=temps, order="none")
        variables = list(dict.fromkeys(v for _, wrt in jacobians.values() for v in wrt))
        chain = _Chain(assignments, set(variables), temps)
        results: dict[str, list] = {}
        k = 0
        for name, m in outputs.items():
            results[name] = reduced[k:k + len(m)]
            k += len(m)
        self.shapes = {name: m.shape for name, m in outputs.items()}
        final = []
        for name, m in outputs.items():
            final += results[name]
        for name, (of, wrt) in jacobians.items():
            rows = results[of]
            final += [chain.derivative(e, z) for e in rows for z in wrt]
            self.shapes[name] = (len(rows), len(wrt))
        code = chain.assignments
        self.function = sp.lambdify(args, final or [sp.S.Zero], modules="numpy",
                                    cse=lambda _: (code, final or [sp.S.Zero]))

    def _by_complex_step(self, args, outputs: dict, jacobians: dict, flat) -> None:
        """Compile the outputs only; `__call__` takes the Jacobians by the complex step."""
        self.shapes = {name: m.shape for name, m in outputs.items()}
        self.function = sp.lambdify(args, flat or [sp.S.Zero], modules="numpy", cse=True)
        self.steps = {name: (of, [args.index(z) for z in wrt]) for name, (of, wrt) in jacobians.items()}

    def __call__(self, values) -> dict:
        out = self._outputs(values, float)
        for name, (of, columns) in (self.steps or {}).items():
            rows = self.shapes[of][0]
            derivatives = []
            for k in columns:
                shifted = np.array(values, dtype=complex)
                shifted[k] += 1j * _STEP
                derivatives.append(self._outputs(shifted, complex)[of].imag.reshape(-1) / _STEP)
            out[name] = np.column_stack(derivatives) if derivatives else np.zeros((rows, 0))
        return out

    def _outputs(self, values, dtype) -> dict:
        flat = np.asarray(self.function(*values), dtype=dtype).reshape(-1)
        out, k = {}, 0
        for name, (rows, cols) in self.shapes.items():
            out[name] = flat[k:k + rows * cols].reshape(rows, cols)
            k += rows * cols
        return out


class _Chain:
    """The cse assignments, extended with the derivative of every temporary that
    depends on a variable (`derivative_of[(t, z)]`), in an order that computes each
    before its use."""

    def __init__(self, assignments, variables: set, names):
        self.assignments: list[tuple[sp.Symbol, sp.Expr]] = []
        self.depends: dict[sp.Symbol, set] = {}
        self.derivative_of: dict[tuple, sp.Symbol] = {}
        self.names = names
        self.variables = variables
        for symbol, expr in assignments:
            self.assignments.append((symbol, expr))
            self.depends[symbol] = self._dependence(expr)
            for z in sorted(self.depends[symbol], key=sp.default_sort_key):
                d = self._differentiate(expr, z)
                if d != 0:
                    name = next(self.names)
                    self.assignments.append((name, d))
                    self.derivative_of[(symbol, z)] = name

    def _dependence(self, expr) -> set:
        free = expr.free_symbols
        found = free & self.variables
        for s in free:
            found |= self.depends.get(s, set())
        return found

    def _differentiate(self, expr, z) -> sp.Expr:
        total = expr.diff(z) if z in expr.free_symbols else sp.S.Zero
        for t in sorted(expr.free_symbols, key=sp.default_sort_key):
            rate = self.derivative_of.get((t, z))
            if rate is not None:
                total += expr.diff(t) * rate
        return almost_everywhere(total)

    def derivative(self, expr, z) -> sp.Expr:
        """d expr / dz for an output expression in the variables and temporaries."""
        if z not in self._dependence(expr):
            return sp.S.Zero
        return self._differentiate(expr, z)
