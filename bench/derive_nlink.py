"""Derivation time of the planar N-link pendulum: lagcli against sympy.physics.mechanics.

Run:  python bench/derive_nlink.py [--max-n 20] [--lagranges-max 20] [--repeats 3] [--no-ops]

Prints, per N, the median wall time of lagcli's `derive` (spec parsing and model
building included), LagrangesMethod and KanesMethod (form_lagranges_equations /
kanes_equations, which is where their derivation happens), the ratios, and the
operation count of M and F after `cse` for lagcli and Kane. Same process, side by
side; LagrangesMethod is skipped above --lagranges-max because it grows to minutes.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))
from nlink import mechanics_nlink, nlink_spec_text  # noqa: E402

from lagcli.derive.pipeline import load_model  # noqa: E402
from lagcli.derive import derive  # noqa: E402


def time_lagcli(n: int, folder: Path):
    path = folder / f"nlink{n}.yaml"
    path.write_text(nlink_spec_text(n))
    start = time.perf_counter()
    d = derive(load_model(path))
    return time.perf_counter() - start, d


def time_lagranges(n: int) -> float:
    import sympy.physics.mechanics as me

    q, _, particles, loads, N = mechanics_nlink(n)
    start = time.perf_counter()
    L = me.Lagrangian(N, *particles)
    lm = me.LagrangesMethod(L, q, forcelist=loads, frame=N)
    lm.form_lagranges_equations()
    lm.mass_matrix, lm.forcing  # noqa: B018 (the properties do work)
    return time.perf_counter() - start


def time_kane(n: int):
    import sympy.physics.mechanics as me

    q, u, particles, loads, N = mechanics_nlink(n)
    start = time.perf_counter()
    kdes = [qi.diff() - ui for qi, ui in zip(q, u)]
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kdes)
    km.kanes_equations(particles, loads)
    M, F = km.mass_matrix, km.forcing
    return time.perf_counter() - start, M, F


def cse_ops(exprs) -> int:
    replacements, reduced = sp.cse(list(exprs))
    return sum(sp.count_ops(e) for _, e in replacements) + sum(sp.count_ops(e) for e in reduced)


def median_of(repeats: int, fn):
    runs = [fn() for _ in range(repeats)]
    times = [r[0] if isinstance(r, tuple) else r for r in runs]
    return statistics.median(times), runs[-1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--min-n", type=int, default=2)
    parser.add_argument("--max-n", type=int, default=20)
    parser.add_argument("--lagranges-max", type=int, default=20,
                        help="skip LagrangesMethod above this N (it takes minutes at N = 20)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-ops", dest="ops", action="store_false",
                        help="skip the operation counts of M and F after cse")
    args = parser.parse_args()
    print(f"{'N':>3} {'lagcli s':>9} {'Lagrange s':>10} {'Kane s':>8} {'Lag/lagcli':>10} "
          f"{'Kane/lagcli':>11}" + (f" {'ops lagcli':>10} {'ops Kane':>9}" if args.ops else ""))
    with tempfile.TemporaryDirectory() as tmp:
        for n in range(args.min_n, args.max_n + 1):
            t_ours, (_, d) = median_of(args.repeats, lambda: time_lagcli(n, Path(tmp)))
            t_kane, (_, M_k, F_k) = median_of(args.repeats, lambda: time_kane(n))
            t_lag = (statistics.median(time_lagranges(n) for _ in range(max(1, args.repeats // 2)))
                     if n <= args.lagranges_max else float("nan"))
            line = (f"{n:>3} {t_ours:>9.3f} {t_lag:>10.3f} {t_kane:>8.3f} {t_lag / t_ours:>10.1f} "
                    f"{t_kane / t_ours:>11.2f}")
            if args.ops:
                ours = cse_ops(list(d.mass_matrix) + list(d.forcing))
                kane = cse_ops(list(M_k) + list(F_k))
                line += f" {ours:>10} {kane:>9}"
            print(line, flush=True)


if __name__ == "__main__":
    main()
