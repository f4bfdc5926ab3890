"""A long fuzzing campaign: random specs through `lagcli check` and `lagcli derive --json`.

    .venv/bin/python tools/fuzz_campaign.py --examples 100000 --out fuzz-findings

Each input (from the strategies in tests/fuzz_specs.py: the whole spec language, frames,
rolling, dampers, units and inputs included) is written to a file and run through what
`lagcli check` and `lagcli derive --json` do, in this process (cheap: no interpreter start
per input). A finding is anything but success or a `LagcliError` whose message renders:
another exception (a traceback in the CLI), or more than `--timeout` seconds of CPU time
for one input (measured by the process's profiling timer, so a busy machine does not turn
slow inputs into findings). `--subprocess` runs the real CLI instead, one process per input
and command, exit status 0 or 2 required (slower; the same classes of finding).

Findings are grouped by class (the exception type and the lagcli line it came from); the
first spec of each class is saved as `<out>/<kind>-<digest>.yaml` with the report beside it
in `<digest>.txt`, so it can be replayed with `lagcli check <file>` and turned into a case
of tests/data/bad/. The run ends with the figures (inputs, CPU time, classes) and exits 1
when anything was found.

`--seed` picks the examples (the same seed gives the same inputs); the time limit guards
the campaign only: lagcli itself has no wall-clock limits, so a slow input is a finding to
fix with a deterministic budget, not a timeout to raise.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from hypothesis import HealthCheck, given, seed, settings  # noqa: E402

from fuzz_specs import spec_texts  # noqa: E402

COMMANDS = (["check"], ["derive", "--json"])
MEMORY = 3 << 30   # bytes of address space for the in-process campaign: a MemoryError is a finding


class CpuBudget(BaseException):
    """One input used more CPU time than the campaign allows (not an Exception: lagcli's
    and sympy's `except Exception` must not swallow it)."""


def _on_cpu_budget(signum, frame):
    raise CpuBudget


def run_in_process(text: str, workdir: Path, timeout: float) -> tuple[str, str, str] | None:
    """(kind, class, report) when `check` or `derive --json` misbehaves on `text`, else None."""
    from lagcli.commands import check_summary, derive_json
    from lagcli.errors import LagcliError

    path = workdir / "fuzz.yaml"
    path.write_text(text, encoding="utf-8")
    for name, command in (("check", check_summary), ("derive --json", derive_json)):
        signal.setitimer(signal.ITIMER_PROF, timeout)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                command(str(path))
        except LagcliError as exc:
            try:
                exc.render()
            except Exception as inner:  # noqa: BLE001 - the message itself failed
                return "crash", _class_of(inner), f"{name}: rendering the error failed\n{traceback.format_exc()}"
        except CpuBudget:
            return "hang", f"cpu in {_where(sys.exc_info()[2])}", f"{name}: more than {timeout:g} s of CPU time"
        except (Exception, RecursionError, MemoryError) as exc:  # noqa: BLE001 - a finding
            return "crash", _class_of(exc), f"{name}:\n{traceback.format_exc()[-6000:]}"
        finally:
            signal.setitimer(signal.ITIMER_PROF, 0)
    return None


def _where(tb) -> str:
    """The innermost lagcli frame of a traceback (file:line), else the innermost frame."""
    frames = traceback.extract_tb(tb)
    ours = [f for f in frames if "/lagcli/" in f.filename] or frames
    frame = ours[-1] if ours else None
    return f"{Path(frame.filename).name}:{frame.lineno}" if frame else "?"


def _class_of(exc: BaseException) -> str:
    return f"{type(exc).__name__} at {_where(exc.__traceback__)}"


def run_subprocess(text: str, workdir: Path, timeout: float) -> tuple[str, str, str] | None:
    """The same through the real CLI, one process per command, CPU-limited."""
    path = workdir / "fuzz.yaml"
    path.write_text(text, encoding="utf-8")
    for command in COMMANDS:
        argv = [sys.executable, "-m", "lagcli", *command, str(path)]
        try:
            done = subprocess.run(argv, capture_output=True, text=True, timeout=6 * timeout, cwd=workdir,
                                  env={**os.environ, "XDG_CACHE_HOME": str(workdir / "cache")},
                                  preexec_fn=lambda: _limit_cpu(timeout))
        except subprocess.TimeoutExpired:
            return "hang", "wall clock", f"{' '.join(command)}: no answer within {6 * timeout:g} s (wall clock)"
        if done.returncode in (-signal.SIGXCPU, -signal.SIGKILL):
            return "hang", "cpu", f"{' '.join(command)}: more than {timeout:g} s of CPU time"
        if "Traceback" in done.stderr or done.returncode not in (0, 2):
            last = done.stderr.strip().splitlines()[-1:] or ["?"]
            return "crash", last[0][:120], f"{' '.join(command)}: exit {done.returncode}\n{done.stderr[-4000:]}"
    return None


def _limit_cpu(seconds: float) -> None:
    limit = max(1, round(seconds))
    resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 5))


