"""`System`: a loaded spec with its model, derivation and layout — the Python API.

    import lagcli
    system = lagcli.load("specs/cartesian_pendulum.yaml")     # or the spec's YAML text
    traj = system.simulate(t_end=2.0, parameters={"l": 2.0})  # a lagcli.trajectory.Trajectory
    traj["x"], traj.to_csv(), traj.to_pandas()
    system.report("json"); system.generate("c", "out/")

Every method delegates to the machinery behind the command line (the CLI's
commands are thin clients of these): the report functions of `lagcli.emit`, the
code generators, the consistent initial state of `lagcli.simulate.initial` and the
Python backend's integrator. docs/api.md has a worked example.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from lagcli.derive.result import Derivation
from lagcli.errors import UsageError
from lagcli.layout import Layout, layout_of
from lagcli.model_types import Model
from lagcli.output import check_directory_output, write_output

SPEC_SUFFIXES = (".yaml", ".yml", ".toml")
REPORT_FORMATS = ("text", "json", "dict", "latex", "latex-document")
API_SOURCES = ("initial=", "initial:", "parameters=")   # how notes and hints name the inputs


def load(source: str | Path) -> "System":
    """A `System` from a spec file (a `Path`, or a string ending in .yaml/.yml/.toml
    without a newline) or from the spec's YAML text. Raises `lagcli.errors.SpecError`
    with every problem found, each located."""
    from lagcli.api import load_model, load_model_text
    from lagcli.derive import derive

    is_path = isinstance(source, Path) or ("\n" not in source and source.endswith(SPEC_SUFFIXES))
    model = load_model(source) if is_path else load_model_text(source)
    derivation = derive(model)
    return System(model, derivation, layout_of(derivation))


@dataclass(frozen=True, eq=False)
class System:
    model: Model
    derivation: Derivation
    layout: Layout

    @property
    def name(self) -> str:
        return self.layout.name

    # --- reports and code ---------------------------------------------------------------

    def report(self, format: str = "text", simplify: bool = True, parts: str | None = None):
        """What `lagcli derive` prints: "text", "json" (a string), "dict" (the same
        content as Python values), "latex" (a fragment) or "latex-document"; `parts`
        (text and LaTeX): the sections to print, e.g. "equations,energies" (None: all)."""
        from lagcli.emit.report import report_content, report_parts, spec_printer

        if format in ("json", "dict"):
            if parts is not None:
                raise UsageError("--part selects sections of the text and LaTeX reports; "
                                 "the JSON report always carries every key")
            content = report_content(self.derivation, spec_printer(), simplify)
            return content if format == "dict" else json.dumps(content, indent=2) + "\n"
        if format == "text":
            from lagcli.emit.templates import render

            content = report_content(self.derivation, spec_printer(), simplify, named=True)
            return render("report/derive.txt.jinja", r=content, parts=report_parts(parts))
        if format in ("latex", "latex-document"):
            from lagcli.emit.latex import latex_document, latex_fragment

            make = latex_document if format == "latex-document" else latex_fragment
            return make(self.derivation, simplify, report_parts(parts))
        raise UsageError(f"report format {format!r}: expected one of {', '.join(REPORT_FORMATS)}")

    def generate(self, target: str, path: str | Path | None = None) -> dict[str, str]:
        """{file name: text} of `target` (python, c, latex: `lagcli.emit.LANGUAGES`),
        embedding the spec's initial state made consistent; written atomically into
        `path` when given (a directory for C, a file otherwise)."""
        from lagcli.emit import LANGUAGES, generate as emit

        language = LANGUAGES.get(target)
        directory = None
        if path is not None and language is not None and language.directory:
            directory = check_directory_output(str(path))    # before any work
        initial, notes = None, ()
        if language is not None and language.embeds_initial:   # solved for once, here, not in emit
            from lagcli.simulate.initial import spec_initial_state

            start, _ = spec_initial_state(self.derivation)
            initial, notes = start.values, start.notes
        files = emit(self.derivation, target, initial, notes)
        if directory is not None:
            directory.mkdir(exist_ok=True)
            for name, text in files.items():      # a name may have a folder: src/lib.rs
                (directory / name).parent.mkdir(exist_ok=True)
                write_output(directory / name, text)
        elif path is not None:
            (text,) = files.values()
            write_output(path, text)
        return files

    # --- simulation ---------------------------------------------------------------------

    def initial_state(self, parameters: dict | None = None, initial: dict | None = None):
        """The initial state [q..., q'...] from the spec's `initial:` overridden by
        `initial`, made consistent with the constraints for `parameters` (a
        `lagcli.simulate.initial.InitialState`: values and notes)."""
        from lagcli.simulate.initial import Sources, initial_state

        params = self._parameters(parameters)
        given = dict(initial or {})
        self._known("initial", given, self.layout.state_names, "coordinate or velocity")
        return initial_state(self.derivation, {**self.model.initial, **given}, params,
                             soft=set(self.model.initial) - set(given), sources=Sources(*API_SOURCES))

    def simulate(self, t_end: float | None = None, dt: float | None = None, method: str | None = None,
                 rtol: float | None = None, atol: float | None = None, parameters: dict | None = None,
                 initial: dict | None = None, baumgarte: tuple[float, float] | None = None):
        """Integrate with the Python backend (scipy) as `lagcli simulate --backend python`
        does; None takes the spec's `simulate:` value, else lagcli's default. Returns a
        `lagcli.trajectory.Trajectory`; a failed integration keeps its rows and says
        why in `failure`."""
        from lagcli.simulate.options import Request, resolve_settings
        from lagcli.simulate.python_backend import integrate_module
        from lagcli.trajectory import from_rows

        settings = resolve_settings(Request(self.model.source, t_end, dt, method, rtol, atol,
                                            baumgarte=baumgarte), self.layout.settings.as_dict())
        params = self._parameters(parameters)
        start = self.initial_state(parameters, initial)
        module = self._module()
        rows = integrate_module(module, [params[name] for name in self.layout.parameter_names],
                                list(start.values), settings)
        d = self.derivation
        return from_rows(self.layout, rows, start.notes,
                         d.jacobi_integral is not None and d.energy_is_jacobi)

    def _module(self):
        """The generated Python module, made once per System."""
        cached = self.__dict__.get("_generated_module")
        if cached is None:
            from lagcli.simulate.python_backend import load_module

            cached = load_module(self.derivation)
            object.__setattr__(self, "_generated_module", cached)   # a cache, not state
        return cached

    def _parameters(self, parameters: dict | None) -> dict[str, float]:
        given = dict(parameters or {})
        self._known("parameters", given, self.layout.parameter_names, "parameter")
        return {**self.layout.parameter_defaults, **{k: float(v) for k, v in given.items()}}

    def _known(self, argument: str, given: dict, allowed, what: str) -> None:
        unknown = [name for name in given if name not in allowed]
        if unknown:
            raise UsageError(f"{argument}=: unknown {what} {unknown[0]!r}\n"
                             f"  hint: known names are: {', '.join(allowed) or '(none)'}")

    # --- rich display -------------------------------------------------------------------

    def _repr_latex_(self) -> str:
        """The equations of motion, for Jupyter (MathJax)."""
        from lagcli.emit.latex import latex_printer

        printer = latex_printer(self.derivation)
        rows = [f"{printer.doprint(e.lhs)} &= {printer.doprint(e.rhs)}" for e in self.derivation.equations]
        rows += [f"{printer.doprint(c.expr)} &= 0" for c in self.derivation.constraints]
        return "$$\\begin{aligned}" + " \\\\ ".join(rows) + "\\end{aligned}$$"

    def _repr_html_(self) -> str:
        from html import escape

        layout = self.layout
        items = [("coordinates", ", ".join(layout.coordinates)),
                 ("parameters", ", ".join(f"{p.name} = {p.default:g}" for p in layout.parameters)),
                 ("multipliers", ", ".join(layout.multiplier_names) or "(none)"),
                 ("columns", ", ".join(layout.header))]
        body = "".join(f"<tr><th>{k}</th><td>{escape(v)}</td></tr>" for k, v in items)
        return f"<p><b>{escape(layout.name)}</b></p><table>{body}</table>"

    def __repr__(self) -> str:
        return f"<lagcli.System {self.name}: {', '.join(self.layout.coordinates)}>"
