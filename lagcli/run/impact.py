"""The impact law, solved numerically like the augmented system (never a symbolic inverse).

At an impact of gap g(t, q) with G = dg/dq, restitution e and the constraint rows
A q' + d = 0, the velocities jump from q'- to q'+ with the impulse P (and Lambda for
the constraints):

    [ M  -G^T  -A^T ] [ q'+    ]   [ M q'-                  ]
    [ G   0     0   ] [ P      ] = [ -e (G q'- + g_t) - g_t ]
    [ A   0     0   ] [ Lambda ]   [ -d                     ]

The positions do not change. The matrix is singular when G lies in the span of the
constraint rows (the constraints already forbid the motion the impact would stop).
"""
from __future__ import annotations

import numpy as np

from lagcli.errors import SimulationError


def impact(M, A, d, G, g_t: float, e: float, qd_minus) -> tuple[np.ndarray, float]:
    """(q'+, P) for one impact (see the module docstring)."""
    n, m = len(qd_minus), len(d)
    K = np.zeros((n + 1 + m, n + 1 + m))
    K[:n, :n], K[:n, n], K[:n, n + 1:] = M, -G, -A.T
    K[n, :n], K[n + 1:, :n] = G, A
    rhs = np.concatenate([M @ qd_minus, [-e * (G @ qd_minus + g_t) - g_t], -d])
    try:
        x = np.linalg.solve(K, rhs)
    except np.linalg.LinAlgError:
        raise SimulationError("the impact's direction dg/dq lies in the span of the constraint rows "
                              "(or the mass matrix is singular): no impulse can change the approach speed")
    return x[:n], float(x[n])


def approach_speed(G, g_t: float, qd) -> float:
    """dg/dt = G q' + g_t: negative while a falling gap closes."""
    return float(G @ qd + g_t)
