"""The C backend: compile the generated driver once, cache it, run it.

Cache: `lagcli.simulate.cache` (`$XDG_CACHE_HOME/lagcli/<key>/`, the compiler's
`--version` line as the key's variant), holding the driver binary `sim` and
`meta.json`.

`meta.json` is everything a warm run needs without sympy: state, parameter and
column names, the spec's `initial:` and `simulate:` values, whether the system is
constrained, and the spec's initial state already made consistent (with the
notes saying what was solved for).

This module imports neither sympy nor numpy: a warm run goes spec bytes -> key
-> meta.json -> driver, and the driver's output lines are passed through as CSV.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from lagcli import __version__
from lagcli.errors import SimulationError, UsageError
from lagcli.simulate import cache
from lagcli.simulate.cache import cache_root
from lagcli.simulate.options import RunSettings
from lagcli.simulate.trajectory import Trajectory

CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic")
BINARY, META = "sim", "meta.json"


def find_compiler() -> str | None:
    return shutil.which("cc")


def cache_key(spec_path: str, spec_bytes: bytes, compiler: str) -> str:
    return cache.cache_key(spec_path, spec_bytes, compiler_version(compiler))


def compiler_version(compiler: str) -> str:
    try:
        done = subprocess.run([compiler, "--version"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError) as exc:
        raise SimulationError(f"cannot run the C compiler {compiler!r}: {exc}") from None
    return f"{compiler}\n{done.stdout.splitlines()[0] if done.stdout else ''}"


@dataclass(frozen=True)
class Cached:
    directory: Path
    meta: dict

    @property
    def binary(self) -> Path:
        return self.directory / BINARY


def lookup(key: str) -> Cached | None:
    directory = cache_root() / key
    try:
        meta = json.loads((directory / META).read_text())
    except (OSError, ValueError):
        return None
    if not (directory / BINARY).is_file() or meta.get("lagcli") != __version__:
        return None
    return Cached(directory, meta)


def build(files: dict[str, str], key: str, compiler: str, meta: dict) -> Cached:
    """Compile the generated C `files` (name -> text) into the cache under `key`."""
    root = cache_root()
    root.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix=f".{key}.", dir=root))
    try:
        for name, text in files.items():
            (work / name).write_text(text)
        _compile(compiler, work, sorted(name for name in files if name.endswith(".c")))
        (work / META).write_text(json.dumps({**meta, "lagcli": __version__}, indent=1))
        try:
            os.rename(work, root / key)        # atomic; another run may have won the race
        except OSError:
            pass
    finally:
        shutil.rmtree(work, ignore_errors=True)
    cached = lookup(key)
    if cached is None:
        raise SimulationError(f"the compiled driver could not be stored in {root / key}")
    return cached


def _compile(compiler: str, work: Path, sources: list[str]) -> None:
    command = [compiler, *CFLAGS, "-o", BINARY, *sources, "-lm"]
    try:
        done = subprocess.run(command, cwd=work, capture_output=True, text=True, timeout=600)
    except (OSError, subprocess.SubprocessError) as exc:
        raise SimulationError(f"cannot run the C compiler {compiler!r}: {exc}") from None
    if done.returncode != 0:
        log = "\n".join((done.stderr or done.stdout).strip().splitlines()[:40])
        raise SimulationError(f"the C compiler failed: {' '.join(command)}\n{log}")


def driver_arguments(s: RunSettings, sets: dict[str, float], state: dict[str, float]) -> list[str]:
    args = ["--t-end", _num(s.t_end), "--dt", _num(s.dt), "--method", s.method,
            "--rtol", _num(s.rtol), "--atol", _num(s.atol), "--baumgarte", _num(s.alpha), _num(s.beta)]
    for option, values in (("--set", sets), ("--init", state)):
        for name, value in values.items():
            args += [option, f"{name}={_num(value)}"]
    return args


def _num(value: float) -> str:
    return format(float(value), ".17g")


def run(cached: Cached, args: list[str], progress=None, max_first_residual: float | None = None
        ) -> Trajectory | None:
    """Run the driver, passing its CSV through. Returns None (and stops the driver) when
    `max_first_residual` is given and the first row's constraint_residual exceeds it."""
    reader = _Reader(progress, max_first_residual)
    with tempfile.TemporaryFile("w+") as errors:
        proc = subprocess.Popen([str(cached.binary), *args], stdout=subprocess.PIPE, stderr=errors,
                                text=True, bufsize=1)
        try:
            reader.read(proc)
        except KeyboardInterrupt:
            reader.traj.interrupted = True
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            proc.stdout.close()
        errors.seek(0)
        message = errors.read().strip()
    if reader.rejected or reader.traj.interrupted:
        return None if reader.rejected else reader.traj
    return _finish(reader.traj, proc.returncode, message)


class _Reader:
    """Collects the driver's CSV lines as they come (so Ctrl-C keeps them)."""

    def __init__(self, progress, max_first_residual):
        self.progress, self.limit = progress, max_first_residual
        self.traj, self.rejected = Trajectory([]), False

    def read(self, proc) -> None:
        header = proc.stdout.readline()
        if not header.endswith("\n"):
            return
        self.traj.header = header.rstrip("\n").split(",")
        check = "constraint_residual" in self.traj.header and self.limit is not None
        column = self.traj.header.index("constraint_residual") if check else None
        for line in proc.stdout:
            if not line.endswith("\n"):
                return                         # cut off: the driver died mid-line
            line = line.rstrip("\n")
            if check and not self.traj.lines and not float(line.split(",")[column]) <= self.limit:
                self.rejected = True
                return
            self.traj.lines.append(line)
            if self.progress is not None:
                self.progress(float(line.split(",", 1)[0]))


def _finish(traj: Trajectory, code: int, message: str) -> Trajectory:
    if code == 0:
        return traj
    reason = message.removeprefix("error: ").strip() or f"the driver exited with status {code}"
    if code == 2:
        raise UsageError(f"the compiled driver rejected its options: {reason}")
    if code < 0:
        reason = f"the driver was killed by signal {-code}"
    traj.failure = reason
    return traj
