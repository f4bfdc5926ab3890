"""The C backend: compile the generated driver once, cache it, run it.

Cache: `lagcli.simulate.cache` (`$XDG_CACHE_HOME/lagcli/<key>/`, the compiler's
`--version` line as the key's variant), holding the driver binary `sim` and
`meta.json`.

`meta.json` is everything a warm run needs without sympy: state, parameter and
column names, the spec's `initial:` and `simulate:` values, whether the system is
constrained, and the spec's initial state already made consistent (with the
notes saying what was solved for).

This module imports neither sympy nor numpy: a warm run goes spec bytes -> key
-> meta.json -> driver, and the driver's output lines are passed through as CSV,
read from its pipe as they come and handed to a sink (lagcli.simulate.trajectory):
never collected whole.
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
from lagcli.simulate.trajectory import RowSink, Trajectory

CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic")
BINARY, META = "sim", "meta.json"
READ_SIZE = 1 << 16                   # bytes of driver output read at a time


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


def run(cached: Cached, args: list[str], progress=None, max_first_residual: float | None = None,
        sink: RowSink | None = None) -> RowSink | None:
    """Run the driver, passing its CSV through to `sink` (a new in-memory `Trajectory`
    when None) as it comes, and return the sink.  Returns None (and stops the driver,
    with nothing given to the sink) when `max_first_residual` is given and the first
    row's constraint_residual exceeds it."""
    sink = Trajectory() if sink is None else sink
    with tempfile.TemporaryFile("w+") as errors:
        proc = subprocess.Popen([str(cached.binary), *args], stdout=subprocess.PIPE, stderr=errors)
        try:
            accepted = _pass_through(proc.stdout, sink, progress, max_first_residual)
        except KeyboardInterrupt:
            sink.interrupted, accepted = True, True
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            proc.stdout.close()
        errors.seek(0)
        message = errors.read().strip()
    if not accepted:
        return None
    return sink if sink.interrupted else _finish(sink, proc.returncode, message)


def _pass_through(stdout, sink: RowSink, progress, limit: float | None) -> bool:
    """Give the driver's complete CSV lines to `sink` a pipe-full at a time (nothing is
    held but the line being received); False when the first row is rejected."""
    header = stdout.readline()
    if not header.endswith(b"\n"):
        return True                            # the driver died first: its status says why
    names = header.decode().rstrip("\n").split(",")
    pending = stdout.readline()
    if limit is not None and "constraint_residual" in names and pending.endswith(b"\n"):
        if not float(pending.split(b",")[names.index("constraint_residual")]) <= limit:
            return False
    sink.begin(names)
    while True:
        end = pending.rfind(b"\n") + 1
        if end:
            sink.add_csv(pending[:end].decode())
            pending = pending[end:]
            if progress is not None:
                progress(sink.last_time)
        chunk = stdout.read1(READ_SIZE)
        if not chunk:
            return True                        # a line cut off (the driver died mid-row) is dropped
        pending += chunk


def _finish(sink: RowSink, code: int, message: str) -> RowSink:
    if code == 0:
        return sink
    reason = message.removeprefix("error: ").strip() or f"the driver exited with status {code}"
    if code == 2:
        raise UsageError(f"the compiled driver rejected its options: {reason}")
    if code < 0:
        reason = f"the driver was killed by signal {-code}"
    sink.failure = reason
    return sink
