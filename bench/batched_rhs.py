"""Batched right-hand-side evaluations per second: the generated JAX module (jax.jit of
jax.vmap, CPU, float64) and the generated CasADi Function (`rhs.map(B)`) against the
generated C called in a loop, for the double pendulum and the planar 10-link chain.

    PYTHONPATH=. .venv/bin/python bench/batched_rhs.py [--batch 100000] [--repeats 5]

Every side evaluates the same B random states (uniform in [-1, 1]) at the spec's default
parameters and is timed in CPU seconds (`--clock cpu` of the other benchmarks): the C
harness by `clock()` around its loop over the B states, JAX and CasADi by
`time.process_time()` around one batched call (the CPU of every thread XLA uses, so a
multi-threaded run is not counted as faster than it is); jit compilation is done first
and reported apart. Prints the median of the repeats as evaluations per second and the
ratio JAX/C (nothing is asserted: machines are noisy). Needs cc, jax and casadi (a side
whose tool is missing prints nan).
"""
from __future__ import annotations

import argparse
import importlib.util
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import lagcli  # noqa: E402
from nlink import nlink_spec_text  # noqa: E402

HARNESS = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "NAME.h"

/* B states (n values a line on stdin) through NAME_rhs in a loop, REPEATS times:
   the CPU seconds of each pass on stdout. */
int main(int argc, char **argv)
{
    long batch = atol(argv[1]), i;
    int repeats = atoi(argv[2]), r, k;
    const int n = atoi(argv[3]);
    double *states = malloc(sizeof(double) * batch * n), *out = malloc(sizeof(double) * batch * n);
    double sink = 0.0;
    for (i = 0; i < batch * n; ++i)
        if (scanf("%lf", &states[i]) != 1) return 2;
    for (r = 0; r < repeats; ++r) {
        clock_t start = clock();
        for (i = 0; i < batch; ++i)
            NAME_rhs(0.0, states + i * n, NAME_parameter_defaults, out + i * n);
        printf("%.9g\n", (double)(clock() - start) / CLOCKS_PER_SEC);
        for (k = 0; k < n; ++k) sink += out[(batch - 1) * n + k];
    }
    fprintf(stderr, "%g\n", sink);
    return 0;
}
"""


def load_module(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def c_rate(system, states: np.ndarray, folder: Path, repeats: int) -> float:
    """Evaluations per CPU second of the generated C's `<name>_rhs` in a loop."""
    cc = shutil.which("cc")
    if cc is None:
        return float("nan")
    name = system.model.name
    system.generate("c", folder / "c")
    (folder / "c" / "harness.c").write_text(HARNESS.replace("NAME", name))
    exe = folder / "c" / "harness"
    subprocess.run([cc, "-std=c99", "-O2", "-o", str(exe), str(folder / "c" / f"{name}.c"),
                    str(folder / "c" / "harness.c"), "-lm"], check=True)
    text = "\n".join(" ".join(repr(float(v)) for v in row) for row in states)
    out = subprocess.run([str(exe), str(len(states)), str(repeats), str(states.shape[1])], input=text, capture_output=True,
                         text=True, check=True).stdout.split()
    return len(states) / statistics.median(float(v) for v in out)


def jax_rate(system, states: np.ndarray, folder: Path, repeats: int) -> tuple[float, float]:
    """(evaluations per CPU second of jit(vmap(rhs)), CPU seconds of its compilation)."""
    try:
        import jax
    except ImportError:
        return float("nan"), float("nan")
    jax.config.update("jax_enable_x64", True)
    path = folder / "model_jax.py"
    system.generate("jax", path)
    model = load_module(path, f"{system.model.name}_jax")
    batched = jax.jit(jax.vmap(model.rhs, in_axes=(None, 0, None)))
    y, p = jax.numpy.asarray(states), model.parameter_vector()
    start = time.process_time()
    batched(0.0, y, p).block_until_ready()
    compile_s = time.process_time() - start
    times = []
    for _ in range(repeats):
        start = time.process_time()
        batched(0.0, y, p).block_until_ready()
        times.append(time.process_time() - start)
    return len(states) / statistics.median(times), compile_s


def casadi_rate(system, states: np.ndarray, folder: Path, repeats: int) -> float:
    """Evaluations per CPU second of the CasADi Function `rhs.map(B)` on numbers."""
    try:
        import casadi  # noqa: F401
    except ImportError:
        return float("nan")
    path = folder / "model_casadi.py"
    system.generate("casadi", path)
    model = load_module(path, f"{system.model.name}_casadi")
    batched = model.rhs.map(len(states))
    y, p = states.T.copy(), model.parameter_vector()
    times = []
    for _ in range(repeats):
        start = time.process_time()
        batched(0.0, y, p, [])
        times.append(time.process_time() - start)
    return len(states) / statistics.median(times)


def systems(folder: Path):
    chain = folder / "nlink10.yaml"
    chain.write_text(nlink_spec_text(10))
    return [("double pendulum", ROOT / "specs" / "double_pendulum.yaml"), ("10-link chain", chain)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batch", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    rng = np.random.default_rng(1)
    print(f"batch {args.batch}, median of {args.repeats}, evaluations per CPU second "
          f"({os.cpu_count()} CPUs visible)")
    print(f"{'system':16} {'C loop':>12} {'JAX vmap':>12} {'CasADi map':>12} {'JAX/C':>7} {'jit s':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for label, spec in systems(Path(tmp)):
            folder = Path(tmp) / spec.stem
            folder.mkdir()
            system = lagcli.load(spec)
            states = rng.uniform(-1.0, 1.0, (args.batch, 2 * system.derivation.n))
            c = c_rate(system, states, folder, args.repeats)
            jx, compile_s = jax_rate(system, states, folder, args.repeats)
            ca = casadi_rate(system, states, folder, args.repeats)
            print(f"{label:16} {c:12.3e} {jx:12.3e} {ca:12.3e} {jx / c:7.2f} {compile_s:6.2f}")


if __name__ == "__main__":
    main()
