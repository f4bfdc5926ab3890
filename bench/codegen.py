"""Benchmark of `lagcli generate` on the planar N-link pendulum (N = 2, 4, 8).

    PYTHONPATH=. .venv/bin/python bench/codegen.py [--links 2 4 8] [--repeats 7]

For each N, in one run, prints a table with ratios (no assertions):

- ops: operations (sympy.count_ops, CSE temporaries included) of the expressions lagcli's
  generated code evaluates for M and F, after its one CSE, against sympy's KanesMethod
  mass matrix and forcing after `sympy.cse` (target: no more);
- C ns/call: the generated `<name>_rhs` against a hand-written double-pendulum RHS
  (N = 2 only; target within 1.5x), both timed in the same C harness loop over the same
  states, median of several repeats;
- Rust ns/call: the generated crate's right-hand side (`--lang rust`, `cargo build
  --release`), timed by its example binary's `--bench-rhs` over the same kind of states
  (random in [-0.5, 0.5], the same parameters), median of several repeats, and its ratio
  to the generated C (target: within 1.5x);
- Python us/call: the generated module's `rhs` against `sympy.lambdify(..., cse=True)`
  of (M, F) plus `numpy.linalg.solve` (target: no slower), median of several repeats.

Point masses m_k on massless rods l_k, absolute angles q_k from the downward vertical,
gravity g: x_k = sum_{i<=k} l_i sin q_i, y_k = -sum_{i<=k} l_i cos q_i.
"""
from __future__ import annotations

import argparse
import ctypes
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import types
from pathlib import Path

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from lagcli.derive.pipeline import load_model  # noqa: E402
from lagcli.derive import derive  # noqa: E402
from lagcli.targets import codegen  # noqa: E402
from lagcli.interface import layout_of  # noqa: E402
from lagcli.targets.c import c_files  # noqa: E402
from lagcli.targets.python import python_module  # noqa: E402
from lagcli.targets.rust import crate_name, rust_files  # noqa: E402

CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]
CALLS = 200_000          # C calls per timed loop
STATES = 1024            # distinct random states cycled through


def spec_text(n: int) -> str:
    coords = ", ".join(f"q{k}" for k in range(1, n + 1))
    params = "\n".join(f"  m{k}: 1.0\n  l{k}: 1.0" for k in range(1, n + 1))
    lines = [f"name: pendulum{n}", f"coordinates: [{coords}]", "parameters:", params, "  g: 9.81",
             "gravity: [0, -g]", "particles:"]
    x, y = [], []
    for k in range(1, n + 1):
        x.append(f"l{k}*sin(q{k})")
        y.append(f"l{k}*cos(q{k})")
        lines.append(f"  P{k}: {{mass: m{k}, position: [{' + '.join(x)}, -({' + '.join(y)})]}}")
    init = ", ".join(f"q{k}: 0.{k}" for k in range(1, n + 1))
    lines.append(f"initial: {{{init}}}")
    return "\n".join(lines) + "\n"


def uncoupled_spec(n: int) -> str:
    """n particles on their own line x_i, each tied to the origin of its line by a spring k_i."""
    lines = [f"name: springs{n}", f"coordinates: [{', '.join(f'x{i}' for i in range(1, n + 1))}]", "parameters:"]
    lines += [f"  m{i}: {1 + i % 3}.0\n  k{i}: {1 + i % 7}.0" for i in range(1, n + 1)]
    lines.append("particles:")
    lines += [f"  P{i}: {{mass: m{i}, position: [x{i}, {i}, 0]}}" for i in range(1, n + 1)]
    lines.append("springs:")
    lines += [f"  - {{between: [P{i}, [0, {i}, 0]], stiffness: k{i}}}" for i in range(1, n + 1)]
    return "\n".join(lines) + "\n"


def kane_ops(n: int) -> int:
    """count_ops of cse(KanesMethod mass matrix and forcing) for the same pendulum."""
    q, u = me.dynamicsymbols(f"q1:{n + 1}"), me.dynamicsymbols(f"u1:{n + 1}")
    m, l = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    N, O = me.ReferenceFrame("N"), me.Point("O")
    O.set_vel(N, 0)
    particles, loads, previous = [], [], O
    for k in range(n):
        A = N.orientnew(f"A{k}", "Axis", [q[k], N.z])
        A.set_ang_vel(N, u[k] * N.z)
        P = previous.locatenew(f"P{k}", -l[k] * A.y)
        P.v2pt_theory(previous, N, A)
        particles.append(me.Particle(f"Pa{k}", P, m[k]))
        loads.append((P, -m[k] * g * N.y))
        previous = P
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[qi.diff() - ui for qi, ui in zip(q, u)])
    km.kanes_equations(particles, loads)
    plain = {f: sp.Symbol(f"s{i}") for i, f in enumerate(q + u)}
    exprs = [e.xreplace(plain) for e in list(km.mass_matrix) + list(km.forcing)]
    temps, reduced = sp.cse(exprs)
    return int(sum(sp.count_ops(e) for e in [v for _, v in temps] + reduced))


