"""Compiled templates kept between commands, under the cache's trust rules (`lagcli.run.cache`).

Jinja compiles each template it loads (lexing, parsing, Python code generation and
`compile`): 0.12 s of CPU for `c/model.c.jinja`, ~0.2 s of every `generate --lang c`,
0.1 s of `derive --text` (bench/README.md, "compiled templates"). Jinja's own remedy, a
bytecode cache, unmarshals code objects from files; whoever can write those files runs
code in lagcli. So each template's code is an entry of the cache's kind, read only through
`cache.load`: a private root of the user, private files, the manifest's SHA-256 checked
before the bytes are unmarshalled (and they are the bytes that were checked).

The entries live in their own root, `$XDG_CACHE_HOME/lagcli-templates/` (beside the run
cache's `lagcli/`, whose entries are one per spec and backend: `lagcli cache info` counts
those; `lagcli cache clear` removes both). An entry's key is the SHA-256 of the template's
name and file, its source's checksum, Jinja's bytecode format (its version and Python's)
and lagcli's version: an edited template, another Jinja or another Python never reuses a
stale entry (Jinja checks the format and checksum again when it reads the code).

A root that is not safe (`cache.root_problem`) is not used, silently: the templates are
then compiled as before, and nothing is written. A cache that cannot be written makes a
slower command, never a failed one. Output does not depend on the cache: the code is the
same whether compiled now or read back.
"""
from __future__ import annotations

import contextlib
from pathlib import Path

import jinja2
from jinja2.bccache import bc_magic

from lagcli.run import cache
from lagcli.version import __version__

CODE = "template.code"           # the one file of an entry: the bucket's bytes
LABEL = "compiled template"


def template_root() -> Path:
    """`$XDG_CACHE_HOME/lagcli-templates` (default `~/.cache/lagcli-templates`)."""
    return cache.cache_root().with_name("lagcli-templates")


def usable_root() -> Path | None:
    """The root when it is safe to use (made if missing, never where others may write), else None."""
    root = template_root()
    if not root.is_dir() and cache.existing_parents_problem(root) is not None:
        return None
    return root if cache.root_problem(root) is None else None


class TemplateCache(jinja2.BytecodeCache):
    """Jinja's bytecode cache, stored as entries of `lagcli.run.cache`."""

    def load_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        root = usable_root()
        if root is None:
            return
        entry = cache.load(entry_key(bucket), root=root)
        if entry is not None and CODE in entry.contents:
            bucket.bytecode_from_string(entry.contents[CODE])     # Jinja resets it if stale

    def dump_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        root = usable_root()
        if root is None:
            return
        key = entry_key(bucket)
        with contextlib.suppress(OSError):
            with cache.new_entry(key, root=root) as work:
                (work / CODE).write_bytes(bucket.bytecode_to_string())
                cache.publish(work, key, LABEL)


def entry_key(bucket: jinja2.bccache.Bucket) -> str:
    return cache.digest(*(part.encode() for part in (bucket.key, bucket.checksum, bc_magic.hex(), __version__)))

