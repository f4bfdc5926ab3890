"""`lagcli generate --lang fmu`: an FMI 2.0 FMU (Model Exchange and Co-Simulation), one zip.

    modelDescription.xml             from the system's layout (templates/fmu/)
    binaries/<platform>/<name>.so    the sources below compiled by `cc` (linux64; darwin64: .dylib)
    sources/                         the generated C model (`lagcli.targets.c`: <name>.{h,c}), the
                                     FMI functions lagcli_fmi2.c and the standard's fmi2 headers
                                     (lagcli/runtime/fmi2/), the integrator lagcli_ode.{h,c}, the
                                     generated lagcli_fmu_model.h and buildDescription.xml
    documentation/licenses/          the licence of the fmi2 headers

Variables, in value-reference order (lagcli_fmi2.c serves the same order): the states
[q..., q'...] (outputs, so that a tool can plot them or close a loop on them;
initial="exact", start: the spec's consistent initial state), their derivatives, the
parameters (fixed, start: their defaults), the inputs (continuous, start 0; an input with a
law runs the law inside the FMU, the FMU input added to it: `_with_laws`), then the
other outputs: the multipliers and the invariant columns of `lagcli simulate` (energy,
jacobi, p_<q>, constraint_residual). A unit of the run interface (the spec's `unit:`s:
docs/simulate.md, "Units of the columns") becomes the variable's `unit` and a `<Unit>`
of `<UnitDefinitions>`.

Same spec, same compiler -> same bytes: the zip's entries are sorted, stamped
1980-01-01 00:00 with mode 0644, and the GUID is a hash of the text files. Everything
but the binary is the same whatever the compiler.
"""
from __future__ import annotations

import hashlib
import io
import platform
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from lagcli.derive.result import Derivation
from lagcli.targets import c as c_target
from lagcli.render.spec_printer import spec_str
from lagcli.render.templates import render
from lagcli.errors import Loc, Problem, SimulationError, SpecError
from lagcli.interface import STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT, Layout
from lagcli.runtime.run_rules import max_step
from lagcli.runtime import c_runtime_files, fmi2_license, fmi2_runtime_files

MODEL_HEADER = "lagcli_fmu_model.h"
INTEGRATOR = ("lagcli_model.h", "lagcli_linalg.h", "lagcli_ode.h", "lagcli_ode.c",   # of the C runtime: no driver
              "lagcli_events.h", "lagcli_events.c")      # the impact law of the events (lagcli_events_impact)
ZIP_TIME = (1980, 1, 1, 0, 0, 0)      # the earliest time a zip entry can hold
ZIP_MODE = 0o644 << 16
PLATFORMS = {("Linux", "x86_64"): ("linux64", ".so"), ("Linux", "i686"): ("linux32", ".so"),
             ("Darwin", "x86_64"): ("darwin64", ".dylib"), ("Darwin", "arm64"): ("darwin64", ".dylib")}


@dataclass(frozen=True)
class Variable:
    """One ScalarVariable of modelDescription.xml."""

    name: str
    reference: int
    description: str
    causality: str
    variability: str
    initial: str | None = None
    start: str | None = None           # printed with repr: round-trips the double
    derivative: int | None = None      # the 1-based index of the state it is the derivative of
    unit: str | None = None


def model_variables(layout: Layout, initial: tuple[float, ...], descriptions: dict) -> tuple[Variable, ...]:
    """Every variable, in value-reference order (= index - 1)."""
    states = [Variable(s.name, 0, f"velocity of {s.coordinate}" if s.kind == "velocity" else f"coordinate {s.name}",
                       "output", "continuous", "exact", repr(float(x)), unit=s.unit)
              for s, x in zip(layout.states, initial)]
    derivatives = [Variable(f"der({s.name})", 0, f"time derivative of {s.name}", "local", "continuous",
                            derivative=k + 1) for k, s in enumerate(layout.states)]
    parameters = [Variable(p.name, 0, descriptions.get(p.name) or "parameter", "parameter", "fixed", "exact",
                           repr(float(p.default)), unit=p.unit) for p in layout.parameters]
    inputs = [Variable(u.name, 0, descriptions.get(u.name) or u.description or "input", "input", "continuous",
                       start=repr(float(u.default)),
                       unit=u.unit) for u in layout.inputs]
    outputs = ([Variable(m.name, 0, f"multiplier of the {m.kind} constraint", "output", "continuous")
                for m in layout.multipliers]
               + [Variable(c.name, 0, _invariant_description(c), "output", "continuous", unit=c.unit)
                  for c in layout.invariants])
    ordered = states + derivatives + parameters + inputs + outputs
    return tuple(Variable(**{**v.__dict__, "reference": k}) for k, v in enumerate(ordered))


