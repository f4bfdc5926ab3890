"""Whole commands, fresh processes, imports included: lagcli against sympy.physics.mechanics.

Run:  python bench/whole_command.py [--n 5 10 20 40] [--repeats 3] [--lagranges-max 10]
                                    [--formats json text latex c python check] [--clock wall|cpu]
                                    [--bicycle [--bicycle-spec specs/benchmark_bicycle.yaml]]
       python bench/whole_command.py --n --simulate specs/double_pendulum.yaml --clock cpu

For each planar N-link pendulum (bench/nlink.py) it times, each in a new Python
process (`python -m lagcli ...`, output to a temporary file): every `lagcli derive`
format, `lagcli check` and `lagcli generate` per language; and, also in new
processes, sympy.physics.mechanics building the same system: LagrangesMethod
(form_lagranges_equations + mass_matrix + forcing) and KanesMethod
(kanes_equations + mass_matrix + forcing). Medians of --repeats runs and the
ratios mechanics / lagcli are printed. With --bicycle the same lagcli commands run
on bench/specs/bicycle.yaml (bench/bicycle.py: 4 spatial bodies, 8 coordinates,
5 constraints), and the standalone LaTeX is compiled with pdflatex when present.
With --simulate SPEC it times `lagcli simulate SPEC` as a whole command: a first
run (an empty cache: the derivation, the C code, its compilation) and a warm run
(the cached driver), each with and without `--plot`. Nothing here is asserted in tests (machines are noisy).
"""
from __future__ import annotations

import argparse
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from nlink import nlink_spec_text  # noqa: E402

COMMANDS = {
    "json": ["derive", "{spec}", "--json", "-o", "{out}/out.json"],
    "text": ["derive", "{spec}", "--text", "-o", "{out}/out.txt"],
    "latex": ["derive", "{spec}", "--latex", "--standalone", "-o", "{out}/out.tex"],
    "check": ["check", "{spec}"],
    "python": ["generate", "{spec}", "--lang", "python", "-o", "{out}/out.py"],
    "c": ["generate", "{spec}", "--lang", "c", "-o", "{out}"],
}

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


CLOCK = "wall"      # --clock cpu: user + system CPU seconds of the child (steadier on a shared machine)


def timed(args: list[str]) -> float:
    start, before = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(args, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"failed: {' '.join(args)}\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu if CLOCK == "cpu" else elapsed


def lagcli_time(fmt: str, spec: Path, repeats: int) -> float:
    runs = []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as out:
            args = [a.format(spec=spec, out=out) for a in COMMANDS[fmt]]
            runs.append(timed([sys.executable, "-m", "lagcli", *args]))
    return statistics.median(runs)


def mechanics_time(method: str, n: int, repeats: int) -> float:
    code = MECHANICS.format(here=str(HERE), n=n, method=method)
    return statistics.median(timed([sys.executable, "-c", code]) for _ in range(repeats))


def nlink_table(ns, formats, repeats: int, lagranges_max: int, kane_max: int) -> None:
    print(f"{'N':>3} " + " ".join(f"{f:>8}" for f in formats)
          + f" {'Lagrange':>9} {'Kane':>8} {'Lag/json':>8} {'Kane/json':>9} {'latex/json':>10}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            spec = Path(tmp) / f"nlink{n}.yaml"
            spec.write_text(nlink_spec_text(n))
            ours = {f: lagcli_time(f, spec, repeats) for f in formats}
            lag = mechanics_time("lagrange", n, max(1, repeats // 2)) if n <= lagranges_max else float("nan")
            kane = mechanics_time("kane", n, repeats) if n <= kane_max else float("nan")
            base = ours.get("json", float("nan"))
            print(f"{n:>3} " + " ".join(f"{ours[f]:>8.2f}" for f in formats)
                  + f" {lag:>9.2f} {kane:>8.2f} {lag / base:>8.1f} {kane / base:>9.2f}"
                  + f" {ours.get('latex', float('nan')) / base:>10.2f}", flush=True)


def bicycle(formats, repeats: int, spec: Path) -> None:
    for fmt in formats:
        print(f"bicycle {fmt:>8}: {lagcli_time(fmt, spec, repeats):8.2f} s", flush=True)
    if shutil.which("pdflatex"):
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([sys.executable, "-m", "lagcli", "derive", str(spec), "--latex", "--standalone",
                            "-o", f"{out}/bicycle.tex"], check=True)
            start = time.perf_counter()
            subprocess.run(["pdflatex", "-interaction=nonstopmode", "bicycle.tex"], cwd=out,
                           capture_output=True, check=False)
            elapsed = time.perf_counter() - start
            pages = subprocess.run(["pdfinfo", f"{out}/bicycle.pdf"], capture_output=True, text=True).stdout
            count = next((line.split()[-1] for line in pages.splitlines() if line.startswith("Pages")), "?")
            print(f"bicycle pdflatex: {elapsed:8.2f} s, {count} pages", flush=True)


SIMULATE_CASES = (("first", False), ("first", True), ("warm", False), ("warm", True))


def simulate_table(spec: Path, repeats: int) -> None:
    """Whole `lagcli simulate` commands: first (empty cache) and warm, with and without --plot."""
    import os

    for kind, plot in SIMULATE_CASES:
        runs = []
        for _ in range(repeats):
            with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
                os.environ["XDG_CACHE_HOME"] = cache        # inherited by the timed child
                args = [sys.executable, "-m", "lagcli", "simulate", str(spec), "-o", f"{out}/out.csv"]
                extra = ["--plot", f"{out}/out.png"] if plot else []
                if kind == "warm":
                    subprocess.run(args, capture_output=True, check=True)    # fills the cache
                runs.append(timed(args + extra))
        label = f"simulate {kind}{' --plot' if plot else ''}"
        print(f"{label:>24}: {statistics.median(runs):8.3f} s", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="*", default=[5, 10, 20, 40], help="chain lengths (none: only --bicycle)")
    parser.add_argument("--formats", nargs="+", default=list(COMMANDS), choices=list(COMMANDS))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--lagranges-max", type=int, default=10,
                        help="skip LagrangesMethod above this N (minutes at N = 20)")
    parser.add_argument("--kane-max", type=int, default=40)
    parser.add_argument("--bicycle", action="store_true", help="also time bench/specs/bicycle.yaml")
    parser.add_argument("--bicycle-spec", default=str(HERE / "specs" / "bicycle.yaml"),
                        help="the bicycle-sized spec (e.g. specs/benchmark_bicycle.yaml, the Meijaard bicycle)")
    parser.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                        help="wall time, or the child's user + system CPU time (steadier under load)")
    parser.add_argument("--simulate", metavar="SPEC", default=None,
                        help="time `lagcli simulate SPEC`: first (empty cache) and warm, with and without --plot")
    args = parser.parse_args()
    global CLOCK
    CLOCK = args.clock
    if args.n:
        nlink_table(args.n, args.formats, args.repeats, args.lagranges_max, args.kane_max)
    if args.simulate:
        simulate_table(Path(args.simulate), args.repeats)
    if args.bicycle:
        bicycle(args.formats, args.repeats, Path(args.bicycle_spec))


if __name__ == "__main__":
    main()
