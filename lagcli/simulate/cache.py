"""The cache of generated artefacts, shared by both backends.

`$XDG_CACHE_HOME/lagcli/<key>/` (default `~/.cache/lagcli`). The key is a SHA-256
of the spec file's bytes and name, the lagcli version, a variant (the C compiler's
`--version` line for a compiled driver, `python-module` for the generated Python
module) and a fingerprint (size, mtime) of lagcli's own source and templates — so
an edited spec, another compiler or another lagcli never reuses a stale entry.
Parameters and the initial state are *not* in the key: both backends take them at
run time.

This module imports neither sympy nor numpy (the warm C path uses it).
"""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

from lagcli import __version__

_SOURCE_ROOTS = (Path(__file__).resolve().parents[1], Path(__file__).resolve().parents[2] / "templates")


def cache_root() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "lagcli"


def cache_key(spec_path: str, spec_bytes: bytes, variant: str) -> str:
    digest = hashlib.sha256()
    for part in (spec_bytes, Path(spec_path).name.encode(), __version__.encode(),
                 variant.encode(), source_fingerprint().encode()):
        digest.update(len(part).to_bytes(8, "little"))
        digest.update(part)
    return digest.hexdigest()[:32]


def source_fingerprint() -> str:
    """Size and mtime of every lagcli source file and template (cheap: stat only)."""
    items = []
    for root in _SOURCE_ROOTS:
        for folder, dirs, files in os.walk(root):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for name in sorted(files):
                if name.endswith((".py", ".jinja", ".c", ".h")):   # .c, .h: the C runtime
                    st = os.stat(os.path.join(folder, name))
                    items.append(f"{name}:{st.st_size}:{st.st_mtime_ns}")
    return ";".join(items)
