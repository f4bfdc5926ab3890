"""Reading a spec file's bytes safely: the one function every reader of a spec uses.

It is used by the YAML/TOML reader and by the warm C path of `simulate` (which
hashes the spec bytes to find a cached driver before anything else), so this
module imports nothing heavy: no yaml, sympy or numpy.

The path `-` is standard input (`lagcli derive - < spec.yaml`): read once, with the
size limit of a file, and kept, because one command may read its spec more than once
(the warm C path, then the System). Messages name it `<stdin>`.
"""
from __future__ import annotations

import os
import stat
import sys
from pathlib import Path

from lagcli.errors import Loc, Problem, SpecError

MAX_BYTES = 1 << 20
STDIN = "-"                 # the SPEC argument that means standard input
STDIN_NAME = "<stdin>"      # how messages name it
_stdin_bytes: tuple[object, bytes] | None = None     # (the stream, its bytes)


def read_spec_bytes(path: str | Path) -> bytes:
    """The bytes of the spec at `path`, read safely; every reader of a spec uses this.

    Only a regular file of at most `MAX_BYTES` is read: a FIFO, a device such as
    /dev/zero or a directory is refused before reading (the file is opened
    non-blocking, so a FIFO without a writer cannot stall the open, and the opened
    descriptor is checked, so a file swapped after the first look is caught too).
    `-` is standard input (see the module's docstring).
    Raises `SpecError`. Imports nothing heavy: the warm C path calls it.
    """
    name = str(path)
    if name == STDIN:
        return _read_stdin()
    try:
        _require_regular(name, os.stat(name).st_mode)
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except OSError as exc:
        hint = missing_spec_hint(name) if isinstance(exc, FileNotFoundError) else ""
        raise SpecError(Problem(Loc(name), f"cannot read the spec: {exc.strerror or exc}", hint)) from None
    try:
        _require_regular(name, os.fstat(fd).st_mode)
        with os.fdopen(fd, "rb", closefd=False) as stream:
            data = stream.read(MAX_BYTES + 1)
    except OSError as exc:
        raise SpecError(Problem(Loc(name), f"cannot read the spec: {exc.strerror or exc}")) from None
    finally:
        os.close(fd)
    if len(data) > MAX_BYTES:
        raise SpecError(Problem(Loc(name), "spec file is too large (the limit is 1 MiB)"))
    return data


def _require_regular(name: str, mode: int) -> None:
    if stat.S_ISREG(mode):
        return
    kind = ("a directory" if stat.S_ISDIR(mode) else "a named pipe (FIFO)" if stat.S_ISFIFO(mode)
            else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "a socket"
            if stat.S_ISSOCK(mode) else "not a regular file")
    raise SpecError(Problem(Loc(name), f"cannot read the spec: it is {kind}",
                            "a spec is a regular .yaml, .yml or .toml file"))


def _read_stdin() -> bytes:
    """Standard input's bytes (at most `MAX_BYTES` + 1 of them), read once per stream:
    kept with the stream they came from, so a new `sys.stdin` (a test runner's) is read."""
    global _stdin_bytes
    stream = sys.stdin
    if _stdin_bytes is None or _stdin_bytes[0] is not stream:
        try:
            _stdin_bytes = (stream, stream.buffer.read(MAX_BYTES + 1))
        except (OSError, ValueError, AttributeError) as exc:  # closed, or not a byte stream
            raise SpecError(Problem(Loc(STDIN_NAME), f"cannot read the spec: {exc}")) from None
    data = _stdin_bytes[1]
    if len(data) > MAX_BYTES:
        raise SpecError(Problem(Loc(STDIN_NAME), "spec text is too large (the limit is 1 MiB)"))
    return data


def missing_spec_hint(name: str) -> str:
    """For a spec file that does not exist but is named like a bundled example
    (`specs/cart_pole.yaml` typed outside the checkout): how to get the examples."""
    from lagcli.runtime.package_data import data_dir      # only on this error path: keeps the warm path light

    path = Path(name)
    bundled = data_dir("lagcli.specs", "specs")
    if not (bundled / path.name).is_file() or path.resolve() == (bundled / path.name).resolve():
        return ""
    folder = str(path.parent) if str(path.parent) != "." else "."
    return (f"'{path.stem}' is a bundled example, but it is not in {folder}/ here: "
            f"`lagcli examples --copy {folder}/` writes the examples there "
            f"(`lagcli examples {path.stem}` prints this one)")
