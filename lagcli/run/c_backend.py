"""The C backend: compile the generated driver once, cache it, run it.

Cache: `lagcli.run.cache` (`$XDG_CACHE_HOME/lagcli/<key>/`, the compiler's
`--version` line as the key's variant), holding the generated sources, the driver
binary `sim` and `meta.json`, all checked against the entry's manifest before the
driver runs (see that module for why that is enough).

`meta.json` is everything a warm run needs without sympy: the system's
`lagcli.interface.Layout` (its own JSON, `Layout.to_json`: states, parameters and
defaults, columns and their kinds, settings), the spec's `initial:` values, whether
the energy column is conserved, and the spec's initial state already made
consistent (with the notes saying what was solved for).

This module imports neither sympy nor numpy: a warm run goes spec bytes -> key
-> meta.json -> driver, and the driver's output lines are passed through as CSV,
read from its pipe as they come and handed to a sink (lagcli.run.rows):
never collected whole.
"""
from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from lagcli.errors import SimulationError, UsageError
from lagcli.interface import C_METHODS, VARIATIONAL, Layout
from lagcli.run import cache
from lagcli.run.options import RunSettings
from lagcli.run.rows import RowSink, Trajectory

CFLAGS = ("-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic")
BINARY, META = "sim", "meta.json"
META_TYPES = {"layout": str, "initial": dict, "energy_conserved": bool,
              "default_state": (list, type(None)), "default_notes": list}
READ_SIZE = 1 << 16                   # bytes of driver output read at a time


def find_compiler() -> str | None:
    return shutil.which("cc")


def require_compiler(method: str) -> str:
    """The C compiler for a run with `method`, or the error saying why there is none."""
    if method not in C_METHODS:
        raise UsageError(f"--method {method}: the C backend implements "
                         f"{', '.join(C_METHODS[:-1])} and {C_METHODS[-1]} only; use --backend python for {method}")
    compiler = find_compiler()
    if compiler is None:
        raise SimulationError("--backend c needs a C compiler, but 'cc' was not found on PATH "
                              "(install gcc or clang, or use --backend python)")
    return compiler


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
    """A verified cache entry holding a driver; `binary` is what to execute (see
    `lagcli.run.cache.Entry.program`)."""

    entry: cache.Entry
    meta: dict
    layout: Layout

    @property
    def binary(self) -> str:
        return self.entry.program


def lookup(key: str) -> Cached | None:
    """The driver cached under `key`, checked; None when missing or damaged (a damaged
    entry is noted on stderr and removed, so the caller's build replaces it)."""
    entry = cache.load(key, executable=BINARY)
    if entry is None:
        return None
    meta = _meta(entry.contents.get(META, b""))
    layout = _layout(meta)
    if layout is None:
        cache.note(f"cache entry {entry.directory} failed its integrity check ({META} lacks "
                   "values a run needs); rebuilding it")
        cache.discard(entry.directory)
        return None
    return Cached(entry, meta, layout)


def _meta(data: bytes) -> dict | None:
    """meta.json's values, or None unless it holds every key a warm run reads."""
    try:
        meta = json.loads(data)
    except (ValueError, UnicodeDecodeError):
        return None
    return meta if _complete(meta) else None


def _layout(meta: dict | None) -> Layout | None:
    try:
        return Layout.from_json(meta["layout"]) if meta is not None else None
    except (ValueError, KeyError, TypeError):
        return None


def _complete(meta) -> bool:
    return isinstance(meta, dict) and all(isinstance(meta.get(k), t) for k, t in META_TYPES.items())


def driver(system, compiler: str, laws: dict | None = None) -> Cached:
    """The compiled driver of `system` (a `lagcli.system.System`) from the cache,
    generating and compiling it (with meta.json) when it is not there. `laws` (input
    name -> sympy law; None for none): the model is generated with them substituted
    (`lagcli.hybrid.closed_loop`), so the law is C code of the driver, and part of its
    cache key: a cached driver is never reused for another law. A spec with laws never
    has a driver under the plain key, which the warm path looks up."""
    spec_bytes = system.spec_bytes
    if laws or system.model.laws:
        spec_bytes += ("\0laws:" + ";".join(f"{k}={v!s}" for k, v in sorted(laws.items()))).encode()
    key = cache_key(system.model.source, spec_bytes, compiler)
    cached = lookup(key)
    if cached is not None:
        return cached
    from lagcli.targets.c import c_files

    start, consistent = system.spec_start()
    d = system.derivation
    if laws:
        from lagcli.hybrid.closed_loop import closed_loop
        d = closed_loop(d, laws)
    meta = {
        "layout": system.layout.to_json(),
        "initial": dict(system.model.initial),
        "energy_conserved": system.energy_conserved,
        "default_state": list(start.values) if consistent else None,   # else only a repairing --init runs
        "default_notes": list(start.notes) if consistent else [],
    }
    return build(c_files(d, initial=start.values, initial_notes=start.notes), key, compiler, meta)


