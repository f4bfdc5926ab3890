"""What each CLI command does, without click: path + options in, text out.

`derive`, `check`, `generate` and `simulate` are thin clients of the Python API
(`lagcli.system.System`; `simulate` through `lagcli.run.simulate`, whose cold path
loads a System). The engine (sympy) is imported inside the functions, not at the
top: `lagcli simulate` with a warm C cache must start without importing sympy at all.
"""
from __future__ import annotations

from pathlib import Path

from lagcli.model.collector import collector_paused


def _derive(path: str):
    from lagcli.system import load

    return load(Path(path)).derivation


def derive_text(path: str, simplify: bool = True, parts: str | None = None) -> str:
    """The text report; `parts`: the sections to print ("equations,energies"; None: all)."""
    from lagcli.system import load

    return load(Path(path)).report("text", simplify, parts)


def derive_json(path: str, simplify: bool = True) -> str:
    from lagcli.system import load

    return load(Path(path)).report("json", simplify)


def derive_latex(path: str, simplify: bool = True, standalone: bool = False,
                 parts: str | None = None) -> str:
    """LaTeX (a fragment or, `standalone`, a document); `parts` as for `derive_text`."""
    from lagcli.system import load

    return load(Path(path)).report("latex-document" if standalone else "latex", simplify, parts)


def page(path: str, output: str | None = None, pictures: bool = True, note=lambda text: None) -> None:
    """`lagcli report`: the page to share (`System.page`), to `output` (stdout for None or '-')."""
    from lagcli.render.output import write_output
    from lagcli.system import load

    write_output(output, load(Path(path)).page(pictures=pictures))
    _wrote(output, note)


def check_summary(path: str) -> str:
    """Validate the spec (through the derivation, which classifies constraints) and summarise."""
    from lagcli.report.content import check_content
    from lagcli.render.templates import render

    from lagcli.model.units import check_derivation_units

    derivation = _derive(path)
    check_derivation_units(derivation)
    derivation.forcing   # computed on first use and refused then, as by every command that uses F (representable.py)
    return render("report/check.txt.jinja", c=check_content(derivation))


PLOT_ROWS = 20_000     # --plot draws at most 2 x this many rows (evenly thinned) plus the last


def simulate(request, output: str | None = None, plot: str | None = None,
             note=lambda text: None, progress=None, columns=None, phase=(), events: str | None = None) -> None:
    """`lagcli simulate`: run `request` (a lagcli.run.options.Request), writing the
    CSV to `output` (stdout for None or '-') row by row as it is computed, then the
    picture to `plot` (PNG, SVG or PDF by its extension).  Both targets are checked, and
    `output` opened, before any work starts. The CSV is kept even when the integration
    fails or is interrupted (the rows so far); the error is raised after it.  `note` and
    `progress`: see `run_request`. `events`: the file of one row per event (`--events`),
    written after the run; a run with events also says on stderr what happened."""
    from lagcli.errors import SimulationError
    from lagcli.render.output import open_output, resolve_target
    from lagcli.run.rows import CsvSink, Decimated, Tee
    from lagcli.run.simulate import Interrupted

    for target in (plot, events):
        if target:
            resolve_target(target)
    if plot:
        from lagcli.viz.plot import figure_format
        figure_format(plot)
    with open_output(output) as out:
        csv = CsvSink(out.stream)
        shown = Decimated(PLOT_ROWS) if plot else None        # the plot's bounded copy
        outcome = run_request(request, note, progress, Tee(csv, shown) if shown else csv)
    sink = outcome.trajectory
    _report_events(sink, outcome, events, note)
    plot_error = None
    if plot and sink.rows:
        from lagcli.viz.plot import PlotOptions, plot_file
        try:                   # the title, angles and units from the run interface: no model rebuilt
            layout = outcome.layout
            plot_file(shown.trajectory(), outcome.coordinates, outcome.energy_conserved, plot, layout.name,
                      PlotOptions(columns, tuple(phase), layout.angles, layout.units, layout.kinds))
        except SimulationError as exc:
            plot_error = exc
    where = "stdout" if output in (None, "-") else output
    kept = (f"{sink.rows} rows up to t = {sink.last_time:.10g} kept in {where}" if sink.rows
            else f"no rows computed; the header was written to {where}")
    if sink.failure:
        raise SimulationError(f"{request.spec}: integration failed {sink.failure} ({kept})")
    if sink.interrupted:
        raise Interrupted(f"{request.spec}: interrupted ({kept})")
    if plot_error:
        raise plot_error


