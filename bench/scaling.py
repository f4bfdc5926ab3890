"""How lagcli scales with the size of a system: the planar N-link chain, N = 5 .. 100.

Run:  python bench/scaling.py [--n 5 10 20 40 70 100] [--kane-max 40] [--lagranges-max 10]
                              [--pinocchio] [--rhs-calls 20000] [--uncoupled 1000] > scaling.txt
      python bench/scaling.py --plot scaling.txt bench/scaling.png     # the picture of a run

Per N, each in a fresh process (imports included), CPU seconds (user + system of that
child, from os.wait4: the machine is shared, wall times mean little) and peak memory
(the child's maxrss):

- `lagcli derive --json` and `lagcli generate --lang c` of the chain as written by
  bench/codegen.py (positions as flat sums);
- the generated C right-hand side, compiled with the contract's rule
  (cc -std=c99 -O2 ...), microseconds of process CPU per call over 1024 random states;
- sympy.physics.mechanics building the same chain: KanesMethod (kanes_equations,
  mass_matrix, forcing) up to --kane-max, LagrangesMethod up to --lagranges-max;
- `lagcli check` of n uncoupled coordinates (--uncoupled, default 1 000: particles on
  springs, bench/codegen.py `uncoupled_spec`), after the table;
- with --pinocchio: Pinocchio's articulated-body algorithm (`pin.aba`) on an N-link
  planar chain of point masses, microseconds per call timed from Python (the binding's
  call overhead, measured on the 1-link chain, is printed with it).

Then the growth exponent of each lagcli command: the least-squares slope of log(cost)
against log(N) over every N measured. sympy's runs are bounded by --sympy-cpu seconds
of CPU each (prlimit; nan past it). Nothing is asserted (machines are noisy).
"""
from __future__ import annotations

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

MECHANICS = """
import sys
sys.path.insert(0, {here!r})
import sympy.physics.mechanics as me
from nlink import mechanics_nlink
q, u, particles, loads, N = mechanics_nlink({n})
if {method!r} == "lagrange":
    lm = me.LagrangesMethod(me.Lagrangian(N, *particles), q, forcelist=loads, frame=N)
    lm.form_lagranges_equations()
    lm.mass_matrix, lm.forcing
else:
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=[a.diff() - b for a, b in zip(q, u)])
    km.kanes_equations(particles, loads)
    km.mass_matrix, km.forcing
"""