def save(out: Path, text: str, kind: str, report: str) -> Path:
    digest = hashlib.sha256(text.encode()).hexdigest()[:12]
    out.mkdir(parents=True, exist_ok=True)
    spec = out / f"{kind}-{digest}.yaml"
    spec.write_text(text, encoding="utf-8")
    (out / f"{kind}-{digest}.txt").write_text(report + "\n", encoding="utf-8")
    return spec


def campaign(examples: int, out: Path, timeout: float, chosen_seed: int, in_process: bool = True,
             every: int = 1000) -> int:
    classes: Counter = Counter()
    seen: set[int] = set()
    tried = [0]
    run = run_in_process if in_process else run_subprocess
    start = time.process_time()
    if in_process:
        signal.signal(signal.SIGPROF, _on_cpu_budget)
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))
    with tempfile.TemporaryDirectory() as directory:
        workdir = Path(directory)

        @seed(chosen_seed)
        @settings(max_examples=examples, deadline=None, database=None,
                  suppress_health_check=list(HealthCheck))
        @given(text=spec_texts())
        def one(text):
            key = hash(text)
            if key in seen:  # Hypothesis may replay an example
                return
            seen.add(key)
            tried[0] += 1
            finding = run(text, workdir, timeout)
            if finding:
                kind, where, report = finding
                classes[(kind, where)] += 1
                if classes[(kind, where)] == 1:
                    print(f"{kind} [{where}]: {save(out, text, kind, report)}", flush=True)
            if tried[0] % every == 0:
                print(f"... {tried[0]} inputs, {time.process_time() - start:.0f} s CPU, "
                      f"{len(classes)} classes", flush=True)

        one()
    seconds = time.process_time() - start
    print(f"{tried[0]} distinct inputs in {seconds:.0f} s of CPU time ({1000 * seconds / max(1, tried[0]):.1f} ms "
          f"each), {sum(classes.values())} findings in {len(classes)} classes"
          + (f" (specs in {out}/)" if classes else ""))
    for (kind, where), count in classes.most_common():
        print(f"  {count:6d}  {kind}: {where}")
    return 1 if classes else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--examples", type=int, default=1000, help="how many specs to try")
    parser.add_argument("--out", type=Path, default=Path("fuzz-findings"), help="where findings go")
    parser.add_argument("--timeout", type=float, default=10.0, help="CPU seconds per input (a guard)")
    parser.add_argument("--seed", type=int, default=0, help="picks the examples")
    parser.add_argument("--subprocess", action="store_true", help="run the real CLI, one process per input")
    args = parser.parse_args()
    return campaign(args.examples, args.out, args.timeout, args.seed, in_process=not args.subprocess)


if __name__ == "__main__":
    sys.exit(main())
