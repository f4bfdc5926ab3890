"""lagcli's version, written once (pyproject.toml reads it: `[tool.setuptools.dynamic]`).

A module of its own at the ground floor: every room that stamps what it made (generated
files, caches, reports) imports it without importing the package's front door
(`lagcli/__init__.py`, which reaches up to the System).
"""

__version__ = "0.1.0"
