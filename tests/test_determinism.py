"""Same spec -> same bytes, for every output of `derive` (text, JSON, LaTeX) and of
`generate` in every language (Python, C, Octave, Rust, CasADi, JAX, LaTeX, and the FMU's zip, its
compiled binary included: zip entries carry a fixed date and cc is deterministic).

Each command runs in fresh processes, several at once while other processes keep the
CPU busy, each with its own PYTHONHASHSEED and an empty cache directory; every
run must write exactly the same bytes. (Output once depended on a wall-clock alarm
that stopped display tidying under load; nothing in lagcli may decide output by
time, hash order or machine.)
"""
from __future__ import annotations

import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

SPECS = Path(__file__).resolve().parent.parent / "specs"
CHOSEN = ("ex20_spinning_disk_double_pendulum", "rolling_disc")
SEEDS = ("0", "1", "4242")
COMMANDS = {
    "text": ["derive", "--text"],
    "json": ["derive", "--json"],
    "latex": ["derive", "--latex"],
    "latex-standalone": ["derive", "--latex", "--standalone"],
    "python": ["generate", "--lang", "python"],
    "c": ["generate", "--lang", "c"],
    "octave": ["generate", "--lang", "octave"],
    "rust": ["generate", "--lang", "rust"],
    "fmu": ["generate", "--lang", "fmu"],
    "casadi": ["generate", "--lang", "casadi"],
    "jax": ["generate", "--lang", "jax"],
    "latex-document": ["generate", "--lang", "latex"],
}
DIRECTORIES = ("c", "octave", "rust")   # -o names a folder; the others write one file
BURNERS = 2          # busy processes alongside the runs
PARALLEL = 4         # runs at once


def _run(spec: Path, name: str, seed: str, workdir: Path) -> dict[str, bytes]:
    """{file name: bytes} written by one command in a fresh process."""
    out = workdir / f"{spec.stem}-{name}-{seed}"
    out.mkdir()
    cache = workdir / f"cache-{spec.stem}-{name}-{seed}"
    args = [sys.executable, "-m", "lagcli", *COMMANDS[name][:1], str(spec), *COMMANDS[name][1:]]
    args += ["-o", str(out if name in DIRECTORIES else out / "output")]
    env = {**os.environ, "PYTHONHASHSEED": seed, "XDG_CACHE_HOME": str(cache)}
    done = subprocess.run(args, env=env, capture_output=True, timeout=900)
    assert done.returncode == 0, done.stderr.decode()
    return {str(path.relative_to(out)): path.read_bytes() for path in sorted(out.rglob("*")) if path.is_file()}


@pytest.fixture(scope="module")
def cpu_load():
    """Processes that keep the CPU busy while the runs compete with them."""
    burners = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(BURNERS)]
    yield
    for burner in burners:
        burner.kill()
        burner.wait()


@pytest.mark.parametrize("spec,seeds", [
    (CHOSEN[0], SEEDS[::2]),                      # the default run: two seeds, every output
    pytest.param(CHOSEN[0], SEEDS, marks=pytest.mark.slow),
    pytest.param(CHOSEN[1], SEEDS, marks=pytest.mark.slow),
])
def test_every_output_is_the_same_bytes_under_load_and_any_hash_seed(spec, seeds, tmp_path, cpu_load):
    path = SPECS / f"{spec}.yaml"
    jobs = [(name, seed) for name in COMMANDS for seed in seeds]
    with ThreadPoolExecutor(PARALLEL) as pool:
        outputs = list(pool.map(lambda job: _run(path, *job, tmp_path), jobs))
    by_command: dict[str, list] = {}
    for (name, seed), files in zip(jobs, outputs):
        by_command.setdefault(name, []).append((seed, files))
    for name, runs in by_command.items():
        (_, first), *others = runs
        assert first and all(first.values()), f"{name}: no output"
        for seed, files in others:
            assert files == first, f"{name}: PYTHONHASHSEED={seed} wrote different bytes"