def build(files: dict[str, str], key: str, compiler: str, meta: dict) -> Cached:
    """Compile the generated C `files` (name -> text) into the cache under `key`."""
    layout = _layout(meta if _complete(meta) else None)
    if layout is None:                     # keeps META_TYPES in step with what `driver` writes
        raise SimulationError(f"lagcli bug: {META} needs {sorted(META_TYPES)}")
    try:
        with cache.new_entry(key) as work:
            for name, text in files.items():
                (work / name).write_text(text)
            _compile(compiler, work, sorted(name for name in files if name.endswith(".c")))
            (work / META).write_text(json.dumps(meta, indent=1))
            entry = cache.publish(work, key, f"{layout.name}: C driver", executable=BINARY)
    except OSError as exc:                 # a full disk, say: even the temporary directory failed
        raise SimulationError(f"the C driver could not be built and stored: {exc}") from None
    return Cached(entry, meta, layout)


def compile_library(compiler: str, work: Path, sources: list[str], output: str) -> None:
    """Compile `sources` (in `work`) into the shared library `output` (an FMU's binary)."""
    _compile(compiler, work, sources, output, ("-shared", "-fPIC"))


def _compile(compiler: str, work: Path, sources: list[str], output: str = BINARY, flags=()) -> None:
    """Run the compiler in its own process group, so that an interruption stops all of it
    (cc, cc1, as, ld) before the work directory is removed."""
    command = [compiler, *CFLAGS, *flags, "-o", output, *sources, "-lm"]
    try:
        proc = subprocess.Popen(command, cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True, start_new_session=True)
    except OSError as exc:
        raise SimulationError(f"cannot run the C compiler {compiler!r}: {exc}") from None
    try:
        out, err = proc.communicate(timeout=600)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        if isinstance(exc, subprocess.TimeoutExpired):
            raise SimulationError(f"the C compiler {compiler!r} did not finish in 600 s") from None
        raise
    if proc.returncode != 0:
        log = "\n".join((err or out).strip().splitlines()[:40])
        raise SimulationError(f"the C compiler failed: {' '.join(command)}\n{log}")


def driver_arguments(s: RunSettings, sets: dict[str, float], state: dict[str, float]) -> list[str]:
    args = ["--t-end", _num(s.t_end), "--dt", _num(s.dt), "--method", s.method,
            "--rtol", _num(s.rtol), "--atol", _num(s.atol), "--baumgarte", _num(s.alpha), _num(s.beta),
            "--max-steps", str(s.step_budget)]
    if s.method == VARIATIONAL:
        args += ["--steps-per-row", str(s.steps_per_row)]
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
    row's residual column (the layout's column of kind "residual") exceeds it."""
    sink = Trajectory() if sink is None else sink
    residual = [i for i, c in enumerate(cached.layout.columns) if c.kind == "residual"]
    check = (residual[0], max_first_residual) if residual and max_first_residual is not None else None
    with tempfile.TemporaryFile("w+") as errors:
        proc = subprocess.Popen([str(cached.binary), *args], stdout=subprocess.PIPE, stderr=errors)
        try:
            accepted = _pass_through(proc.stdout, sink, progress, check)
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


def _pass_through(stdout, sink: RowSink, progress, check: tuple[int, float] | None) -> bool:
    """Give the driver's complete CSV lines to `sink` a pipe-full at a time (nothing is
    held but the line being received); False when the first row fails `check`
    (column index, largest value)."""
    header = stdout.readline()
    if not header.endswith(b"\n"):
        return True                            # the driver died first: its status says why
    names = header.decode().rstrip("\n").split(",")
    pending = stdout.readline()
    if check is not None and pending.endswith(b"\n"):
        column, limit = check
        if not float(pending.split(b",")[column]) <= limit:
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