def _report_events(sink, outcome, events: str | None, note) -> None:
    """The summary line and the end note of a run with events on stderr; the --events file."""
    from lagcli.run.records import events_csv, summary
    from lagcli.render.output import write_output

    if sink.events or outcome.watched_events:
        note(summary(sink.events))
    if sink.end_note:
        note(f"note: {sink.end_note}")
    if events:
        write_output(events, events_csv(sink.events, outcome.states))


def column_units(spec: str) -> str:
    """`lagcli simulate SPEC --units`: `column,kind,unit` of each CSV column (the unit empty
    where the spec gives none), from the cached driver's run interface when there is one."""
    from lagcli.run import c_backend, simulate as runs
    from lagcli.spec.files import read_spec_bytes

    spec_bytes = read_spec_bytes(spec)
    compiler = c_backend.find_compiler()
    driver = runs.cached_driver(spec, spec_bytes, compiler) if compiler else None
    if driver is not None:
        layout = driver.layout
    else:
        from lagcli.system import load_file

        layout = load_file(spec, spec_bytes).layout
    return "column,kind,unit\n" + "".join(f"{c.name},{c.kind},{c.unit or ''}\n" for c in layout.columns)


def run_request(request, note=lambda text: None, progress=None, sink=None, system=None):
    """One run of `request`, its rows given to `sink` (in memory when None): the cached
    driver of this very spec when there is one (no sympy: the run interface and the
    program come from the cache), else through the System (derive, make the initial
    state consistent, generate and build the program). Either way the run layer gets
    the same two values, a `lagcli.interface.Layout` and a program. `note(text)`
    receives remarks for stderr; `progress(t_end)` is a context manager yielding
    `update(t)` (or None); `system`: the System of the spec when the caller has it.
    Returns a `lagcli.run.simulate.Outcome`."""
    from lagcli.run.rows import Trajectory
    from lagcli.run.simulate import Interrupted

    try:
        return _run_request(request, note, progress, Trajectory() if sink is None else sink, system)
    except KeyboardInterrupt:
        raise Interrupted(f"{request.spec}: interrupted before the integration started "
                          "(while deriving, generating or compiling); nothing was written") from None


def _run_request(request, note, progress, sink, system):
    from lagcli.interface import C_METHODS
    from lagcli.run import c_backend, simulate as runs
    from lagcli.run.options import parse_overrides, resolve_settings
    from lagcli.runtime.run_rules import EXPLICIT_METHODS
    from lagcli.spec.files import read_spec_bytes

    spec_bytes = read_spec_bytes(request.spec)       # once: the cache key and the model
    compiler = c_backend.find_compiler()
    if request.backend == "c":
        c_backend.require_compiler(request.method or EXPLICIT_METHODS[0])   # before any work
    if compiler and request.backend in (None, "c") and request.method in (None, *C_METHODS) \
            and not request.inputs and system is None:
        driver = runs.cached_driver(request.spec, spec_bytes, compiler)
        if driver is not None:
            outcome = _warm_run(driver, request, note, progress, sink, spec_bytes)
            if outcome is not None:
                return outcome
    if system is None:
        from lagcli.system import load_file

        system = load_file(request.spec, spec_bytes)
    layout = system.layout
    settings = resolve_settings(request, layout.settings.as_dict())
    overrides = parse_overrides(layout, request.sets, request.inits)
    laws = input_laws(request.inputs, system)
    backend = request.backend or ("c" if compiler and settings.method in C_METHODS else "python")
    if request.backend is None and system.compiled_laws(overrides.values, laws) is None:
        if backend == "c":
            note(f"lagcli: {system.python_only(system.laws(overrides.values, laws))} runs on the Python backend")
        backend = "python"
    start = system.start(overrides.values, overrides.initial)
    for text in runs.at_rest(layout.initial, overrides.initial) + list(start.notes):
        note(text)
    system._check_method(settings.method, overrides.values, laws)
    program = system.program(backend, settings.method, overrides.values, laws)
    sink, drift = runs.watched(settings, layout, sink)
    rows = runs.run(program, settings, overrides, start.values, sink, progress)
    runs.drift_note(drift, settings, note)
    return runs.Outcome(rows, backend, layout, bool(system.model.events))


