"""lagcli's runtime: plain sources shipped with the package and copied, unchanged, next
to generated code (`lagcli generate --lang c` copies `c/`). They are not templates: one
copy per language, usable on their own by someone embedding a generated model
(docs/codegen.md, docs/c-integrator.md).

Python: `run_rules.py` is a module lagcli itself runs (`lagcli.numerics` re-exports
it) whose code the generated Python module carries verbatim (`python_run_rules`), so
that module stays one self-contained file."""
from __future__ import annotations

import ast
import functools
from importlib import resources

C_RUNTIME = ("lagcli_model.h", "lagcli_ode.h", "lagcli_ode.c", "lagcli_driver.h", "lagcli_driver.c")


@functools.lru_cache(maxsize=1)
def _c_runtime_texts() -> tuple[tuple[str, str], ...]:
    folder = resources.files(__name__).joinpath("c")
    return tuple((name, folder.joinpath(name).read_text(encoding="utf-8")) for name in C_RUNTIME)


def c_runtime_files() -> dict[str, str]:
    """{file name: text} of the C runtime."""
    return dict(_c_runtime_texts())


@functools.lru_cache(maxsize=1)
def python_run_rules() -> str:
    """The code of `run_rules.py` without its module docstring: what the generated
    Python module pastes after its imports."""
    text = resources.files(__name__).joinpath("run_rules.py").read_text(encoding="utf-8")
    first_statement = ast.parse(text).body[1].lineno      # body[0] is the docstring
    lines = text.splitlines(keepends=True)
    start = first_statement - 1
    while start > 0 and lines[start - 1].startswith("#"):  # keep the comment above it
        start -= 1
    return "".join(lines[start:])
