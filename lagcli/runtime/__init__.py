"""lagcli's runtime: plain sources shipped with the package and copied, unchanged, next
to generated code (`lagcli generate --lang c` copies `c/`; `--lang fmu` puts `fmi2/`
and part of `c/` into the FMU's sources/). They are not templates: one copy per
language, usable on their own by someone embedding a generated model
(docs/codegen.md, docs/c-integrator.md).

`fmi2/` holds lagcli's FMI 2.0 functions (lagcli_fmi2.c) and the FMI 2.0 standard's
headers, unchanged, under the licence in fmi2/LICENSE.txt (the Modelica Association's
2-clause BSD licence)."""
from __future__ import annotations

import functools
from importlib import resources

C_RUNTIME = ("lagcli_model.h", "lagcli_ode.h", "lagcli_ode.c", "lagcli_driver.h", "lagcli_driver.c")
FMI2_RUNTIME = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h", "lagcli_fmi2.c")
FMI2_LICENSE = "LICENSE.txt"


@functools.lru_cache(maxsize=None)
def _texts(folder: str, names: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    where = resources.files(__name__).joinpath(folder)
    return tuple((name, where.joinpath(name).read_text(encoding="utf-8")) for name in names)


def c_runtime_files() -> dict[str, str]:
    """{file name: text} of the C runtime."""
    return dict(_texts("c", C_RUNTIME))


def fmi2_runtime_files() -> dict[str, str]:
    """{file name: text} of the FMI 2.0 functions and the standard's headers."""
    return dict(_texts("fmi2", FMI2_RUNTIME))


def fmi2_license() -> str:
    """The licence of the FMI 2.0 headers."""
    return _texts("fmi2", (FMI2_LICENSE,))[0][1]
