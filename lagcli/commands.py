"""What each CLI command does, without click: path + options in, text out.

`derive`, `check`, `generate` and `simulate` are thin clients of the Python API
(`lagcli.system.System`; `simulate` through `lagcli.simulate.run`, whose cold path
loads a System). The engine (sympy) is imported inside the functions, not at the
top: `lagcli simulate` with a warm C cache must start without importing sympy at all.
"""
from __future__ import annotations

from pathlib import Path


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


def check_summary(path: str) -> str:
    """Validate the spec (through the derivation, which classifies constraints) and summarise."""
    from lagcli.emit.report import check_content
    from lagcli.emit.templates import render

    return render("report/check.txt.jinja", c=check_content(_derive(path)))


PLOT_ROWS = 20_000     # --plot draws at most 2 x this many rows (evenly thinned) plus the last


def simulate(request, output: str | None = None, plot: str | None = None,
             note=lambda text: None, progress=None) -> None:
    """`lagcli simulate`: run `request` (a lagcli.simulate.options.Request), writing the
    CSV to `output` (stdout for None or '-') row by row as it is computed, then the PNG
    to `plot`.  Both targets are checked, and `output` opened, before any work starts.
    The CSV is kept even when the integration fails or is interrupted (the rows so
    far); the error is raised after it.  `note` and `progress`: see
    lagcli.simulate.run.simulate."""
    from lagcli.errors import SimulationError
    from lagcli.output import open_output, resolve_target
    from lagcli.simulate.run import Interrupted, simulate as run
    from lagcli.simulate.trajectory import CsvSink, Decimated, Tee

    if plot:
        resolve_target(plot)
    with open_output(output) as out:
        csv = CsvSink(out.stream)
        shown = Decimated(PLOT_ROWS) if plot else None        # the plot's bounded copy
        outcome = run(request, note, progress, Tee(csv, shown) if shown else csv)
    sink = outcome.trajectory
    plot_error = None
    if plot and sink.rows:
        from lagcli.simulate.plot import plot_png
        try:
            plot_png(shown.trajectory(), outcome.coordinates, outcome.energy_conserved, plot, request.spec)
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


def generate(path: str, lang: str, output: str | None = None) -> None:
    """`lagcli generate`: code or a document for `path` in `lang` (see lagcli.emit.LANGUAGES).

    One-file languages write to `output` (stdout for None or '-'); C writes its files
    into the directory `output` (required; created if only it is missing), each
    atomically, after all are made.  The target is checked before deriving."""
    from lagcli.emit import LANGUAGES
    from lagcli.errors import UsageError
    from lagcli.output import check_directory_output, open_output
    from lagcli.system import load

    language = LANGUAGES.get(lang)
    if language is not None and language.directory:
        if output in (None, "-"):
            raise UsageError(f"--lang {lang} writes several files: give the directory with -o DIR")
        check_directory_output(output)
        load(Path(path)).generate(lang, output)
        return
    with open_output(output) as out:
        (text,) = load(Path(path)).generate(lang).values()
        out.stream.write(text)


# -- analysis: lagcli linearize / equilibria / hamiltonian / routh (lagcli/analysis/) --

def linearize(path: str, at=(), independent=(), inputs=(), sweep: str | None = None,
              find_critical: bool = False, fmt: str = "text", symbolic: bool = False) -> str:
    """`lagcli linearize`: the linear model about `--at`, or the eigenvalue table of a sweep."""
    from lagcli.analysis import report
    from lagcli.analysis.linearize import CompiledSystem, linearize as linear_model
    from lagcli.analysis.operating_point import evaluate, parse_assignments
    from lagcli.analysis.stability import stability
    from lagcli.analysis.sweep import critical_values, parse_sweep, sweep as run_sweep
    from lagcli.errors import UsageError

    d = _derive(path)
    span = parse_sweep(sweep) if sweep else None
    if find_critical and span is None:
        raise UsageError("--find-critical needs --sweep NAME=START:STOP:COUNT")
    points = parse_assignments(d, at, span.name if span else None)
    if symbolic:
        return _symbolic_linear(d, points, inputs, fmt)
    system = CompiledSystem(d, inputs)
    if span is not None:
        table = run_sweep(system, points, span.values, independent)
        critical = critical_values(system, points, table, independent) if find_critical else []
        content = report.sweep_content(span.name, table, critical)
        if fmt == "latex":
            raise UsageError("--sweep prints a table: use the text or --json output")
        return report.to_json(content) if fmt == "json" else report.sweep_text(content)
    lm = linear_model(system, evaluate(d, points), independent)
    content = report.linear_content(d, lm, stability(lm))
    if fmt == "json":
        return report.to_json(content)
    if fmt == "latex":
        return report.linear_latex(content, _latex_names(d))
    return report.linear_text(content)


