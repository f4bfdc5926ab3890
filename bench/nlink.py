"""The planar N-link pendulum (point masses, absolute angles, gravity) as a spec
and as sympy.physics.mechanics models: shared by the benchmarks."""
from __future__ import annotations

import sympy as sp


def nlink_spec_text(n: int) -> str:
    """YAML spec of the N-link pendulum: angles th1..thN from the downward vertical."""
    lines = [f"name: nlink{n}", f"coordinates: [{', '.join(f'th{i}' for i in range(1, n + 1))}]",
             "parameters:", "  g: 9.81"]
    lines += [f"  m{i}: 1.0\n  l{i}: 1.0" for i in range(1, n + 1)]
    lines += ["gravity: [0, -g]", "particles:"]
    xs, ys = [], []
    for i in range(1, n + 1):
        xs.append(f"l{i}*sin(th{i})")
        ys.append(f"l{i}*cos(th{i})")
        lines.append(f"  P{i}: {{mass: m{i}, position: ['{' + '.join(xs)}', '-({' + '.join(ys)})']}}")
    lines.append("initial: {th1: 0.5}")
    return "\n".join(lines) + "\n"


def mechanics_nlink(n: int):
    """(coordinates, speeds, particles, loads, frame) for sympy.physics.mechanics."""
    import sympy.physics.mechanics as me

    q = me.dynamicsymbols(f"th1:{n + 1}")
    u = me.dynamicsymbols(f"u1:{n + 1}")
    m = sp.symbols(f"m1:{n + 1}")
    l = sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    point, particles, loads = O, [], []
    for i in range(n):
        nxt = point.locatenew(f"P{i + 1}", l[i] * sp.sin(q[i]) * N.x - l[i] * sp.cos(q[i]) * N.y)
        nxt.set_vel(N, nxt.pos_from(O).dt(N))
        particles.append(me.Particle(f"Pa{i + 1}", nxt, m[i]))
        loads.append((nxt, -m[i] * g * N.y))
        point = nxt
    return q, u, particles, loads, N