HAND_RHS = r"""
#include <math.h>
/* Hand-written double pendulum (point masses), p = [m1, m2, l1, l2, g]. */
int hand_rhs(double t, const double *y, const double *p, double *dydt)
{
    const double m1 = p[0], m2 = p[1], l1 = p[2], l2 = p[3], g = p[4];
    const double d = y[0] - y[1], s = sin(d), c = cos(d);
    const double w1 = y[2], w2 = y[3];
    const double den = m1 + m2 * s * s;
    (void)t;
    dydt[0] = w1;
    dydt[1] = w2;
    dydt[2] = (m2 * g * sin(y[1]) * c - m2 * s * (l1 * w1 * w1 * c + l2 * w2 * w2)
               - (m1 + m2) * g * sin(y[0])) / (l1 * den);
    dydt[3] = ((m1 + m2) * (l1 * w1 * w1 * s - g * sin(y[1]) + g * sin(y[0]) * c)
               + m2 * l2 * w2 * w2 * s * c) / (l2 * den);
    return 0;
}
"""

HARNESS = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int NAME_rhs(double t, const double *y, const double *p, double *dydt);
int hand_rhs(double t, const double *y, const double *p, double *dydt);
typedef int (*rhs_fn)(double, const double *, const double *, double *);

static double now(void) { struct timespec ts; clock_gettime(CLOCK_MONOTONIC, &ts); return ts.tv_sec + 1e-9 * ts.tv_nsec; }

static double time_loop(rhs_fn f, const double *states, const double *p, int nstate, long calls, double *sink)
{
    double dydt[64], start = now(), acc = 0.0;
    long i;
    for (i = 0; i < calls; ++i) {
        f(0.0, states + (i % STATES) * nstate, p, dydt);
        acc += dydt[nstate - 1];
    }
    *sink += acc;
    return (now() - start) / calls * 1e9;
}

