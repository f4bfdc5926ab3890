"""`System`: a loaded spec with its model, derivation and layout — the Python API.

    import lagcli
    system = lagcli.load("specs/cartesian_pendulum.yaml")     # or the spec's YAML text
    traj = system.simulate(t_end=2.0, parameters={"l": 2.0})  # a lagcli.trajectory.Trajectory
    system.simulate(t_end=2.0, backend="c")                   # the compiled driver (cached)
    system.parts.mass_matrix                                  # LaTeX in Jupyter
    traj["x"], traj.to_csv(), traj.to_pandas()
    system.report("json"); system.generate("c", "out/")

The command line is a thin client of this class: `lagcli derive`, `generate`,
`check` and the cold path of `simulate` load a `System` and call the methods below
(only a warm `simulate`, which finds a compiled driver in the cache, runs without
one: it must not import sympy). Each method delegates to one piece of machinery: the
report functions of `lagcli.report`, the code targets of `lagcli.targets`, the consistent initial state
of `lagcli.analysis.initial_state`, and the two backends of `lagcli.run` (the
generated Python module with scipy, the compiled C driver). docs/api.md has a
worked example.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from lagcli.derive.result import Derivation
from lagcli.errors import UsageError
from lagcli.interface import Layout, Start, layout_of
from lagcli.model.collector import collector_paused
from lagcli.model.model_types import Model
from lagcli.render.output import check_directory_output, write_output

SPEC_SUFFIXES = (".yaml", ".yml", ".toml")
REPORT_FORMATS = ("text", "json", "dict", "latex", "latex-document")
API_SOURCES = ("initial=", "initial:", "parameters=")   # how notes and hints name the inputs


def load(source: str | Path) -> "System":
    """A `System` from a spec file (a `Path`, or a string ending in .yaml/.yml/.toml
    without a newline) or from the spec's YAML text. Raises `lagcli.errors.SpecError`
    with every problem found, each located."""
    from lagcli.spec.files import read_spec_bytes

    is_path = isinstance(source, Path) or ("\n" not in source and source.endswith(SPEC_SUFFIXES))
    if is_path:
        return load_file(str(source), read_spec_bytes(source))
    from lagcli.derive.pipeline import derive_model, load_model_text

    return System(derive_model(load_model_text(source)), source.encode())


def load_file(path: str, spec_bytes: bytes) -> "System":
    """The System of the spec file `path` whose bytes were read already (`lagcli simulate`
    reads them once, for the cache key and the model alike)."""
    from lagcli.derive.pipeline import derive_model, load_model

    return System(derive_model(load_model(path, spec_bytes)), spec_bytes)


@dataclass(frozen=True, eq=False)
class System:
    derivation: Derivation
    spec_bytes: bytes              # the spec as read: with model.source, the key of cached code

    @property
    def model(self) -> Model:
        return self.derivation.model

    @property
    def layout(self) -> Layout:
        """The run interface (lagcli.interface.Layout), built once: names, defaults, units,
        columns, settings, the consistent default state; what runs, targets, sweeps and
        pictures read."""
        return self._once("_layout", self._make_layout)

    def _make_layout(self) -> Layout:
        from lagcli.model.angles import angle_coordinates

        start, consistent = self.spec_start()
        return layout_of(self.derivation, Start(tuple(start.values), tuple(start.notes), consistent),
                         angle_coordinates(self.model))

    @property
    def name(self) -> str:
        return self.model.name

    @property
    def parts(self):
        """The derivation's parts for notebooks (`lagcli.report.parts.Parts`): `parts.mass_matrix`,
        `parts.equations`, `parts.lagrangian`...; each shows as LaTeX in Jupyter and as
        spec-language text in a console, and holds the sympy object in `.value`."""
        from lagcli.report.parts import Parts

        return self._once("_parts", lambda: Parts(self.derivation))

    # --- reports and code ---------------------------------------------------------------

    @collector_paused()     # the report builds and drops ~10^5 expressions: 7% of a 40-link derive --json
    def report(self, format: str = "text", simplify: bool = True, parts: str | None = None):
        """What `lagcli derive` prints: "text", "json" (a string), "dict" (the same
        content as Python values), "latex" (a fragment) or "latex-document"; `parts`
        (text and LaTeX): the sections to print, e.g. "equations,energies" (None: all)."""
        from lagcli.report.content import report_content, report_parts, spec_printer

        if format in ("json", "dict"):
            if parts is not None:
                raise UsageError("--part selects sections of the text and LaTeX reports; "
                                 "the JSON report always carries every key")
            content = report_content(self.derivation, spec_printer(), simplify)
            return content if format == "dict" else json.dumps(content, indent=2) + "\n"
        if format == "text":
            from lagcli.report.content import text_report

            return text_report(self.derivation, simplify, report_parts(parts))
        if format in ("latex", "latex-document"):
            from lagcli.report.latex import latex_document, latex_fragment

            make = latex_document if format == "latex-document" else latex_fragment
            return make(self.derivation, simplify, report_parts(parts))
        raise UsageError(f"report format {format!r}: expected one of {', '.join(REPORT_FORMATS)}")

    def generate(self, target: str, path: str | Path | None = None,
                 variational: bool | None = None) -> dict[str, str | bytes]:
        """{file name: text} of `target` (python, c, latex; fmu: bytes: `lagcli.targets.LANGUAGES`),
        embedding the spec's initial state made consistent; written atomically into
        `path` when given (a directory for C, a file otherwise). `variational` (python, c):
        True generates the variational integrator's functions for a big system too (by
        default only a small system has them: docs/codegen.md)."""
        from lagcli.targets import LANGUAGES, generate as emit

        language = LANGUAGES.get(target)
        directory = None
        if path is not None and language is not None and language.directory:
            directory = check_directory_output(str(path))    # before any work
        initial, notes, layout = None, (), None
        if language is not None and language.embeds_initial:   # solved for once, here, not in emit
            layout = self.layout
            initial, notes = layout.start.values, layout.start.notes
        files = emit(self.derivation, target, initial, notes, layout, variational)
        if directory is not None:
            directory.mkdir(exist_ok=True)
            for name, text in files.items():      # a name may have a folder: src/lib.rs
                (directory / name).parent.mkdir(exist_ok=True)
                write_output(directory / name, text)
        elif path is not None:
            (text,) = files.values()
            write_output(path, text)
        return files

    def page(self, path: str | Path | None = None, pictures: bool = True) -> str:
        """The page to share (`lagcli report -o page.html`, docs/page.md): one self-contained
        HTML file with the spec, its equations in MathML, the linearization at the initial
        state, the simulation's plot (inline SVG) and the animation (`pictures`: the last
        two, which need matplotlib). Written atomically to `path` when given."""
        from lagcli.report.page import page_html

        html = page_html(self, pictures)
        if path is not None:
            write_output(path, html)
        return html

    # --- simulation ---------------------------------------------------------------------

    @property
    def energy_conserved(self) -> bool:
        """The energy column is conserved (it is the Jacobi integral)."""
        return self.layout.energy_conserved

    def initial_state(self, parameters: dict | None = None, initial: dict | None = None):
        """The initial state [q..., q'...] from the spec's `initial:` overridden by
        `initial`, made consistent with the constraints for `parameters` (a
        `lagcli.analysis.initial_state.InitialState`: values and notes)."""
        from lagcli.analysis.initial_state import Sources

        given = dict(initial or {})
        self._known("initial", given, self.layout.state_names, "coordinate or velocity")
        return self.start(self._parameters(parameters), given, Sources(*API_SOURCES))

    def start(self, parameters: dict[str, float], initial: dict[str, float], sources=None):
        """`initial_state` for names already checked: `parameters` and `initial` hold the
        values given for this run only; `sources` names them in notes and hints
        (`lagcli.analysis.initial_state.Sources`; the command line's by default)."""
        from lagcli.analysis.initial_state import Sources, initial_state

        spec_start, consistent = self.spec_start()
        if not parameters and not initial and consistent:
            return spec_start                           # solved once per System
        defaults = self.layout.parameter_defaults
        params = {**defaults, **{k: v for k, v in parameters.items() if k in defaults}}   # not inputs
        if params != defaults:
            _refuse_impossible(self.derivation, params, (sources or Sources()).parameter)
        return initial_state(self.derivation, {**self.model.initial, **initial}, params,
                             soft=set(self.model.initial) - set(initial), sources=sources or Sources())

    def spec_start(self):
        """The spec's own initial state made consistent, and whether that was possible
        (`lagcli.analysis.initial_state.spec_initial_state`), computed once: what generated
        code embeds."""
        from lagcli.analysis.initial_state import spec_initial_state

        return self._once("_spec_start", lambda: spec_initial_state(self.derivation))

    def simulate(self, t_end: float | None = None, dt: float | None = None, method: str | None = None,
                 rtol: float | None = None, atol: float | None = None, parameters: dict | None = None,
                 initial: dict | None = None, baumgarte: tuple[float, float] | None = None,
                 inputs: dict | None = None, backend: str = "python", steps_per_row: int | None = None):
        """Integrate as `lagcli simulate --backend BACKEND` does: "python" (scipy's
        `solve_ivp` methods on the generated module) or "c" (the compiled driver, built
        once and cached, RK45, DOP853 and variational). None takes the spec's `simulate:`
        value, else lagcli's default. `method="variational"`: lagcli's variational
        integrator (docs/simulate.md), `steps_per_row` fixed steps of dt / steps_per_row
        between rows (default 1). `inputs`: {name: value} of the spec's `inputs:`: a number (held
        constant), an expression string (a law of t, q, q', parameters: "-k*x - c*x_dot")
        or a Python callable u(t, y) returning a number; missing ones follow the spec's
        law or sit at their default. Expression laws and the spec's `events:` run on both
        backends, a callable on the Python backend. Returns a `lagcli.trajectory.Trajectory` (its `events` lists what
        happened); a failed integration keeps its rows and says why in `failure`."""
        from lagcli.run.options import Request, resolve_settings
        from lagcli.trajectory import from_rows

        settings = resolve_settings(Request(self.model.source, t_end, dt, method, rtol, atol,
                                            baumgarte=baumgarte, steps_per_row=steps_per_row),
                                    self.layout.settings.as_dict())
        start = self.initial_state(parameters, initial)
        constants, laws = self._inputs(inputs)
        rows = self.run(settings, {**self._parameters(parameters), **constants}, start, backend, laws=laws)
        return from_rows(self.layout, rows, start.notes, self.energy_conserved, self.angles)

    @property
    def angles(self) -> frozenset:
        """The coordinates that are angles (the layout's, from `lagcli.model.angles`): the
        angle panel of a plot."""
        return self.layout.angles

    def laws(self, values: dict[str, float], laws: dict | None = None) -> dict:
        """The input laws of one run: the spec's, minus the inputs `values` holds constant
        (`--set`), overridden by `laws` (input name -> a sympy law or a callable u(t, y))."""
        spec_laws = {law.symbol.name: law.expr for law in self.model.laws if law.symbol.name not in values}
        return {**spec_laws, **(laws or {})}

    def hybrid(self, values: dict[str, float], laws: dict | None = None):
        """The numeric laws and events of one run (`lagcli.targets.numeric.Hybrid`), or None
        when the run has neither. `values`: parameters and constant inputs of the run;
        `laws`: see `laws`."""
        from lagcli.targets.numeric import hybrid_run

        laws = self.laws(values, laws)
        if not self.model.events and not laws:
            return None
        params = {**self.layout.parameter_defaults, **{k: v for k, v in values.items()
                                                       if k in self.layout.parameter_defaults}}
        inputs = {**self.layout.input_defaults, **{k: v for k, v in values.items()
                                                   if k in self.layout.input_defaults}, **laws}
        return hybrid_run(self.derivation, params, inputs)

    def compiled_laws(self, values: dict[str, float], laws: dict | None = None) -> dict | None:
        """The laws of a run the compiled driver can take (expressions), or None when only
        the Python backend runs it (`python_only`)."""
        laws = self.laws(values, laws)
        return None if self.python_only(laws) else laws

    def python_only(self, laws: dict) -> str | None:
        """Why a run with these input `laws` needs the Python backend (a Python callable as a
        law, a contact held while it pushes: `rest: true`), or None."""
        if any(callable(v) and not hasattr(v, "free_symbols") for v in laws.values()):
            return "Python callables as input laws"
        if any(e.rest for e in self.model.events):
            return "an event's rest: true (a contact held while it pushes)"
        return None

    def run(self, settings, values: dict[str, float], start, backend: str, sink=None, progress=None,
            laws: dict | None = None):
        """One run's rows, given to `sink` (a `lagcli.run.rows.RowSink`; in memory when
        None) as they are computed, and the sink returned: the level `lagcli simulate`
        works at. `settings`: `lagcli.interface.RunSettings`; `values`: the parameters
        and inputs changed for this run (as `--set` gives them); `start`: from `start`;
        `progress(t_end)`: a context manager yielding `update(t)` (or None), entered once
        the code is ready and the integration starts; `laws`: see `hybrid`."""
        from lagcli.run import simulate
        from lagcli.run.options import Overrides

        self._check_method(settings.method, values, laws)
        program = self.program(backend, settings.method, values, laws)
        return simulate.run(program, settings, Overrides(values), start.values, sink, progress)

    def program(self, backend: str, method: str | None = None, values: dict | None = None,
                laws: dict | None = None):
        """What the run layer runs (lagcli.run.simulate) for `backend` and a run's constant
        `values` and input `laws`: "python" (the generated module,
        `lagcli.run.python_backend.PythonModule`; with events or callable laws
        `HybridModule`) or "c" (the compiled driver in the cache, `lagcli.run.c_backend.CDriver`,
        its model generated with the run's expression laws substituted and carrying the
        spec's events; `method` must be one it implements; `python_only` says what it
        cannot run)."""
        values = values or {}
        compiled = self.compiled_laws(values, laws) if backend == "c" else None
        hybrid = self.hybrid(values, laws) if compiled is None else None
        if hybrid is not None:
            from lagcli.run.hybrid_run import HybridModule

            if backend != "python":
                why = self.python_only(self.laws(values, laws))
                rest = next((e.loc for e in self.model.events if e.rest and e.loc is not None), None)
                where = rest.child("rest") if rest is not None and why.startswith("an event's rest") \
                    else self.model.source
                raise UsageError(f"{where}: the {backend} backend does not run {why}\n  hint: use the Python "
                                 "backend (--backend python; the default for such a run)")
            return HybridModule(self._module(), self.layout, hybrid)
        if backend == "python":
            from lagcli.run.python_backend import PythonModule

            return PythonModule(self._module(), self.layout)
        if backend == "c":
            from lagcli.run import c_backend
            from lagcli.runtime.run_rules import EXPLICIT_METHODS

            return self._driver(c_backend.require_compiler(method or EXPLICIT_METHODS[0]), compiled or {})
        raise UsageError(f"backend {backend!r}: expected 'python' or 'c'")

    def sweep(self, grid: dict | None = None, sample: dict | None = None, count: int | None = None,
              seed: int | None = None, runs=None, output: str | None = None, **options):
        """Many runs through the compiled driver, as `lagcli sweep` (docs/sweep.md).

        grid: {name: (start, stop, count)}; sample: {name: ("uniform", a, b) or
        ("normal", mu, sigma)} with `count` and `seed`; runs: a CSV file name or a list of
        {name: value}. `options` are the fields of `lagcli.sweep.SweepOptions`
        (parameters=, initial=, exceed=, trajectories=, workers=, scheduler=, t_end=, ...).
        Returns a `lagcli.sweep.SweepResult` (written to `output` too when given)."""
        from lagcli.sweep import Plan, SweepOptions, make_plan, sweep
        from lagcli.sweep.driver import number

        if isinstance(runs, (list, tuple)):
            names = tuple(runs[0]) if runs else ()
            plan = Plan(names, tuple(tuple(float(r[n]) for n in names) for r in runs))
        else:
            grids = [f"{k}={number(a)}:{number(b)}:{int(n)}" for k, (a, b, n) in (grid or {}).items()]
            samples = [f"{k}={kind}({number(a)},{number(b)})" for k, (kind, a, b) in (sample or {}).items()]
            plan = make_plan(grids, samples, count, seed, runs)
        return sweep(self, plan, SweepOptions(output=output, **options))

    def animate(self, path: str | None = None, trajectory=None, links=(), traces=(), fps: float = 25.0,
                frame: float | None = None, parameters: dict | None = None, **simulate):
        """Draw the motion (docs/animate.md): `trajectory` (a lagcli.trajectory.Trajectory;
        default: `self.simulate(parameters=parameters, **simulate)`), `links` [("origin",
        "P1"), ...], `traces` ["P2"], one PNG `frame` at a time or a .gif/.mp4 `path`.
        Returns a `lagcli.viz.animate.Drawing` (its `figure` shows in a notebook)."""
        from lagcli.viz.animate import Request, animate

        if trajectory is None:
            trajectory = self.simulate(parameters=parameters, **simulate)
        request = Request(tuple(tuple(link) for link in links), tuple(traces), fps, frame)
        return animate(self, trajectory.t, trajectory.states,
                       {**self.layout.parameter_defaults, **self._parameters(parameters)}, path, request)

    def _check_method(self, method: str, values: dict, laws: dict | None) -> None:
        """A usage error (before any work) when `method` cannot integrate this run."""
        from lagcli.derive.discrete import METHOD, refusal

        if method != METHOD:
            return
        reason = refusal(self.derivation)
        if reason is None and self.hybrid(values, laws) is not None:
            reason = (f"--method {METHOD} does not run events or input laws (yet)\n"
                      "  hint: use --method DOP853 (or Radau) for this run")
        if reason is not None:
            raise UsageError(f"{self.model.source}: {reason}")
    # --- analyses (docs/analysis.md; lagcli/analysis/methods.py) -------------------------

    def linearize(self, at: dict | None = None, parameters: dict | None = None, inputs: dict | None = None,
                  independent=(), extra_inputs=(), closed_loop: bool = False):
        """The linear model about `at` (as `lagcli linearize --at`: {name: number or
        expression text} of coordinates, velocities (`q_dot`), parameters, inputs, `t`;
        what is not given is 0, parameters and inputs their spec value), with
        `parameters` and `inputs` changed for this call. `independent`: the independent
        coordinates and speeds of a constrained system; `extra_inputs`: parameters taken
        as inputs too (`--input`); `closed_loop`: the spec's input laws substituted first
        (`--closed-loop`). A `lagcli.analysis.results.Linearization`: A, B, M, C, K (numpy
        arrays), eigenvalues, verdict, the point used."""
        from lagcli.analysis import methods

        return methods.linearize(self, at, parameters, inputs, independent, extra_inputs, closed_loop)

    def linearize_sweep(self, variable: str, values, at: dict | None = None, parameters: dict | None = None,
                        inputs: dict | None = None, independent=(), extra_inputs=(), find_critical: bool = False,
                        closed_loop: bool = False):
        """`linearize` at each of `values` of `variable` (a parameter, or a name the `at`
        expressions use), as `lagcli linearize --sweep` (`--find-critical`: where the count
        of unstable eigenvalues changes). A `lagcli.analysis.sweep.LinearizationSweep`."""
        from lagcli.analysis import methods

        return methods.linearize_sweep(self, variable, values, at, parameters, inputs, independent,
                                       extra_inputs, find_critical, closed_loop)

    def linearize_symbolic(self, at: dict | None = None, extra_inputs=(), closed_loop: bool = False):
        """A and B as sympy matrices of the parameters (`lagcli linearize --symbolic`; small
        unconstrained systems): a `lagcli.analysis.symbolic.SymbolicLinear`."""
        from lagcli.analysis import methods

        return methods.linearize_symbolic(self, at, extra_inputs, closed_loop)

    def equilibria(self, parameters: dict | None = None, inputs: dict | None = None, guesses=None):
        """The equilibria (q' = 0) with their stability, as `lagcli equilibria`; `guesses`:
        starting points [{coordinate: value}] of the numeric search. A
        `lagcli.analysis.results.Equilibria` (a sequence of `Equilibrium`)."""
        from lagcli.analysis import methods

        return methods.equilibria(self, parameters, inputs, guesses)

    def hamiltonian(self):
        """Momenta, H(q, p, t) and Hamilton's equations (`lagcli hamiltonian`): a
        `lagcli.analysis.results.Hamiltonian` of sympy expressions."""
        from lagcli.analysis import methods

        return methods.hamiltonian(self)

    def routh(self, momenta: dict | None = None, parameters: dict | None = None, inputs: dict | None = None,
              guesses=None):
        """The Routhian over the cyclic coordinates and, given every cyclic `momenta`
        ({"p_phi": 0.5}), the steady motions (`lagcli routh`): a `lagcli.analysis.results.Routh`."""
        from lagcli.analysis import methods

        return methods.routh(self, momenta, parameters, inputs, guesses)

    def _module(self):
        """The generated Python module, its source kept in the cache; made once per System."""
        return self._once("_generated_module", self._make_module)

    def _make_module(self):
        from lagcli.run import cache, python_backend

        key = cache.cache_key(self.model.source, self.spec_bytes, python_backend.MODULE_VARIANT)
        source = python_backend.cached_source(key)
        if source is None:
            (source,) = self._sources("python").values()
            python_backend.store(key, self.name, source)
        return python_backend.module_of(self.name, source)

    def _driver(self, compiler, laws: dict):
        """The compiled driver in the cache, generated (C target) and built when missing.
        `laws` (input name -> sympy law): the model is generated with them substituted
        (`lagcli.derive.closed_loop`), so the law is C code of the driver, and part of its
        cache key: a cached driver is never reused for another law. A spec with laws never
        has a driver under the plain key, which the warm path looks up."""
        from lagcli.run import c_backend

        spec_bytes = self.spec_bytes
        if laws or self.model.laws:
            spec_bytes += ("\0laws:" + ";".join(f"{k}={v!s}" for k, v in sorted(laws.items()))).encode()
        key = c_backend.cache_key(self.model.source, spec_bytes, compiler)
        found = c_backend.lookup(key)
        if found is not None:
            return found
        derivation = self.derivation
        if laws:
            from lagcli.derive.closed_loop import closed_loop

            derivation = closed_loop(derivation, laws)
        return c_backend.build(self._sources("c", derivation), key, compiler, self.layout)

    def _sources(self, target: str, derivation=None) -> dict[str, str]:
        """The generated sources of a program (`lagcli.targets.program_sources`), embedding
        the consistent default state of the layout."""
        from lagcli.targets import program_sources

        start = self.layout.start
        return program_sources(derivation or self.derivation, target, start.values, start.notes, self.layout)

    def _once(self, name: str, make):
        if name not in self.__dict__:
            object.__setattr__(self, name, make())        # a cache, not state
        return self.__dict__[name]

    def _parameters(self, parameters: dict | None) -> dict[str, float]:
        given = dict(parameters or {})
        self._known("parameters", given, self.layout.parameter_names, "parameter")
        return {k: float(v) for k, v in given.items()}

    def _inputs(self, inputs: dict | None) -> tuple[dict[str, float], dict]:
        """The constant inputs {name: value} and the laws {name: sympy law or callable}."""
        from lagcli.model.hybrid_model import parse_law
        from lagcli.targets.numeric import input_number, law_callable

        given = dict(inputs or {})
        self._known("inputs", given, self.layout.input_names, "input")
        constants, laws = {}, {}
        for name, value in given.items():
            if isinstance(value, str):
                laws[name] = parse_law(self.model, name, value, f"inputs={{{name!r}: ...}}").expr
            elif callable(value):
                laws[name] = law_callable(name, value)
            else:
                constants[name] = input_number(name, value)
        return constants, laws

    def _known(self, argument: str, given: dict, allowed, what: str) -> None:
        unknown = [name for name in given if name not in allowed]
        if unknown:
            raise UsageError(f"{argument}=: unknown {what} {unknown[0]!r}\n"
                             f"  hint: known names are: {', '.join(allowed) or '(none)'}")

    # --- rich display -------------------------------------------------------------------

    def _repr_latex_(self) -> str:
        """The equations of motion and the constraints, for Jupyter (MathJax): the rows of
        `lagcli derive --latex`, long ones broken, big expressions through named quantities."""
        return "$$" + self.parts.latex_of("equations", "constraints") + "$$"

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



def _refuse_impossible(derivation, params: dict[str, float], option: str) -> None:
    """Physical validation at the parameter values of a run (`--set m=0`): an impossible
    mass or inertia, or a mass matrix singular at the start, is said as such before any run
    (not as a singular matrix at t = 0)."""
    from lagcli.model.validation import problems_at

    problems = problems_at(derivation, params)
    if problems:
        spec = {p.symbol.name: p.value for p in derivation.model.parameters}
        changed = ", ".join(f"{name}={value:g}" for name, value in params.items() if value != spec[name])
        raise UsageError("\n".join(f"{option} {changed}: {p}" for p in problems))
