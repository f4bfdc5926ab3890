"""Folders shipped as package data: `templates/` as `lagcli.templates`, `specs/` as
`lagcli.specs` (pyproject.toml maps them). From a source checkout that is not
installed, the checkout's own folder is used."""
from __future__ import annotations

from importlib import resources
from pathlib import Path

CHECKOUT = Path(__file__).resolve().parents[2]


def data_dir(package: str, folder: str) -> Path:
    """The installed `package`'s folder, else `folder` of the checkout."""
    try:
        installed = Path(str(resources.files(package)))
        if installed.is_dir():
            return installed
    except ModuleNotFoundError:
        pass
    return CHECKOUT / folder
