"""lagcli's runtime: plain sources shipped with the package and copied, unchanged, next
to generated code (`lagcli generate --lang c` copies `c/`, `--lang rust` copies `rust/`). They are not templates: one
copy per language, usable on their own by someone embedding a generated model
(docs/codegen.md, docs/c-integrator.md)."""
from __future__ import annotations

import functools
from importlib import resources

C_RUNTIME = ("lagcli_model.h", "lagcli_ode.h", "lagcli_ode.c", "lagcli_driver.h", "lagcli_driver.c")
RUST_RUNTIME = ("ode.rs", "driver.rs")


@functools.lru_cache(maxsize=None)
def _runtime_texts(language: str, names: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    folder = resources.files(__name__).joinpath(language)
    return tuple((name, folder.joinpath(name).read_text(encoding="utf-8")) for name in names)


def c_runtime_files() -> dict[str, str]:
    """{file name: text} of the C runtime."""
    return dict(_runtime_texts("c", C_RUNTIME))


def rust_runtime_files() -> dict[str, str]:
    """{file name: text} of the Rust runtime (the integrator and the driver)."""
    return dict(_runtime_texts("rust", RUST_RUNTIME))
