"""The C backend: a compiled driver in the cache, run with a run's settings and overrides.

Cache: `lagcli.run.cache` (`$XDG_CACHE_HOME/lagcli/<key>/`, the compiler's
`--version` line as the key's variant), holding the generated sources, the driver
binary `sim` and `meta.json`, all checked against the entry's manifest before the
driver runs (see that module for why that is enough).

`meta.json` is the system's run interface (`lagcli.interface.Layout.to_json`: states,
parameters and their units, columns, settings, the spec's `initial:`, the consistent
default state and its notes, which integrals exist): everything a warm run needs,
without sympy. The sources come from the System (the C target); this layer only
compiles them (`lagcli.runtime.toolchain`), stores and runs them.

This module imports neither sympy nor numpy: a warm run goes spec bytes -> key
-> meta.json -> driver, and the driver's output lines are passed through as CSV,
read from its pipe as they come and handed to a sink (lagcli.run.rows): never
collected whole. A spec with events (`Layout.events`) runs them in the driver
(lagcli/runtime/c/lagcli_events.c), which writes its log of raw records to a temporary
file (`--events`); the sink's `events` and `end_note` are read from it
(`lagcli.run.records.read_event_log`), so both backends print them alike.
"""
from __future__ import annotations

import os
import subprocess
import tempfile
from dataclasses import dataclass

from lagcli.errors import SimulationError, UsageError
from lagcli.interface import C_METHODS, VARIATIONAL, Layout, RunSettings
from lagcli.run import cache
from lagcli.run.records import read_event_log
from lagcli.run.rows import RowSink, Trajectory
from lagcli.runtime import toolchain

BINARY, META = "sim", "meta.json"
READ_SIZE = 1 << 16                   # bytes of driver output read at a time


def find_compiler() -> toolchain.Compiler | None:
    """The C compiler with its version (probed once per process), or None."""
    path = toolchain.find_compiler()
    return toolchain.probe(path) if path else None


def require_compiler(method: str) -> toolchain.Compiler:
    """The C compiler for a run with `method`, or the error saying why there is none."""
    if method not in C_METHODS:
        raise UsageError(f"--method {method}: the C backend implements "
                         f"{', '.join(C_METHODS[:-1])} and {C_METHODS[-1]} only; use --backend python for {method}")
    compiler = find_compiler()
    if compiler is None:
        raise SimulationError("--backend c needs a C compiler, but 'cc' was not found on PATH "
                              "(install gcc or clang, or use --backend python)")
    return compiler


def cache_key(spec_path: str, spec_bytes: bytes, compiler: toolchain.Compiler) -> str:
    return cache.cache_key(spec_path, spec_bytes, compiler.version)


@dataclass(frozen=True)
class CDriver:
    """A verified cache entry holding a driver, and the interface it was built for; `binary`
    is what to execute (see `lagcli.run.cache.Entry.program`)."""

    entry: cache.Entry
    layout: Layout

    @property
    def binary(self) -> str:
        return self.entry.program

    def run(self, settings: RunSettings, values: dict[str, float], state, sink=None, progress=None,
            max_first_residual: float | None = None) -> RowSink | None:
        """One run (the program protocol of the run layer: see lagcli.run.simulate)."""
        args = driver_arguments(settings, values, dict(zip(self.layout.state_names, state)))
        if not self.layout.events:
            return run(self, args, progress, max_first_residual, sink)
        with tempfile.TemporaryDirectory(prefix="lagcli-events-") as folder:
            log = os.path.join(folder, "events.log")
            done = run(self, [*args, "--events", log], progress, max_first_residual, sink)
            if done is not None and os.path.exists(log):
                with open(log, encoding="utf-8") as text:
                    done.events[:], done.end_note = read_event_log(text.read(), len(self.layout.states))
        return done


def lookup(key: str) -> CDriver | None:
    """The driver cached under `key`, checked; None when missing or damaged (a damaged
    entry is noted on stderr and removed, so the caller's build replaces it)."""
    entry = cache.load(key, executable=BINARY)
    if entry is None:
        return None
    layout = _layout(entry.contents.get(META, b""))
    if layout is None:
        cache.note(f"cache entry {entry.directory} failed its integrity check ({META} lacks "
                   "values a run needs); rebuilding it")
        cache.discard(entry.directory)
        return None
    return CDriver(entry, layout)


def _layout(data: bytes) -> Layout | None:
    """meta.json's layout, or None unless it is one with a default state."""
    try:
        layout = Layout.from_json(data)
    except (ValueError, KeyError, TypeError, UnicodeDecodeError):
        return None
    return layout if layout.start is not None else None


def build(files: dict[str, str], key: str, compiler: toolchain.Compiler, layout: Layout) -> CDriver:
    """Compile the generated C `files` (name -> text, the C target's) into the cache
    under `key`, with `layout` (which must hold its default state) as meta.json."""
    if layout.start is None:
        raise SimulationError("lagcli bug: the layout of a cached driver needs its default state")
    try:
        with cache.new_entry(key) as work:
            for name, text in files.items():
                (work / name).write_text(text)
            toolchain.compile_program(compiler.path, work, sorted(n for n in files if n.endswith(".c")), BINARY)
            (work / META).write_text(layout.to_json())
            entry = cache.publish(work, key, f"{layout.name}: C driver", executable=BINARY)
    except OSError as exc:                 # a full disk, say: even the temporary directory failed
        raise SimulationError(f"the C driver could not be built and stored: {exc}") from None
    return CDriver(entry, layout)


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


def run(cached: CDriver, args: list[str], progress=None, max_first_residual: float | None = None,
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
