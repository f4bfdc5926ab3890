"""A long fuzzing campaign: random specs through the real CLI, one subprocess each.

    .venv/bin/python tools/fuzz_campaign.py --examples 2000 --out fuzz-findings

Each input (from the strategies in tests/fuzz_specs.py) is written to a file and
run as `lagcli check` and `lagcli derive --json` in a fresh process limited to
10 seconds of CPU time (`--timeout`; CPU, not wall-clock time, so that a busy
machine does not turn slow starts into findings; the wall clock gets six times
as long as a backstop). A finding is a run that ends with a traceback, an exit
status other than 0 or 2, or one of those limits; its spec is saved as
`<out>/<kind>-<digest>.yaml` with the command and output beside it in
`<digest>.txt`, so it can be replayed with `lagcli check <file>` and turned into
a case of tests/data/bad/. The exit status is 1 when anything was found.

`--seed` picks the examples (the same seed gives the same inputs); the time limit
guards the campaign only: lagcli itself has no wall-clock limits, so a slow input
is a finding to fix with a deterministic budget, not a timeout to raise.
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
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from hypothesis import HealthCheck, given, seed, settings  # noqa: E402

from fuzz_specs import spec_texts  # noqa: E402

COMMANDS = (["check"], ["derive", "--json"])


def run_one(text: str, workdir: Path, timeout: float) -> tuple[str, str] | None:
    """(kind, report) of the first command that misbehaves on `text`, else None."""
    path = workdir / "fuzz.yaml"
    path.write_text(text, encoding="utf-8")
    for command in COMMANDS:
        argv = [sys.executable, "-m", "lagcli", *command, str(path)]
        try:
            done = subprocess.run(argv, capture_output=True, text=True, timeout=6 * timeout, cwd=workdir,
                                  env={**os.environ, "XDG_CACHE_HOME": str(workdir / "cache")},
                                  preexec_fn=lambda: _limit_cpu(timeout))
        except subprocess.TimeoutExpired:
            return "hang", f"{' '.join(command)}: no answer within {6 * timeout:g} s (wall clock)"
        if done.returncode in (-signal.SIGXCPU, -signal.SIGKILL):
            return "hang", f"{' '.join(command)}: more than {timeout:g} s of CPU time"
        if "Traceback" in done.stderr or done.returncode not in (0, 2):
            return "crash", f"{' '.join(command)}: exit {done.returncode}\n{done.stderr[-4000:]}"
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


def campaign(examples: int, out: Path, timeout: float, chosen_seed: int) -> int:
    found, seen = [], set()
    with tempfile.TemporaryDirectory() as directory:
        workdir = Path(directory)

        @seed(chosen_seed)
        @settings(max_examples=examples, deadline=None, database=None,
                  suppress_health_check=list(HealthCheck))
        @given(text=spec_texts())
        def one(text):
            if text in seen:  # Hypothesis may replay an example
                return
            seen.add(text)
            finding = run_one(text, workdir, timeout)
            if finding:
                found.append(save(out, text, *finding))
                print(f"{finding[0]}: {found[-1]}", flush=True)

        one()
    print(f"{examples} examples, {len(found)} findings" + (f" in {out}/" if found else ""))
    return 1 if found else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--examples", type=int, default=1000, help="how many specs to try")
    parser.add_argument("--out", type=Path, default=Path("fuzz-findings"), help="where findings go")
    parser.add_argument("--timeout", type=float, default=10.0, help="CPU seconds per command (a guard)")
    parser.add_argument("--seed", type=int, default=0, help="picks the examples")
    args = parser.parse_args()
    return campaign(args.examples, args.out, args.timeout, args.seed)


if __name__ == "__main__":
    sys.exit(main())