int main(int argc, char **argv)
{
    int nstate = atoi(argv[1]), nparam = atoi(argv[2]), hand = atoi(argv[3]), i;
    long calls = atol(argv[4]);
    double *states = malloc(sizeof(double) * STATES * nstate), p[64], sink = 0.0;
    for (i = 0; i < STATES * nstate; ++i) states[i] = (double)rand() / RAND_MAX - 0.5;
    for (i = 0; i < nparam; ++i) p[i] = i + 1 == nparam ? 9.81 : 1.0;
    for (i = 0; i < REPEATS; ++i) {
        printf("%g", time_loop(NAME_rhs, states, p, nstate, calls, &sink));
        if (hand) printf(" %g", time_loop(hand_rhs, states, p, nstate, calls, &sink));
        printf("\n");
    }
    fprintf(stderr, "%g\n", sink);
    return 0;
}
"""


def c_times(d, directory: Path, repeats: int) -> tuple[float, float | None]:
    cc = shutil.which("cc")
    if cc is None:
        return float("nan"), None
    name = d.model.name
    for file, text in c_files(d, layout_of(d)).items():
        (directory / file).write_text(text)
    (directory / "hand.c").write_text(HAND_RHS)
    harness = HARNESS.replace("NAME", name).replace("STATES", str(STATES)).replace("REPEATS", str(repeats))
    (directory / "harness.c").write_text(harness)
    exe = directory / "bench"
    subprocess.run([cc, "-O2", "-o", str(exe), str(directory / f"{name}.c"), str(directory / "hand.c"),
                    str(directory / "harness.c"), "-lm"], check=True)
    hand = d.n == 2
    out = subprocess.run([str(exe), str(2 * d.n), str(len(d.model.parameters)), str(int(hand)), str(CALLS)],
                         check=True, capture_output=True, text=True).stdout.split("\n")
    rows = [list(map(float, line.split())) for line in out if line.strip()]
    generated = statistics.median(r[0] for r in rows)
    return generated, statistics.median(r[1] for r in rows) if hand else None


def cargo() -> str | None:
    found = shutil.which("cargo") or str(Path.home() / ".cargo" / "bin" / "cargo")
    return found if Path(found).exists() else None


def rust_time(d, directory: Path, repeats: int) -> float:
    """ns per call of the generated Rust right-hand side (nan without cargo)."""
    tool = cargo()
    if tool is None:
        return float("nan")
    crate = directory / "rust"
    for file, text in rust_files(d, layout_of(d)).items():
        (crate / file).parent.mkdir(parents=True, exist_ok=True)
        (crate / file).write_text(text)
    env = {**os.environ, "CARGO_TARGET_DIR": str(directory / "target")}
    subprocess.run([tool, "build", "--offline", "--release", "-q"], cwd=crate, env=env, check=True)
    rng = np.random.default_rng(1)
    nparam = len(d.model.parameters)
    p = [9.81 if i + 1 == nparam else 1.0 for i in range(nparam)]
    lines = "".join(" ".join(repr(float(v)) for v in [0.0, *rng.uniform(-0.5, 0.5, 2 * d.n), *p]) + "\n"
                    for _ in range(STATES))
    binary = directory / "target" / "release" / crate_name(d.model.name)
    times = []
    for _ in range(repeats):
        done = subprocess.run([str(binary), "--bench-rhs", str(CALLS)], input=lines, capture_output=True,
                              text=True, check=True)
        times.append(float(done.stderr.split("ns_per_call ")[1].split(",")[0]))
    return statistics.median(times)


def python_times(d, repeats: int) -> tuple[float, float]:
    module = types.ModuleType("generated")
    exec(compile(python_module(d, layout_of(d)), "generated", "exec"), module.__dict__)
    model, n = d.model, d.n
    args = (model.t, list(model.q + model.qd), list(model.parameter_symbols))
    both = sp.lambdify(args, [d.mass_matrix, d.forcing], modules="numpy", cse=True)

    def baseline(t, y, p):
        M, F = both(t, y, p)
        return np.concatenate((y[n:], np.linalg.solve(M, np.ravel(F))))

    rng = np.random.default_rng(1)
    states = [rng.uniform(-1, 1, 2 * n) for _ in range(200)]
    p = [v for _, v in sorted(((i, pi.value) for i, pi in enumerate(model.parameters)))]
    assert np.allclose(baseline(0.0, states[0], p), module.rhs(0.0, states[0], p))

    def per_call(f) -> float:
        start = time.perf_counter()
        for y in states:
            f(0.0, y, p)
        return (time.perf_counter() - start) / len(states) * 1e6

    generated = statistics.median(per_call(module.rhs) for _ in range(repeats))
    reference = statistics.median(per_call(baseline) for _ in range(repeats))
    return generated, reference


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, nargs="+", default=[2, 4, 8])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--no-tidy", action="store_true",
                        help="CSE of the expressions as derived, not tidied (tidy.py)")
    args = parser.parse_args()
    print(f"{'N':>2} | {'ops lagcli':>10} {'ops Kane':>9} {'ratio':>6} | {'C ns gen':>9} {'C ns hand':>9} "
          f"{'ratio':>6} | {'Rust ns':>8} {'Rust/C':>6} | {'Py us gen':>9} {'Py us lambdify':>14} {'ratio':>6} "
          f"| {'gen s':>6}")
    for n in args.links:
        with tempfile.TemporaryDirectory() as tmp:
            tmp = Path(tmp)
            (tmp / f"pendulum{n}.yaml").write_text(spec_text(n))
            d = derive(load_model(tmp / f"pendulum{n}.yaml"))
            start = time.perf_counter()
            if args.no_tidy:
                reduced = codegen.eliminate(codegen.collect(d, layout_of(d), tidy=False))
            else:
                _, reduced = codegen.reduced_outputs(d, layout_of(d))    # what the generated code evaluates
            ops = reduced.operation_count(("mass_matrix", "forcing"))
            generation = time.perf_counter() - start
            kane = kane_ops(n)
            c_gen, c_hand = c_times(d, tmp, args.repeats)
            rust = rust_time(d, tmp, args.repeats)
            py_gen, py_ref = python_times(d, args.repeats)
        hand = f"{c_hand:9.1f} {c_gen / c_hand:6.2f}" if c_hand else f"{'-':>9} {'-':>6}"
        print(f"{n:>2} | {ops:>10} {kane:>9} {ops / kane:6.2f} | {c_gen:9.1f} {hand} | "
              f"{rust:8.1f} {rust / c_gen:6.2f} | {py_gen:9.2f} {py_ref:14.2f} {py_gen / py_ref:6.2f} | {generation:6.2f}", flush=True)


if __name__ == "__main__":
    main()