def _warm_run(driver, request, note, progress, sink, spec_bytes):
    """The run on the cached driver alone, or None when the System must solve for the state."""
    from lagcli.interface import C_METHODS, VARIATIONAL
    from lagcli.run import simulate as runs
    from lagcli.run.options import parse_overrides, resolve_settings

    layout = driver.layout
    settings = resolve_settings(request, layout.settings.as_dict())
    if settings.method not in C_METHODS or (settings.method == VARIATIONAL and any(
            m.kind != "holonomic" for m in layout.multipliers)):
        return None                           # the cold path refuses it, naming the constraint
    overrides = parse_overrides(layout, request.sets, request.inits)
    start = runs.warm_start(layout, overrides)
    if start is None:
        return None
    state, notes, limit = start
    watched, drift = runs.watched(settings, layout, sink)
    rows = runs.run(driver, settings, overrides, state, watched, progress, limit)
    if rows is None:
        return None
    if overrides.values and rows.failure and rows.rows <= 1:      # --set m=0: say why, as the cold path does
        from lagcli.system import load_file

        load_file(request.spec, spec_bytes).start(overrides.values, {})
    for text in runs.at_rest(layout.initial, overrides.initial) + list(notes):
        note(text)
    runs.drift_note(drift, settings, note)
    return runs.Outcome(rows, "c", layout, bool(layout.events))


def input_laws(items, system) -> dict:
    """--input NAME=EXPR (simulate, sweep, animate) as {name: sympy law}, parsed with the
    safe parser."""
    from lagcli.model.hybrid_model import parse_law
    from lagcli.run.options import parse_assignments

    given = parse_assignments(items, "--input", list(system.layout.input_names), "input", "inputs",
                              lambda text, where: text)
    return {name: parse_law(system.model, name, text.strip(), f"--input {name}").expr
            for name, text in given.items()}


@collector_paused()
def generate(path: str, lang: str, output: str | None = None, form: str = "lagrangian",
             note=lambda text: None, variational: bool | None = None) -> None:
    """`lagcli generate`: code or a document for `path` in `lang` (see lagcli.targets.LANGUAGES).

    One-file languages write to `output` (stdout for None or '-'; the FMU's zip needs
    `output`, '-' for stdout); C writes its files
    into the directory `output` (required; created if only it is missing), each
    atomically, after all are made.  The target is checked before deriving.
    `form="hamiltonian"`: the Python module in (q, p) of lagcli/targets/hamilton.py.
    `variational`: see `System.generate`.
    `note(text)` is told what was written ("wrote dp_c/: 8 files"), unless it went to stdout."""
    from lagcli.targets import LANGUAGES
    from lagcli.errors import UsageError
    from lagcli.render.output import check_directory_output, open_output
    from lagcli.system import load

    if form == "hamiltonian":
        if lang != "python":
            raise UsageError(f"--form hamiltonian: generated for --lang python only (not {lang})")
        from lagcli.interface import layout_of
        from lagcli.targets.hamilton import hamilton_module
        with open_output(output) as out:
            derivation = _derive(path)
            out.stream.write(hamilton_module(derivation, layout_of(derivation)))
        _wrote(output, note)
        return

    language = LANGUAGES.get(lang)
    if language is not None and language.directory:
        if output in (None, "-"):
            raise UsageError(f"--lang {lang} writes several files: give the directory with -o DIR")
        check_directory_output(output)
        files = load(Path(path)).generate(lang, output, variational)
        note(f"wrote {output}: {len(files)} file{'s' if len(files) != 1 else ''}")
        return
    binary = language is not None and language.binary
    if binary and output is None:
        raise UsageError(f"--lang {lang} writes a zip archive: give its file with -o NAME.{lang} "
                         "(or -o - for stdout)")
    with open_output(output, binary=binary) as out:
        (data,) = load(Path(path)).generate(lang, variational=variational).values()
        out.stream.write(data)
    _wrote(output, note)


def _wrote(output: str | None, note) -> None:
    if output not in (None, "-"):
        note(f"wrote {output}")


# -- analysis: lagcli linearize / equilibria / hamiltonian / routh (lagcli/analysis/) --

