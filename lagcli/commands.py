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


def derive_text(path: str, simplify: bool = True, parts: str | None = None) -> str:
    """The text report; `parts`: the sections to print ("equations,energies"; None: all)."""
    from lagcli.emit.report import report_content, report_parts, spec_printer
    from lagcli.emit.templates import render

    chosen = report_parts(parts)
    content = report_content(_derive(path), spec_printer(), simplify, named=True)
    return render("report/derive.txt.jinja", r=content, parts=chosen)


def derive_json(path: str, simplify: bool = True) -> str:
    from lagcli.emit.report import report_content, spec_printer

    content = report_content(_derive(path), spec_printer(), simplify)
    return json.dumps(content, indent=2) + "\n"


def derive_latex(path: str, simplify: bool = True, standalone: bool = False,
                 parts: str | None = None) -> str:
    """LaTeX (a fragment or, `standalone`, a document); `parts` as for `derive_text`."""
    from lagcli.emit.latex import latex_document, latex_fragment
    from lagcli.emit.report import report_parts

    chosen = report_parts(parts)
    derivation = _derive(path)
    make = latex_document if standalone else latex_fragment
    return make(derivation, simplify, chosen)


def check_summary(path: str) -> str:
    """Validate the spec (through the derivation, which classifies constraints) and summarise."""
    from lagcli.emit.report import check_content
    from lagcli.emit.templates import render

    return render("report/check.txt.jinja", c=check_content(_derive(path)))


def simulate(request, output: str | None = None, plot: str | None = None,
             note=lambda text: None, progress=None) -> None:
    """`lagcli simulate`: run `request` (a lagcli.simulate.options.Request), write the CSV to
    `output` (stdout for None or '-'), then the PNG to `plot`.  The CSV is written even
    when the integration fails or is interrupted (the rows so far); the error is raised
    after it.  `note` and `progress`: see lagcli.simulate.run.simulate."""
    from lagcli.errors import SimulationError
    from lagcli.output import write_output
    from lagcli.simulate.run import Interrupted, simulate as run

    outcome = run(request, note, progress)
    traj = outcome.trajectory
    write_output(output, traj.csv_text())
    plot_error = None
    if plot and traj.lines:
        from lagcli.simulate.plot import plot_png
        try:
            plot_png(traj, outcome.coordinates, outcome.energy_conserved, plot, request.spec)
        except SimulationError as exc:
            plot_error = exc
    where = "stdout" if output in (None, "-") else output
    kept = (f"{len(traj.lines)} rows up to t = {traj.last_time:.10g} kept in {where}" if traj.lines
            else f"no rows computed; the header was written to {where}")
    if traj.failure:
        raise SimulationError(f"{request.spec}: integration failed {traj.failure} ({kept})")
    if traj.interrupted:
        raise Interrupted(f"{request.spec}: interrupted ({kept})")
    if plot_error:
        raise plot_error


def generate(path: str, lang: str, output: str | None = None) -> None:
    """`lagcli generate`: code or a document for `path` in `lang` (see lagcli.emit.LANGUAGES).

    One-file languages write to `output` (stdout for None or '-'); C writes its three
    files into the directory `output` (required), each atomically, after all are made."""
    from pathlib import Path

    from lagcli.emit import LANGUAGES, generate as emit
    from lagcli.errors import UsageError
    from lagcli.output import write_atomic, write_output

    language = LANGUAGES.get(lang)
    if language is not None and language.directory and output in (None, "-"):
        raise UsageError(f"--lang {lang} writes several files: give the directory with -o DIR")
    derivation = _derive(path)
    initial, notes = None, ()
    if language is not None and language.embeds_initial:   # solved for once, here, not in emit
        from lagcli.simulate.initial import spec_initial_state

        start, _ = spec_initial_state(derivation)
        initial, notes = start.values, start.notes
    files = emit(derivation, lang, initial, notes)
    if language.directory:
        directory = Path(output)
        if directory.exists() and not directory.is_dir():
            raise UsageError(f"-o {output}: not a directory")
        for name, text in files.items():
            write_atomic(directory / name, text)
    else:
        (text,) = files.values()
        write_output(output, text)