HARNESS = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "NAME.h"
static double cpu(void) { struct timespec ts; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); return ts.tv_sec + 1e-9 * ts.tv_nsec; }
int main(int argc, char **argv)
{
    const int n = UPPER_NSTATE;
    long calls = argc > 1 ? atol(argv[1]) : 20000, k;
    double *states = malloc(sizeof(double) * 1024 * n), dydt[UPPER_NSTATE], sink = 0.0, best = 1e300;
    int i, r;
    for (i = 0; i < 1024 * n; ++i) states[i] = (double)rand() / RAND_MAX - 0.5;
    for (r = 0; r < 5; ++r) {
        double start = cpu(), each;
        for (k = 0; k < calls; ++k) { NAME_rhs(0.0, states + (k % 1024) * n, NAME_parameter_defaults, dydt); sink += dydt[n - 1]; }
        each = (cpu() - start) / calls;
        if (each < best) best = each;
    }
    printf("%.4f\n", best * 1e6);
    fprintf(stderr, "%g\n", sink);
    return 0;
}
"""

CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic"]


def child(args: list[str], cpu_limit: int | None = None) -> tuple[float, float]:
    """(CPU seconds, peak MB) of one child process, started by posix_spawn (a forked child
    would count this process's memory in its peak), output discarded; with `cpu_limit`,
    run under `prlimit --cpu` and (nan, nan) when it is killed there."""
    if cpu_limit is not None:
        args = [shutil.which("prlimit"), f"--cpu={cpu_limit}", *args]
    actions = [(os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
               (os.POSIX_SPAWN_OPEN, 2, os.devnull, os.O_WRONLY, 0)]
    pid = os.posix_spawn(args[0], args, dict(os.environ), file_actions=actions)
    _, status, usage = os.wait4(pid, 0)
    if status != 0 and cpu_limit is not None:
        return float("nan"), float("nan")
    if status != 0:
        raise SystemExit(f"failed ({status}): {' '.join(args)}")
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def rhs_microseconds(folder: Path, name: str, calls: int) -> float:
    (folder / "harness.c").write_text(HARNESS.replace("UPPER", name.upper()).replace("NAME", name))
    subprocess.run(["cc", *CFLAGS, "-c", f"{name}.c"], cwd=folder, check=True)     # the contract's rule
    subprocess.run(["cc", "-O2", "-o", "harness", f"{name}.o", "harness.c", "-lm"], cwd=folder, check=True)
    return float(subprocess.run(["./harness", str(calls)], cwd=folder, check=True, capture_output=True,
                                text=True).stdout)


def pinocchio_microseconds(n: int, calls: int = 20000) -> float:
    """pin.aba on a planar chain of n revolute joints with a point mass at each link's end."""
    import numpy as np
    import pinocchio as pin

    model = pin.Model()
    parent = 0
    for k in range(n):
        placement = pin.SE3(np.eye(3), np.array([0.0, -1.0, 0.0]) if k else np.zeros(3))
        parent = model.addJoint(parent, pin.JointModelRZ(), placement, f"j{k}")
        model.appendBodyToJoint(parent, pin.Inertia(1.0, np.array([0.0, -1.0, 0.0]), np.zeros((3, 3))),
                                pin.SE3.Identity())
    model.gravity.linear = np.array([0.0, -9.81, 0.0])
    data = model.createData()
    rng = np.random.default_rng(1)
    states = [(rng.uniform(-0.5, 0.5, n), rng.uniform(-0.5, 0.5, n)) for _ in range(256)]
    tau = np.zeros(n)
    best = math.inf
    for _ in range(5):
        start = time.process_time()
        for k in range(calls):
            q, v = states[k % 256]
            pin.aba(model, data, q, v, tau)
        best = min(best, (time.process_time() - start) / calls)
    return best * 1e6


def pinocchio_in_child(n: int) -> float:
    code = f"import sys; sys.path.insert(0, {str(HERE)!r}); import scaling; print(scaling.pinocchio_microseconds({n}))"
    return float(subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout)


def exponent(ns, values) -> float:
    """Least-squares slope of log(value) against log(N)."""
    xs, ys = [math.log(n) for n in ns], [math.log(v) for v in values]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def plot(table: Path, picture: Path) -> None:
    """Log-log picture of a printed table: command CPU seconds, and right-hand side microseconds."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [line.split() for line in table.read_text().splitlines() if line.split() and line.split()[0].isdigit()]
    columns = {name: k for k, name in ((1, "lagcli derive --json"), (3, "lagcli generate --lang c"),
                                       (6, "sympy KanesMethod"), (7, "sympy LagrangesMethod"),
                                       (5, "generated C rhs"), (8, "Pinocchio ABA (from Python)"))}
    figure, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    for name, k in columns.items():
        points = [(int(r[0]), float(r[k])) for r in rows if r[k] != "nan"]
        if points:
            axis = right if k in (5, 8) else left
            axis.loglog(*zip(*points), "o-", label=name)
    left.set(xlabel="links N", ylabel="CPU s (whole command, fresh process)", title="derivation")
    right.set(xlabel="links N", ylabel="us per call (CPU)", title="right-hand side")
    for axis in (left, right):
        axis.legend(fontsize=8)
        axis.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    figure.savefig(picture, dpi=100)


def spec_text(n: int) -> str:
    from codegen import spec_text as chain     # imported here: it loads lagcli (and, in a fork, its memory)

    return chain(n)


def uncoupled_text(n: int) -> str:
    from codegen import uncoupled_spec

    return uncoupled_spec(n)


def main() -> None:
    if sys.argv[1:2] == ["--plot"]:
        return plot(Path(sys.argv[2]), Path(sys.argv[3]))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[5, 10, 20, 40, 70, 100])
    parser.add_argument("--kane-max", type=int, default=40)
    parser.add_argument("--lagranges-max", type=int, default=10)
    parser.add_argument("--pinocchio", action="store_true")
    parser.add_argument("--rhs-calls", type=int, default=20000)
    parser.add_argument("--sympy-cpu", type=int, default=600, help="CPU seconds allowed to each sympy run")
    parser.add_argument("--uncoupled", type=int, nargs="*", default=[1000],
                        help="also `lagcli check` of this many uncoupled coordinates (issue 24: 1 000 <= 10 s)")
    args = parser.parse_args()
    have_cc = shutil.which("cc") is not None
    print(f"{'N':>4} {'derive s':>9} {'MB':>6} {'generate s':>10} {'MB':>6} {'C rhs us':>9} "
          f"{'Kane s':>8} {'Lagrange s':>10} {'pin aba us':>10}", flush=True)
    rows = []
    overhead = pinocchio_in_child(1) if args.pinocchio else float("nan")
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.n:
            spec = Path(tmp) / f"pendulum{n}.yaml"
            spec.write_text(spec_text(n))      # bench/codegen.py's chain: positions as flat sums
            lagcli = [sys.executable, "-m", "lagcli"]
            derive, derive_mb = child([*lagcli, "derive", str(spec), "--json", "-o", f"{tmp}/out{n}.json"])
            folder = Path(tmp) / f"c{n}"
            generate, generate_mb = child([*lagcli, "generate", str(spec), "--lang", "c", "-o", str(folder)])
            rhs = rhs_microseconds(folder, f"pendulum{n}", args.rhs_calls) if have_cc else float("nan")
            mechanics = [sys.executable, "-c"]
            kane = child([*mechanics, MECHANICS.format(here=str(HERE), n=n, method="kane")], args.sympy_cpu)[0] \
                if n <= args.kane_max else float("nan")
            lagrange = child([*mechanics, MECHANICS.format(here=str(HERE), n=n, method="lagrange")], args.sympy_cpu)[0] \
                if n <= args.lagranges_max else float("nan")
            aba = pinocchio_in_child(n) if args.pinocchio else float("nan")
            rows.append((n, derive, generate, rhs))
            print(f"{n:>4} {derive:>9.2f} {derive_mb:>6.0f} {generate:>10.2f} {generate_mb:>6.0f} {rhs:>9.3f} "
                  f"{kane:>8.2f} {lagrange:>10.2f} {aba:>10.3f}", flush=True)
        for n in args.uncoupled:
            spec = Path(tmp) / f"springs{n}.yaml"
            spec.write_text(uncoupled_text(n))
            seconds, mb = child([sys.executable, "-m", "lagcli", "check", str(spec)])
            print(f"check of {n} uncoupled coordinates (bench/codegen.py uncoupled_spec): "
                  f"{seconds:.2f} s, {mb:.0f} MB", flush=True)
    if args.pinocchio:
        print(f"pin.aba call overhead from Python (1-link chain): {overhead:.3f} us")
    if len(rows) >= 2:
        ns = [r[0] for r in rows]
        for k, what in ((1, "derive --json"), (2, "generate --lang c"), (3, "C rhs")):
            values = [r[k] for r in rows]
            steps = ", ".join(f"{a}-{b}: {exponent([a, b], [u, v]):.2f}"      # start-up hides the small N
                              for a, b, u, v in zip(ns, ns[1:], values, values[1:]))
            print(f"growth exponent of {what} (least squares, N = {ns[0]}..{ns[-1]}): "
                  f"{exponent(ns, values):.2f}; between neighbours: {steps}")


if __name__ == "__main__":
    main()
