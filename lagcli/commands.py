"""What each CLI command does, without click: path + options in, text out.

The engine (sympy) is imported inside the functions, not at the top: `lagcli
simulate` with a warm C cache must start without importing sympy at all.
"""
from __future__ import annotations

import json


def _derive(path: str):
    from lagcli.api import load_model
    from lagcli.derive import derive

    return derive(load_model(path))


def derive_text(path: str, simplify: bool = True) -> str:
    from lagcli.emit.report import report_content
    from lagcli.spec_printer import spec_str
    from lagcli.emit.templates import render

    content = report_content(_derive(path), spec_str, simplify)
    return render("report/derive.txt.jinja", r=content)


def derive_json(path: str, simplify: bool = True) -> str:
    from lagcli.emit.report import report_content
    from lagcli.spec_printer import spec_str

    content = report_content(_derive(path), spec_str, simplify)
    return json.dumps(content, indent=2) + "\n"


def derive_latex(path: str, simplify: bool = True, standalone: bool = False) -> str:
    from lagcli.emit.latex import latex_document, latex_fragment

    derivation = _derive(path)
    return latex_document(derivation, simplify) if standalone else latex_fragment(derivation, simplify)


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

    One-file languages write to `output` (stdout for None or '-'); C writes its three
    files into the directory `output` (required; created if only it is missing), each
    atomically, after all are made.  The target is checked before deriving."""
    from lagcli.emit import LANGUAGES, generate as emit
    from lagcli.errors import UsageError
    from lagcli.output import check_directory_output, open_output, write_output

    language = LANGUAGES.get(lang)
    if language is not None and language.directory:
        if output in (None, "-"):
            raise UsageError(f"--lang {lang} writes several files: give the directory with -o DIR")
        directory = check_directory_output(output)
        files = _generated(path, lang, language, emit)
        directory.mkdir(exist_ok=True)
        for name, text in files.items():
            write_output(directory / name, text)
        return
    with open_output(output) as out:
        (text,) = _generated(path, lang, language, emit).values()
        out.stream.write(text)


def _generated(path: str, lang: str, language, emit) -> dict[str, str]:
    derivation = _derive(path)
    initial, notes = None, ()
    if language is not None and language.embeds_initial:   # solved for once, here, not in emit
        from lagcli.simulate.initial import spec_initial_state

        start, _ = spec_initial_state(derivation)
        initial, notes = start.values, start.notes
    return emit(derivation, lang, initial, notes)
