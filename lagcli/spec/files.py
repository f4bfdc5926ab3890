"""Reading a spec file's bytes safely: the one function every reader of a spec uses.

It is used by the YAML/TOML reader and by the warm C path of `simulate` (which
hashes the spec bytes to find a cached driver before anything else), so this
module imports nothing heavy: no yaml, sympy or numpy.
"""
from __future__ import annotations

import os
import stat
from pathlib import Path

from lagcli.errors import Loc, Problem, SpecError

MAX_BYTES = 1 << 20


def read_spec_bytes(path: str | Path) -> bytes:
    """The bytes of the spec at `path`, read safely; every reader of a spec uses this.

    Only a regular file of at most `MAX_BYTES` is read: a FIFO, a device such as
    /dev/zero or a directory is refused before reading (the file is opened
    non-blocking, so a FIFO without a writer cannot stall the open, and the opened
    descriptor is checked, so a file swapped after the first look is caught too).
    Raises `SpecError`. Imports nothing heavy: the warm C path calls it.
    """
    name = str(path)
    try:
        _require_regular(name, os.stat(name).st_mode)
        fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except OSError as exc:
        raise SpecError(Problem(Loc(name), f"cannot read the spec: {exc.strerror or exc}")) from None
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
