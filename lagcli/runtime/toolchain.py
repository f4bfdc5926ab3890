"""The C toolchain: find the compiler, ask its version once per process, compile.

Below both the run layer (the cached driver of `lagcli simulate` and sweeps) and the
FMU target (its shared library): neither imports the other for the compiler.

    find_compiler()        `cc` on PATH, or None
    Compiler               a found compiler with its `--version` line (asked once: `probe`)
    compile_program(...)   sources -> an executable or, with `shared`, a shared library

Compilation runs in its own process group, so an interruption stops all of it (cc,
cc1, as, ld) before the work directory is removed. No sympy, no numpy.
"""
from __future__ import annotations

import contextlib
import functools
import os
import shutil
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path

from lagcli.errors import SimulationError

CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic")
SHARED_FLAGS = ("-shared", "-fPIC")
COMPILE_SECONDS = 600                  # a bound, not a decision: a hung compiler is an error


@dataclass(frozen=True)
class Compiler:
    path: str
    version: str                       # `path` and the first line of `--version`: a cache key's variant


def find_compiler() -> str | None:
    return shutil.which("cc")


@functools.cache
def probe(path: str) -> Compiler:
    """The compiler at `path` with its version line, asked once per process."""
    try:
        done = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError) as exc:
        raise SimulationError(f"cannot run the C compiler {path!r}: {exc}") from None
    return Compiler(path, f"{path}\n{done.stdout.splitlines()[0] if done.stdout else ''}")


def compile_program(compiler: str, work: Path, sources: list[str], output: str, shared: bool = False) -> None:
    """Compile `sources` (in `work`) into `output` with lagcli's strict flags."""
    command = [compiler, *CFLAGS, *(SHARED_FLAGS if shared else ()), "-o", output, *sources, "-lm"]
    try:
        proc = subprocess.Popen(command, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, start_new_session=True)
    except OSError as exc:
        raise SimulationError(f"cannot run the C compiler {compiler!r}: {exc}") from None
    try:
        out, err = proc.communicate(timeout=COMPILE_SECONDS)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        if isinstance(exc, subprocess.TimeoutExpired):
            raise SimulationError(f"the C compiler {compiler!r} did not finish in {COMPILE_SECONDS} s") from None
        raise
    if proc.returncode != 0:
        log = "\n".join((err or out).strip().splitlines()[:40])
        raise SimulationError(f"the C compiler failed: {' '.join(command)}\n{log}")
