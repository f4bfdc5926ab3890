"""The bundled example specs (`specs/` in a checkout, `lagcli.specs` when installed).

`lagcli examples` lists them with the first sentence of their opening comment, prints
one, or copies them all into a folder, so a user of a plain `pip install` has the same
worked examples as a checkout.
"""
from __future__ import annotations

import shutil
from pathlib import Path

from lagcli.errors import UsageError
from lagcli.runtime.package_data import data_dir

SUFFIXES = (".yaml", ".yml", ".toml")
HYBRID = "hybrid"       # specs with events or input laws (which not every code target takes yet)


def examples_dir() -> Path:
    """The folder holding the bundled specs (installed package data, else the checkout's)."""
    return data_dir("lagcli.specs", "specs")


def example_paths() -> list[Path]:
    """Every bundled spec (those of the `hybrid/` folder too), sorted by name."""
    folder = examples_dir()
    paths = [p for where in (folder, folder / HYBRID) if where.is_dir()
             for p in where.iterdir() if p.suffix in SUFFIXES]
    return sorted(paths, key=lambda p: p.name)


def summary(path: Path) -> str:
    """A bundled spec's `description:` line (every bundled spec has one)."""
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("description:"):
            return line.partition(":")[2].strip()
    return ""


def find(name: str) -> Path:
    """The bundled spec called `name` (with or without its suffix)."""
    for path in example_paths():
        if name in (path.stem, path.name):
            return path
    from lagcli.spec.checker import did_you_mean

    known = [p.stem for p in example_paths()]
    guess = did_you_mean(name, known)
    raise UsageError(f"no bundled example called {name!r}\n"
                     f"  hint: {guess + ' ' if guess else ''}the examples are: {', '.join(known)}")


def listing() -> str:
    """One line per example: name and description."""
    paths = example_paths()
    width = max(len(p.stem) for p in paths)
    return "".join(f"{p.stem:<{width}}  {summary(p)}\n" for p in paths)


def copy_all(folder: str) -> list[Path]:
    """Copy every bundled spec into `folder` (created if missing); existing files are kept."""
    target = Path(folder)
    if target.exists() and not target.is_dir():
        raise UsageError(f"--copy {folder}: not a directory")
    target.mkdir(parents=True, exist_ok=True)
    written = []
    for path in example_paths():
        destination = target / path.name
        if not destination.exists():
            shutil.copyfile(path, destination)
            written.append(destination)
    return written
