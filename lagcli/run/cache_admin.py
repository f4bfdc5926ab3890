"""`lagcli cache info` and `lagcli cache clear`: what the cache of
`lagcli.run.cache` holds, and removing lagcli's entries (only those).

Only directories named like an entry (32 hex digits) or like a work directory of
an interrupted build (`.<key>.*`), owned by the user and not symlinks, are counted
or removed; anything else in the directory is left alone.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import stat
from dataclasses import dataclass
from pathlib import Path

from lagcli.run import cache, template_cache


@dataclass(frozen=True)
class EntryInfo:
    key: str
    label: str
    size: int
    intact: bool


@dataclass(frozen=True)
class CacheInfo:
    root: Path
    problem: str | None                    # why the root is not used (None: it is used)
    entries: tuple[EntryInfo, ...]
    leftovers: int                         # work directories of interrupted runs (size included)
    size: int
    templates: int = 0                     # compiled templates (`lagcli.run.template_cache`)
    templates_size: int = 0


def info() -> CacheInfo:
    """What the cache holds, without changing it."""
    root = cache.cache_root()
    problem = cache.root_problem(root, create=False)
    entries, leftovers, size = [], 0, 0
    for name, path in _own_directories(root):
        size += _size(path)
        if cache.ENTRY_NAME.fullmatch(name):
            entries.append(_entry_info(path, name))
        else:
            leftovers += 1
    templates = _own_directories(template_cache.template_root())
    return CacheInfo(root, problem, tuple(entries), leftovers, size,
                     len(templates), sum(_size(path) for _, path in templates))


def clear() -> tuple[int, int, int]:
    """Remove lagcli's entries and leftover work directories (the user's own only, nothing
    else in the directory), and the compiled templates. Returns (directories removed, bytes
    freed) of the run cache and the number of compiled templates removed."""
    removed, freed = _remove(cache.cache_root())
    templates, _ = _remove(template_cache.template_root())
    return removed, freed, templates


def _remove(root: Path) -> tuple[int, int]:
    """Remove the user's entry and work directories of `root`: (how many, bytes freed)."""
    removed = freed = 0
    for _, path in _own_directories(root):
        size = _size(path)
        shutil.rmtree(path, ignore_errors=True)
        if not os.path.lexists(path):
            removed, freed = removed + 1, freed + size
    return removed, freed


def _own_directories(root: Path) -> list[tuple[str, Path]]:
    """The entry and work directories in `root` that belong to the user (no symlinks)."""
    try:
        names = sorted(os.listdir(root)) if os.path.isdir(root) else []
    except OSError:
        return []
    found = []
    for name in names:
        if cache.ENTRY_NAME.fullmatch(name) or cache.LEFTOVER_NAME.fullmatch(name):
            st = os.lstat(root / name)
            if stat.S_ISDIR(st.st_mode) and st.st_uid == os.geteuid():
                found.append((name, root / name))
    return found


def _entry_info(path: Path, key: str) -> EntryInfo:
    try:
        return EntryInfo(key, cache.read_entry(path, key, None).label, _size(path), True)
    except (cache.DamagedEntry, OSError):
        return EntryInfo(key, "", _size(path), False)


def _size(path: Path) -> int:
    total = 0
    for folder, _, files in os.walk(path):
        for name in files:
            with contextlib.suppress(OSError):
                total += os.lstat(os.path.join(folder, name)).st_size
    return total


def describe(summary: CacheInfo) -> str:
    """`lagcli cache info` as text."""
    usable = "yes" if summary.problem is None else f"no: {summary.problem} (runs build in a temporary directory)"
    lines = [f"cache directory: {summary.root}", f"usable: {usable}",
             f"entries: {len(summary.entries)}, {human_size(summary.size)} in total"]
    for e in summary.entries:
        state = (e.label or "?") if e.intact else "damaged: rebuilt on next use"
        lines.append(f"  {e.key}  {human_size(e.size):>9}  {state}")
    if summary.leftovers:
        lines.append(f"left over by interrupted runs: {summary.leftovers} work directories "
                     "(`lagcli cache clear` removes them)")
    if summary.templates:
        lines.append(f"compiled templates: {summary.templates}, {human_size(summary.templates_size)} "
                     f"in {template_cache.template_root()}")
    return "\n".join(lines) + "\n"


def describe_cleared(removed: int, freed: int, templates: int = 0) -> str:
    """`lagcli cache clear` as text."""
    text = f"removed {removed} cache directories ({human_size(freed)}) from {cache.cache_root()}\n"
    if templates:
        text += f"removed {templates} compiled templates from {template_cache.template_root()}\n"
    return text


def human_size(size: int) -> str:
    if size < 1000:
        return f"{size} B"
    return f"{size / 1e3:.1f} kB" if size < 1e6 else f"{size / 1e6:.1f} MB"