def _invariant_description(column) -> str:
    return {"energy": "total energy T + V", "jacobi": "Jacobi integral h = T2 - T0 + V",
            "momentum": f"momentum conjugate to the ignorable coordinate {column.of}",
            "residual": "largest |constraint| (positions and velocities)"}[column.kind]


def model_structure(variables: tuple[Variable, ...]) -> dict:
    """The 1-based indices of ModelStructure: outputs (the states among them), derivatives
    and initial unknowns (the derivatives and the outputs computed from the initial state:
    not the states, whose start is exact)."""
    outputs = [k for k, v in enumerate(variables, 1) if v.causality == "output"]
    derivatives = [k for k, v in enumerate(variables, 1) if v.derivative is not None]
    computed = [k for k in outputs if variables[k - 1].initial != "exact"]
    return dict(outputs=outputs, derivatives=derivatives, initial_unknowns=sorted(computed + derivatives))


def fmu_sources(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict[str, str]:
    """{path in the FMU: text} of every file but the binary."""
    name = layout.name
    _check_file_names(d, name)
    context = c_target.c_context(_with_laws(d), layout, initial, initial_notes)
    c_sources = {**c_target.model_sources(context),
                 **{file: c_runtime_files()[file] for file in INTEGRATOR}, **fmi2_runtime_files()}
    descriptions = {p.symbol.name: p.description for p in d.model.parameters}
    descriptions.update({law.symbol.name: f"added to its law {spec_str(law.expr)}" for law in d.model.laws})
    fmu = fmu_context(context, descriptions, sorted(f for f in c_sources if f.endswith(".c")),
                      len(d.events))
    guid = _guid(render("fmu/modelDescription.xml.jinja", guid="", **fmu), c_sources)
    return {
        "modelDescription.xml": render("fmu/modelDescription.xml.jinja", guid=guid, **fmu),
        **{f"sources/{file}": text for file, text in c_sources.items()},
        f"sources/{MODEL_HEADER}": render(f"fmu/{MODEL_HEADER}.jinja", guid=guid, **fmu),
        "sources/buildDescription.xml": render("fmu/buildDescription.xml.jinja", **fmu),
        "documentation/licenses/fmi2-headers.txt": fmi2_license(),
    }


def _with_laws(d: Derivation) -> Derivation:
    """The model the FMU computes: an input u with a law (`simulate: inputs:`) enters F as
    law + u, so the law runs inside the FMU and the FMU input u (start 0) adds to it (a
    disturbance or a feed-forward); an input without a law stays a plain input."""
    if not d.model.laws:
        return d
    from lagcli.derive.closed_loop import closed_loop

    symbols = {u.name: u for u in d.model.input_symbols}
    return closed_loop(d, {law.symbol.name: law.expr + symbols[law.symbol.name] for law in d.model.laws})


def fmu_context(c_context: dict, descriptions: dict, compiled: list[str], nevent: int = 0) -> dict:
    """What the templates of templates/fmu/ need: the variables of the run interface, the
    `Interface` and settings of the C context, the C files to compile; `nevent`: the
    spec's events, the FMU's event indicators (then it is Model Exchange only)."""
    i = c_context["i"]
    layout = i.layout
    variables = model_variables(layout, i.initial, descriptions)
    method = c_context["driver_method"]
    return dict(i=i, variables=variables, sources=compiled, settings=layout.settings, baumgarte=i.baumgarte,
                inputs=[u.name for u in layout.inputs], units=sorted({v.unit for v in variables if v.unit}),
                literal=c_context["literal"], method=method,
                max_step=c_context["literal"](max_step(method, *i.baumgarte, layout.constrained)),
                max_steps=STEP_BUDGET_BASE + STEP_BUDGET_PER_OUTPUT,
                nevent=nevent, constraint_tolerance=c_context["constraint_tolerance"],
                **model_structure(variables))


def _check_file_names(d: Derivation, name: str) -> None:
    """The model's <name>.h and <name>.c must not replace one of the FMU's own sources."""
    taken = {*fmi2_runtime_files(), MODEL_HEADER, *INTEGRATOR}
    if {f"{name}.h", f"{name}.c"} & taken:
        raise SpecError(Problem(Loc(d.model.source, path="name"),
                                f"the name {name!r} gives a file name of the FMU's own sources "
                                f"({', '.join(sorted(taken))})", "set another `name:` in the spec"))


def fmu_files(d: Derivation, layout: Layout, initial=None, initial_notes=()) -> dict[str, bytes]:
    """{`<name>.fmu`: the zip's bytes}: `fmu_sources` plus the binary compiled from them."""
    from lagcli.runtime.toolchain import find_compiler

    name = d.model.name
    compiler = find_compiler()
    if compiler is None:
        raise SimulationError("--lang fmu compiles the FMU's binary with a C compiler, but 'cc' was "
                              "not found on PATH (install gcc or clang); nothing was written")
    files: dict[str, str | bytes] = dict(fmu_sources(d, layout, initial, initial_notes))
    folder, suffix = platform_folder()
    files[f"binaries/{folder}/{name}{suffix}"] = compile_binary(compiler, files, name + suffix)
    return {f"{name}.fmu": archive(files)}


def platform_folder() -> tuple[str, str]:
    """The FMI 2.0 platform folder of this machine and its library suffix."""
    key = (platform.system(), platform.machine())
    if key not in PLATFORMS:
        raise SimulationError(f"--lang fmu: no FMI 2.0 platform folder for {key[0]} on {key[1]} "
                              f"(known: {', '.join(sorted({f for f, _ in PLATFORMS.values()}))})")
    return PLATFORMS[key]


def compile_binary(compiler: str, files: dict, library: str) -> bytes:
    """The shared library built from the FMU's sources/ in a temporary directory."""
    from lagcli.runtime.toolchain import compile_program

    with tempfile.TemporaryDirectory(prefix="lagcli-fmu-") as work:
        sources = []
        for path, text in files.items():
            if path.startswith("sources/"):
                (Path(work) / path.removeprefix("sources/")).write_text(text, encoding="utf-8")
                sources.append(path.removeprefix("sources/"))
        compile_program(compiler, Path(work), sorted(s for s in sources if s.endswith(".c")), library,
                        shared=True)
        return (Path(work) / library).read_bytes()


def archive(files: dict) -> bytes:
    """The zip of `files` ({path: text or bytes}), the same bytes for the same files."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as fmu:
        for path in sorted(files):
            entry = zipfile.ZipInfo(path, ZIP_TIME)
            entry.external_attr = ZIP_MODE
            entry.compress_type = zipfile.ZIP_DEFLATED
            data = files[path]
            fmu.writestr(entry, data.encode("utf-8") if isinstance(data, str) else data, compresslevel=9)
    return buffer.getvalue()


def _guid(description: str, sources: dict[str, str]) -> str:
    """A GUID that changes whenever the model description or the C model does."""
    digest = hashlib.sha256(description.encode("utf-8"))
    for file in sorted(sources):
        digest.update(file.encode("utf-8") + b"\0" + sources[file].encode("utf-8") + b"\0")
    h = digest.hexdigest()
    return "{" + f"{h[:8]}-{h[8:12]}-{h[12:16]}-{h[16:20]}-{h[20:32]}" + "}"

