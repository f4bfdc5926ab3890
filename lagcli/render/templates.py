"""The one Jinja environment that renders every piece of generated text.

Templates live in the top-level `templates/` folder, installed as the package
`lagcli.templates`, and are named `FILE.ext.jinja`. The environment is strict
(an undefined variable is an error, never an empty string). Rendering returns
text; only the caller writes files. Compiled templates are kept between commands
(`lagcli.run.template_cache`, under the cache's trust rules).
"""
from __future__ import annotations

import functools
from pathlib import Path

import jinja2

from lagcli.render.escape import FILTERS
from lagcli.errors import EmitError
from lagcli.run.template_cache import TemplateCache
from lagcli.runtime.package_data import data_dir


def _template_dir() -> Path:
    return data_dir("lagcli.templates", "templates")


@functools.lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    """The one template environment; its filters are the escapes of spec text
    (`{{ i.description | c_comment }}`, see lagcli/render/escape.py)."""
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(_template_dir())),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
        bytecode_cache=TemplateCache(),
    )
    env.filters.update(FILTERS)
    return env


def render(name: str, **context) -> str:
    try:
        return environment().get_template(name).render(**context)
    except jinja2.TemplateNotFound as exc:
        raise EmitError(f"template {exc.name!r} not found in {_template_dir()}") from exc
    except jinja2.UndefinedError as exc:
        raise EmitError(f"template {name!r}: {exc.message}") from exc
