"""The design's own measures (docs/design.md, "Measures"), checked on the source.

Each test reads lagcli's files (with `ast` for imports), so a change that breaks a
rule of the layout fails here with the file and the rule it broke.
"""
from __future__ import annotations

import tomllib
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "lagcli"
FACES = {"__init__", "__main__", "cli", "cli_options", "commands", "system", "interface", "errors", "trajectory"}


def modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_the_package_root_holds_only_the_faces():
    at_root = {p.stem for p in PACKAGE.glob("*.py")}
    assert at_root <= FACES, f"move these into a folder by concept: {sorted(at_root - FACES)}"


def test_no_two_modules_share_a_name():
    names = Counter(p.stem for p in modules() if p.stem != "__init__")
    shared = sorted(n for n, k in names.items() if k > 1)
    assert not shared, f"modules sharing a name: {shared}"


def test_every_folder_is_a_listed_package():
    """CI installs non-editably: a folder missing from pyproject's list is missing from the wheel."""
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    folders = {".".join(p.parent.relative_to(ROOT).parts) for p in PACKAGE.rglob("__init__.py")
               if "__pycache__" not in p.parts}
    assert folders <= listed, f"add to [tool.setuptools] packages: {sorted(folders - listed)}"