def linearize(path: str, at=(), independent=(), inputs=(), sweep: str | None = None,
              find_critical: bool = False, fmt: str = "text", symbolic: bool = False,
              closed: bool = False, sets=(), inits=()) -> str:
    """`lagcli linearize`: the linear model about `--at`, or the eigenvalue table of a sweep
    (`System.linearize`, `linearize_sweep`, `linearize_symbolic`, formatted); `closed`: with
    the spec's input laws substituted (lagcli/derive/closed_loop.py). `--set` (parameters,
    inputs) and `--init` (coordinates, velocities) as every command reads them; they win
    over `--at` of the same name."""
    from lagcli.analysis import report
    from lagcli.analysis.operating_point import parse_assignments
    from lagcli.analysis.sweep import parse_sweep
    from lagcli.errors import UsageError
    from lagcli.run.options import parse_overrides
    from lagcli.system import load

    system = load(Path(path))
    overrides = parse_overrides(system.layout, sets, inits)
    span = parse_sweep(sweep) if sweep else None
    if find_critical and span is None:
        raise UsageError("--find-critical needs --sweep NAME=START:STOP:COUNT")
    points = parse_assignments(system.derivation, at, span.name if span else None).given(
        {**overrides.values, **overrides.initial})
    if symbolic:
        return _symbolic_linear(system, points, inputs, fmt, closed)
    if span is not None:
        found = system.linearize_sweep(span.name, span.values, points, independent=independent,
                                       extra_inputs=inputs, find_critical=find_critical, closed_loop=closed)
        if fmt == "latex":
            raise UsageError("--sweep prints a table: use the text or --json output")
        content = report.sweep_content(found)
        return report.to_json(content) if fmt == "json" else report.sweep_text(content)
    lin = system.linearize(points, independent=independent, extra_inputs=inputs, closed_loop=closed)
    content = report.linear_content(lin)
    if fmt == "json":
        return report.to_json(content)
    if fmt == "latex":
        return report.linear_latex(content, lin.latex_names.__getitem__)
    return report.linear_text(content)


def _symbolic_linear(system, points, inputs, fmt: str, closed: bool) -> str:
    from lagcli.analysis import report
    from lagcli.report.latex_printer import LatexPrinter
    from lagcli.render.spec_printer import spec_str

    d = system.derivation
    lin = system.linearize_symbolic(points, inputs, closed_loop=closed)
    if fmt == "latex":
        return report.symbolic_latex(d, lin, LatexPrinter(d.model))
    content = report.symbolic_content(d, lin, spec_str)
    return report.to_json(content) if fmt == "json" else report.symbolic_text(content)


def _constants(system, sets, inits=()) -> tuple[dict, dict, dict]:
    """`--set NAME=VALUE` (parameters and inputs) and `--init` (coordinates and velocities),
    read by the one parser of every command -> (parameters, inputs, initial values) by name."""
    from lagcli.run.options import parse_overrides

    layout = system.layout
    overrides = parse_overrides(layout, sets, inits)
    return ({k: v for k, v in overrides.values.items() if k in layout.parameter_names},
            {k: v for k, v in overrides.values.items() if k in layout.input_names}, overrides.initial)


def _guesses(system, guesses) -> list[dict]:
    """`--guess theta=1.2,phi=0` (one starting point each) -> [{name: value}]."""
    from lagcli.run.options import parse_assignments as assignments

    d = system.derivation
    names = [s.name for s in (*d.model.q, *d.multipliers)]
    return [assignments(tuple(g.split(",")), "--guess", names, "coordinate", "coordinates") for g in guesses]


def equilibria(path: str, sets=(), guesses=(), fmt: str = "text", inits=()) -> str:
    """`lagcli equilibria`: static and relative equilibria with their stability (`System.equilibria`);
    the `--init` values of coordinates are one starting point of the search, as a `--guess`."""
    from lagcli.analysis import report
    from lagcli.render.spec_printer import spec_str
    from lagcli.system import load

    system = load(Path(path))
    parameters, inputs, initial = _constants(system, sets, inits)
    start = {k: v for k, v in initial.items() if k in system.layout.coordinates}
    found = system.equilibria(parameters, inputs, _guesses(system, guesses) + ([start] if start else []))
    content = report.equilibria_content(found, spec_str)
    return report.to_json(content) if fmt == "json" else report.equilibria_text(content)


def routh(path: str, momenta=(), sets=(), guesses=(), fmt: str = "text") -> str:
    """`lagcli routh`: the Routhian over the cyclic coordinates and the steady motions (`System.routh`)."""
    from lagcli.analysis import report
    from lagcli.interface import momentum_name
    from lagcli.run.options import parse_assignments as assignments
    from lagcli.render.spec_printer import spec_str
    from lagcli.system import load

    system = load(Path(path))
    names = [momentum_name(q.name) for q in system.derivation.ignorable]
    given = assignments(tuple(momenta), "--momentum", names, "momentum", "momenta") if names else {}
    parameters, inputs, _ = _constants(system, sets)
    reduction = system.routh(given, parameters, inputs, _guesses(system, guesses))
    content = report.routh_content(reduction, spec_str)
    return report.to_json(content) if fmt == "json" else report.routh_text(content)


def hamiltonian(path: str, fmt: str = "text") -> str:
    """`lagcli hamiltonian`: momenta, H(q, p, t) and Hamilton's equations (`System.hamiltonian`)."""
    from lagcli.analysis import report
    from lagcli.render.spec_printer import spec_str
    from lagcli.system import load

    found = load(Path(path)).hamiltonian()
    if fmt == "latex":
        return report.hamilton_latex(found.form, found.derivation)
    content = report.hamilton_content(found, spec_str)
    return report.to_json(content) if fmt == "json" else report.hamilton_text(content)


def sweep(spec: str, plan_options: dict, options: dict, note=lambda text: None, progress=None):
    """`lagcli sweep`: the runs of a grid, samples or a table through the compiled driver;
    the summary written to options["output"] (docs/sweep.md)."""
    import lagcli
    from lagcli.run.options import parse_assignments, parse_overrides
    from lagcli.sweep import SweepOptions, make_plan, sweep as run_sweep

    plan = make_plan(**plan_options)                   # option mistakes before deriving
    system = lagcli.load(Path(spec))
    layout = system.layout
    laws = input_laws(options.pop("inputs", ()), system)
    overrides = parse_overrides(layout, options.pop("parameters"), options.pop("initial"))
    exceed = parse_assignments(options.pop("exceed"), "--exceed", list(layout.state_names),
                               "coordinate or velocity", "coordinates and velocities")
    result = run_sweep(system, plan, SweepOptions(**options, parameters=overrides.values, initial=overrides.initial,
                                                  exceed=exceed, inputs=laws), note, progress)
    statuses = list(result.column("status"))
    note(f"{len(statuses)} runs: {statuses.count('ok')} ok, {statuses.count('failed')} failed; "
         f"summary in {result.path}")
    return result


def animate(spec: str, csv_path: str | None, request, output: str, drawn: dict, note=lambda text: None):
    """`lagcli animate`: the motion of SPEC from a CSV of `lagcli simulate` (--csv) or a
    run made here with the request's settings (docs/animate.md); `drawn`: links,
    traces, fps, frame (the options of lagcli.viz.animate.Request)."""
    import numpy as np

    import lagcli
    from lagcli.errors import UsageError
    from lagcli.run.options import parse_overrides
    from lagcli.run.rows import parse_csv
    from lagcli.viz.animate import Request, animate as draw, check_names, parse_links

    system = lagcli.load(Path(spec))
    defaults = system.layout.parameter_defaults
    overrides = parse_overrides(system.layout, request.sets, request.inits)
    params = {**defaults, **{k: v for k, v in overrides.values.items() if k in defaults}}
    drawing = Request(parse_links(drawn.get("links", ())), tuple(drawn.get("traces", ())),
                      drawn.get("fps", 25.0), drawn.get("frame"))
    check_names(system.model, drawing)                # before a run is made
    if csv_path is not None:
        try:
            with open(csv_path, encoding="utf-8") as handle:
                text = handle.read()
        except OSError as exc:
            raise UsageError(f"--csv {csv_path}: cannot read it ({exc.strerror or exc})") from None
        header, rows = parse_csv(text)
    else:
        run = run_request(request, note, system=system).trajectory       # floats, in memory
        header, rows = run.header, run.data
    missing = [n for n in ("t", *system.layout.state_names) if n not in header]
    if missing or not len(rows):
        raise UsageError(f"{csv_path or 'the run'}: expected a CSV of lagcli simulate for {system.name} "
                         f"(missing columns: {', '.join(missing) or 'none'}; rows: {len(rows)})")
    data = np.asarray(rows, dtype=float)
    states = data[:, [header.index(n) for n in system.layout.state_names]]
    draw(system, data[:, header.index("t")], states, params, output, drawing)
