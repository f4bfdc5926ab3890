"""lagcli's runtime: plain sources shipped with the package and copied, unchanged, next
to generated code (`lagcli generate --lang c` copies `c/`, `--lang rust` copies `rust/`, `--lang octave`
`octave/` for a spec with events;
`--lang fmu` puts `fmi2/` and part of `c/` into the FMU's sources/). They are not
templates: one copy per language, usable on their own by someone embedding a generated
model (docs/codegen.md, docs/c-integrator.md).

`fmi2/` holds lagcli's FMI 2.0 functions (lagcli_fmi2.c) and the FMI 2.0 standard's
headers, unchanged, under the licence in fmi2/LICENSE.txt (the Modelica Association's
2-clause BSD licence).

Python: `run_rules.py` is a module lagcli itself runs (the run layer and
the code targets import it) whose code the generated Python module carries verbatim (`python_run_rules`), so
that module stays one self-contained file; so are `variational.py` (the variational
integrator), and for a spec with events `run_limits.py` (the budgets, the event records
and notes) and `event_loop_code.py` (the event loop and the impact law, which lagcli's
Python backend runs too). `package_data.py` finds the other shipped
folders (templates/, specs/) for the spec reader and the Jinja environment."""
from __future__ import annotations

import ast
import functools

C_RUNTIME = ("lagcli_model.h", "lagcli_linalg.h", "lagcli_ode.h", "lagcli_ode.c", "lagcli_driver.h", "lagcli_driver.c",
             "lagcli_variational.h", "lagcli_variational.c", "lagcli_events.h", "lagcli_events.c")
FMI2_RUNTIME = ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h", "lagcli_fmi2.c")
FMI2_LICENSE = "LICENSE.txt"
RUST_RUNTIME = ("ode.rs", "driver.rs")
OCTAVE_EVENT_RUNTIME = ("lagcli_event_loop.m", "lagcli_event_report.m")


@functools.lru_cache(maxsize=None)
def _texts(folder: str, names: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    from importlib import resources     # imported on use: ~3 ms that `derive` would pay for nothing

    where = resources.files(__name__).joinpath(folder)
    return tuple((name, where.joinpath(name).read_text(encoding="utf-8")) for name in names)


def c_runtime_files() -> dict[str, str]:
    """{file name: text} of the C runtime."""
    return dict(_texts("c", C_RUNTIME))


def fmi2_runtime_files() -> dict[str, str]:
    """{file name: text} of the FMI 2.0 functions and the standard's headers."""
    return dict(_texts("fmi2", FMI2_RUNTIME))


def octave_event_files() -> dict[str, str]:
    """{file name: text} of the MATLAB/Octave event loop (shipped with a spec that has events)."""
    return dict(_texts("octave", OCTAVE_EVENT_RUNTIME))


def fmi2_license() -> str:
    """The licence of the FMI 2.0 headers."""
    return _texts("fmi2", (FMI2_LICENSE,))[0][1]


def python_run_rules() -> str:
    """The code of `run_rules.py` without its module docstring: what the generated
    Python module pastes after its imports."""
    return _python_code("run_rules.py")


def python_variational() -> str:
    """The code of `variational.py` (the variational integrator) without its module
    docstring: what the generated Python module pastes after the run rules."""
    return _python_code("variational.py")


def python_run_limits() -> str:
    """The code of `run_limits.py` (the step budget, the accumulation rules, the event
    records and notes): what the generated module of a spec with events pastes after the
    run rules."""
    return _python_code("run_limits.py")


def python_event_loop() -> str:
    """The code of `event_loop_code.py` (the event loop and the impact law) from its
    `# --- ` line on, without lagcli's import of the run limits (pasted above it): what
    the generated module of a spec with events pastes after the run limits."""
    return _python_code("event_loop_code.py")


@functools.lru_cache(maxsize=None)
def _python_code(name: str) -> str:
    """The file's code from the comment line `# --- ` that opens it, after the docstring
    (and after lagcli's own imports of what the generated module has above it)."""
    from importlib import resources

    text = resources.files(__name__).joinpath(name).read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    docstring_end = ast.parse(text).body[0].end_lineno
    return "".join(lines[next(i for i in range(docstring_end, len(lines)) if lines[i].startswith("# --- ")):])


def rust_runtime_files() -> dict[str, str]:
    """{file name: text} of the Rust runtime (the integrator and the driver)."""
    return dict(_texts("rust", RUST_RUNTIME))