def _symbolic_linear(d, points, inputs, fmt: str) -> str:
    from lagcli.analysis import report
    from lagcli.analysis.symbolic import symbolic_linear
    from lagcli.emit.latex_printer import LatexPrinter
    from lagcli.spec_printer import spec_str

    params = [p.symbol.name for p in d.model.parameters]
    unknown = [name for name in inputs if name not in params]
    if unknown:
        from lagcli.errors import UsageError
        raise UsageError(f"--input {unknown[0]!r}: not a parameter")
    lin = symbolic_linear(d, points, inputs)
    if fmt == "latex":
        return report.symbolic_latex(lin, LatexPrinter(d.model))
    content = report.symbolic_content(d, lin, spec_str)
    return report.to_json(content) if fmt == "json" else report.symbolic_text(content)


def _latex_names(d):
    """name -> LaTeX of a coordinate, velocity or parameter, by the LaTeX emitter's printer."""
    from lagcli.emit.latex_printer import LatexPrinter

    printer = LatexPrinter(d.model)
    return lambda name: printer.doprint(d.model.symbol(name))


def _parameters(d, sets) -> dict:
    """Every parameter's value by name: the spec's, overridden by `--set NAME=VALUE`."""
    from lagcli.simulate.options import parse_assignments as assignments

    names = [p.symbol.name for p in d.model.parameters]
    return {p.symbol.name: float(p.value) for p in d.model.parameters} | assignments(
        tuple(sets), "--set", names, "parameter", "parameters")


def _guesses(d, guesses) -> list[dict]:
    """`--guess theta=1.2,phi=0` (one starting point each) -> [{name: value}]."""
    from lagcli.simulate.options import parse_assignments as assignments

    names = [s.name for s in (*d.model.q, *d.multipliers)]
    return [assignments(tuple(g.split(",")), "--guess", names, "coordinate", "coordinates") for g in guesses]


def equilibria(path: str, sets=(), guesses=(), fmt: str = "text") -> str:
    """`lagcli equilibria`: static and relative equilibria with their stability."""
    from lagcli.analysis import report
    from lagcli.analysis.equilibria import default_guesses, equilibria as find
    from lagcli.spec_printer import spec_str

    d = _derive(path)
    found = find(d, _parameters(d, sets), default_guesses(d, _guesses(d, guesses)))
    content = report.equilibria_content(d, found, spec_str)
    return report.to_json(content) if fmt == "json" else report.equilibria_text(content)


def routh(path: str, momenta=(), sets=(), guesses=(), fmt: str = "text") -> str:
    """`lagcli routh`: the Routhian over the cyclic coordinates and the steady motions."""
    from lagcli.analysis import report
    from lagcli.analysis.routh import routhian, steady_motions
    from lagcli.simulate.options import parse_assignments as assignments
    from lagcli.spec_printer import spec_str

    d = _derive(path)
    reduction = routhian(d)
    names = [p.name for p in reduction.momenta]
    given = assignments(tuple(momenta), "--momentum", names, "momentum", "momenta")
    motions = []
    if given:
        missing = [n for n in names if n not in given]
        if missing:
            from lagcli.errors import UsageError
            raise UsageError(f"--momentum: give every cyclic momentum (missing: {', '.join(missing)})")
        guess_points = [{k: v for k, v in g.items()} for g in _guesses(d, guesses)] or [dict(d.model.initial), {}]
        motions = steady_motions(d, reduction, given, _parameters(d, sets), guess_points)
    content = report.routh_content(d, reduction, motions, spec_str)
    return report.to_json(content) if fmt == "json" else report.routh_text(content)


def hamiltonian(path: str, fmt: str = "text") -> str:
    """`lagcli hamiltonian`: momenta, H(q, p, t) and Hamilton's equations."""
    from lagcli.analysis import report
    from lagcli.analysis.hamiltonian import hamilton_form
    from lagcli.emit.latex_printer import LatexPrinter
    from lagcli.spec_printer import spec_str

    d = _derive(path)
    form = hamilton_form(d)
    if fmt == "latex":
        printer = LatexPrinter(d.model)
        printer._settings["symbol_names"].update({p: f"p_{{{printer.doprint(q)}}}"
                                                  for p, q in zip(form.momenta, d.model.q)})
        return report.hamilton_latex(form, d, printer)
    content = report.hamilton_content(d, form, spec_str)
    return report.to_json(content) if fmt == "json" else report.hamilton_text(content)
