"""Where lagcli writes its output (`-o`, `--plot`), decided before any work starts.

    -o - or no -o          stdout
    a regular file, or     a temporary file `.NAME.<random>.lagcli.tmp` in the file's own
    a path not there yet   directory, renamed over NAME when done: the old file stays whole
                           until then; an existing file keeps its mode (and owner, where
                           the user may set it)
    a symlink              the file it points to is the one replaced (the link stays)
    a FIFO, a device       opened and written as a stream (/dev/null stays a device)
    /dev/stdout, /dev/fd/N always a stream, written through this process's own descriptor
    /proc/self/fd/N        (a duplicate: a file stdout is redirected to keeps its offset)
    a directory, a path    UsageError (exit status 2) naming the path, before any work
    in a missing or
    unwritable directory

`open_output` resolves and opens the target (so a bad `-o` fails before deriving or
integrating) and yields an `Output` whose `stream` is written as the work goes on.
Leaving the `with` block normally commits (the rename); an exception discards the
temporary file, and lagcli.runtime.interrupts turns SIGTERM and SIGHUP into that exception
too.  Only `kill -9` can leave a temporary file behind; it is recognisable by the
`.lagcli.tmp` suffix (docs/simulate.md).
"""
from __future__ import annotations

import contextlib
import os
import re
import stat
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from lagcli.errors import UsageError
from lagcli.runtime.interrupts import uninterruptible

TEMP_SUFFIX = ".lagcli.tmp"
STDOUT, FILE, STREAM = "stdout", "file", "stream"
_DESCRIPTOR_ALIASES = re.compile(r"/dev/(stdout|stderr|fd/(?P<fd>\d+))|/proc/(?P<pid>self|\d+)/fd/(?P<n>\d+)")


@dataclass(frozen=True)
class Target:
    """Where an output goes: `kind` STDOUT, FILE (replaced atomically: `path` is the
    resolved regular file) or STREAM (`path` is opened and written in place)."""

    given: str
    kind: str
    path: Path | None = None
    existing: os.stat_result | None = None     # the FILE being replaced, if it exists


def resolve_target(path: str | os.PathLike | None) -> Target:
    """The `Target` of an output path, or a UsageError naming it when it cannot be written."""
    if path is None or str(path) == "-":
        return Target("-", STDOUT)
    given = str(path)
    if _DESCRIPTOR_ALIASES.fullmatch(given):
        return Target(given, STREAM, Path(given))
    try:
        info = os.stat(given)                  # follows symlinks
    except FileNotFoundError:
        info = None
    except OSError as exc:
        raise _cannot_write(given, exc) from None
    if info is not None and stat.S_ISDIR(info.st_mode):
        raise UsageError(f"cannot write {given}: it is a directory (give a file name)")
    if info is not None and not stat.S_ISREG(info.st_mode):
        return Target(given, STREAM, Path(given))
    real = Path(os.path.realpath(given))       # a symlink: replace what it points to
    _check_directory(given, real.parent)
    return Target(given, FILE, real, info)


def check_directory_output(path: str) -> Path:
    """`-o DIR` of a command writing several files: DIR is an existing directory, or
    a new one whose parent exists (it is created when the files are written)."""
    directory = Path(path)
    if directory.exists() and not directory.is_dir():
        raise UsageError(f"cannot write into {path}: not a directory")
    _check_directory(path, directory if directory.is_dir() else directory.absolute().parent)
    return directory


def _check_directory(given: str, directory: Path) -> None:
    if not directory.is_dir():
        raise UsageError(f"cannot write {given}: the directory {directory} does not exist "
                         "(create it first)")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise UsageError(f"cannot write {given}: the directory {directory} is not writable")


def _cannot_write(given: str, exc: OSError) -> UsageError:
    return UsageError(f"cannot write {given}: {exc.strerror or exc}")


class Output:
    """An opened `Target`: write to `stream` (text, or bytes when `binary`), then
    `commit()` (flush / close / rename into place) or `discard()` (the temporary
    file is removed; a stream keeps what it received)."""

    def __init__(self, target: Target, binary: bool = False):
        self.target, self._temporary, self.stream = target, None, None
        try:
            self.stream = self._open(binary)
        except OSError as exc:
            raise _cannot_write(target.given, exc) from None

    def _open(self, binary: bool):
        if self.target.kind == STDOUT:
            return sys.stdout.buffer if binary else sys.stdout
        mode, encoding = ("wb", None) if binary else ("w", "utf-8")
        if self.target.kind == STREAM:
            descriptor = _own_descriptor(self.target.given)
            return open(self.target.path if descriptor is None else descriptor, mode, encoding=encoding)
        path = self.target.path
        with uninterruptible:                  # the temporary file is always known, to be removed
            fd, self._temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=TEMP_SUFFIX, dir=path.parent)
        try:
            _copy_permissions(fd, self.target.existing)
            return open(fd, mode, encoding=encoding)
        except BaseException:
            os.close(fd)
            self.discard()
            raise

    def commit(self) -> None:
        try:
            if self.target.kind == STDOUT:
                self.stream.flush()
                return
            with uninterruptible:
                self.stream.close()
                if self._temporary is not None:
                    os.replace(self._temporary, self.target.path)
                    self._temporary = None
        except OSError as exc:
            self.discard()
            raise _cannot_write(self.target.given, exc) from None

    def discard(self) -> None:
        if self.stream is not None and self.target.kind != STDOUT:
            with contextlib.suppress(OSError):
                self.stream.close()
        if self._temporary is not None:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self._temporary)
            self._temporary = None

    def __enter__(self) -> "Output":
        return self

    def __exit__(self, kind, value, trace) -> None:
        if kind is None:
            self.commit()
        else:
            self.discard()


def _own_descriptor(given: str) -> int | None:
    """A duplicate of this process's descriptor that `given` names (/dev/stdout, /dev/fd/3,
    /proc/self/fd/3...), or None: writing through it shares the descriptor's file offset,
    where opening the path anew would truncate a file that stdout is redirected to."""
    match = _DESCRIPTOR_ALIASES.fullmatch(given)
    if match is None or match["pid"] not in (None, "self", str(os.getpid())):
        return None
    number = {"/dev/stdout": 1, "/dev/stderr": 2}.get(given) or int(match["fd"] or match["n"])
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, OSError, ValueError):
            stream.flush()                     # what this process wrote there comes first
    return os.dup(number)


def _copy_permissions(fd: int, existing: os.stat_result | None) -> None:
    """mkstemp makes 0600: give the new file the replaced file's mode and owner, or the
    mode of a new file (0666 minus the umask)."""
    if existing is None:
        os.fchmod(fd, 0o666 & ~_umask())
        return
    mine = os.fstat(fd)
    if (existing.st_uid, existing.st_gid) != (mine.st_uid, mine.st_gid):
        try:
            os.fchown(fd, existing.st_uid, existing.st_gid)
        except PermissionError:                # only root may give files away
            with contextlib.suppress(PermissionError):
                os.fchown(fd, -1, existing.st_gid)
    os.fchmod(fd, stat.S_IMODE(existing.st_mode))


def open_output(path: str | os.PathLike | None, binary: bool = False) -> Output:
    """`Output(resolve_target(path))`: use it as `with open_output(path) as out:`."""
    return Output(resolve_target(path), binary)


def write_output(path: str | os.PathLike | None, data: str | bytes) -> None:
    """Write `data` to `path` (see the module docstring); stdout for None or '-'."""
    with open_output(path, binary=isinstance(data, bytes)) as out:
        out.stream.write(data)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask

