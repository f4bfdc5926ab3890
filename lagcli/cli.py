"""The `lagcli` command line: options in, library call, output out, errors to exit codes."""
from __future__ import annotations

import atexit
import contextlib
import os
import sys
import threading
import traceback
import warnings
from typing import NoReturn

import click

# sympy's caches keep 1000 results each by default: on a big system the sort keys and
# canonical forms of its subexpressions fall out and are recomputed (the 40-link chain's
# `generate --lang c`: 14.7 s of CPU with 1000, 10.1 s with 20 000, 18 MB more). sympy
# reads this when first imported (lazily, after this line); a value the user set is kept.
os.environ.setdefault("SYMPY_CACHE_SIZE", "20000")

from lagcli import commands  # noqa: E402
from lagcli.model import collector
from lagcli.version import __version__
from lagcli.cli_options import LanguageChoice, note, quiet, quiet_option, settings_options, step_options
from lagcli.targets import LANGUAGES
from lagcli.render.escape import terminal_text
from lagcli.errors import LagcliError, RunNote, SpecWarning
from lagcli.interface import METHODS
from lagcli.runtime.interrupts import interrupt_on_termination
from lagcli.render.output import open_output, write_output
from lagcli.runtime.run_rules import EXPLICIT_METHODS

SPEC = click.Path(dir_okay=False, path_type=str)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="lagcli")
@click.option("--traceback", "show_traceback", is_flag=True, help="Show the Python traceback of errors.")
@quiet_option
@click.pass_context
def cli(ctx: click.Context, show_traceback: bool) -> None:
    """Equations of motion from a spec file, by Lagrange's method.

    SPEC is a .yaml, .yml or .toml file, or - for standard input (YAML, or TOML when
    its first line is a [table] or key = value). Every command takes -q/--quiet.
    """
    ctx.obj = {**(ctx.obj or {}), "traceback": show_traceback}    # -q may have set "quiet"
    ctx.with_resource(interrupt_on_termination())     # SIGTERM, SIGHUP: as Ctrl-C


def _run(ctx: click.Context, action) -> None:
    """Run `action`, mapping lagcli errors to a message on stderr and the exit status."""
    try:
        with _spec_warnings_on_stderr():
            action()
    except LagcliError as exc:
        if ctx.obj and ctx.obj.get("traceback"):
            traceback.print_exc()
        click.echo(terminal_text(exc.render()), err=True)   # messages quote spec text
        sys.exit(exc.exit_code)


@contextlib.contextmanager
def _spec_warnings_on_stderr():
    """Show each `SpecWarning` raised while running a command once, on stderr (even when
    the command then fails); other warnings go their usual way, once the recording has
    ended (shown while recording, each would be recorded again: a loop without end)."""
    caught: list = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", SpecWarning)
            warnings.simplefilter("always", RunNote)
            yield
    finally:
        shown = set()
        for item in caught:
            if isinstance(item.message, RunNote):
                if str(item.message) not in shown:
                    shown.add(str(item.message))
                    note(str(item.message))          # -q silences it, like every note
            elif not isinstance(item.message, SpecWarning):
                warnings.showwarning(item.message, item.category, item.filename, item.lineno)
            elif str(item.message) not in shown and not quiet():
                shown.add(str(item.message))
                click.echo(terminal_text(item.message.render()), err=True)


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--text", "as_text", is_flag=True, help="Readable sectioned report (default).")
@click.option("--latex", "as_latex", is_flag=True, help="LaTeX (a fragment; see --standalone).")
@click.option("--json", "as_json", is_flag=True, help="JSON with the contract's keys.")
@click.option("--standalone", is_flag=True, help="With --latex: a complete document for pdflatex.")
@click.option("--simplify/--no-simplify", default=True, show_default=True,
              help="Tidy small expressions for display (exact; never changes numerics).")
@click.option("--part", "parts", default=None, metavar="NAME[,NAME...]",
              help="With --text or --latex: only these sections (system, energies, forces, "
                   "equations, constraints, explicit, conservation).")
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def derive(ctx, spec, as_text, as_latex, as_json, standalone, simplify, parts, output):
    """Derive the equations of motion of SPEC and report them.

    \b
    Examples:
      lagcli derive specs/double_pendulum.yaml
      lagcli derive specs/double_pendulum.yaml --json -o eom.json
      lagcli derive specs/double_pendulum.yaml --latex --part equations,energies
    """
    chosen = [name for name, on in (("text", as_text), ("latex", as_latex), ("json", as_json)) if on]
    if len(chosen) > 1:
        raise click.UsageError(f"choose one output format, not {' and '.join('--' + c for c in chosen)}")
    fmt = chosen[0] if chosen else "text"
    if standalone and fmt != "latex":
        raise click.UsageError("--standalone goes with --latex")
    if parts is not None and fmt == "json":
        raise click.UsageError("--part goes with --text or --latex (JSON always has every key)")

    def action():
        with open_output(output) as out:      # a bad -o fails before deriving
            if fmt == "json":
                text = commands.derive_json(spec, simplify)
            elif fmt == "latex":
                text = commands.derive_latex(spec, simplify, standalone, parts)
            else:
                text = commands.derive_text(spec, simplify, parts)
            out.stream.write(text)
    _run(ctx, action)


@cli.command()
@click.argument("specs", nargs=-1, required=True, type=SPEC, metavar="SPEC...")
@click.option("--json", "as_json", is_flag=True,
              help="One record per file: file, valid, problems (file, line, column, path, severity, "
                   "message, hint).")
@quiet_option
@click.pass_context
def check(ctx, specs, as_json):
    """Validate each SPEC and summarise it: coordinates, constraints, DOF.

    Every file is checked, even after a broken one; the exit status is 2 if any is invalid.

    \b
    Examples:
      lagcli check specs/cart_pole.yaml
      lagcli check specs/*.yaml --json
      lagcli examples cart_pole | lagcli check -
    """
    from lagcli.spec.diagnostics import check_file, to_json

    verdicts = [check_file(spec, commands.check_summary) for spec in specs]
    if as_json:
        click.echo(to_json(verdicts), nl=False)
    for verdict in [] if as_json else verdicts:
        for warning in [] if quiet() else verdict.warnings:
            click.echo(terminal_text(warning.render()), err=True)
        if verdict.error is None:
            click.echo(verdict.summary, nl=False)
            continue
        if ctx.obj and ctx.obj.get("traceback"):
            traceback.print_exception(verdict.error)
        click.echo(terminal_text(verdict.error.render()), err=True)
    failed = [v.error.exit_code for v in verdicts if v.error is not None]
    if failed:
        sys.exit(max(failed))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("-o", "--output", default=None, help="The HTML file ('-' or none: stdout).")
@click.option("--no-pictures", is_flag=True,
              help="Leave out the simulation's plot and the animation (faster; no matplotlib needed).")
@quiet_option
@click.pass_context
def report(ctx, spec, output, no_pictures):
    """A page to share: SPEC's equations (MathML), linearization, plot and animation in
    one self-contained HTML file (no network needed to view it; docs/page.md).

    \b
    Examples:
      lagcli report specs/double_pendulum.yaml -o double_pendulum.html
      lagcli report specs/benchmark_bicycle.yaml --no-pictures -o bicycle.html
    """
    _run(ctx, lambda: commands.page(spec, output, not no_pictures, note=note))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--lang", required=True, type=LanguageChoice(LANGUAGES),
              help="python: one module (numpy); c: <name>.h, <name>.c, <name>_main.c; "
                   "octave: MATLAB/Octave functions and an ode45 script; rust: a crate; "
                   "latex: a standalone document; fmu: an FMI 2.0 FMU (needs cc); "
                   "casadi: a module of CasADi Functions (needs casadi to run); "
                   "jax: a module of jax.numpy functions (needs jax to run). Any letter case; "
                   "matlab is octave.")
@click.option("-o", "--output", default=None,
              help="Output file ('-' or none: stdout); for --lang c, octave, rust the directory (required); "
                   "for --lang fmu the .fmu file (required).")
@click.option("--form", type=click.Choice(["lagrangian", "hamiltonian"]), default="lagrangian",
              show_default=True,
              help="hamiltonian: a Python module whose state is (q, p), rhs = Hamilton's equations "
                   "(unconstrained systems).")
@click.option("--variational/--no-variational", default=None,
              help="python, c: with (or without) the variational integrator's functions "
                   "(--method variational). Default: with them when the system is small (every "
                   "bundled spec; the N-link chain up to N = 13): for a big system they cost several "
                   "times the rest of the code.")
@quiet_option
@click.pass_context
def generate(ctx, spec, lang, output, form, variational):
    """Generate code (Python, C, Octave, Rust, FMU, CasADi, JAX) or a LaTeX document from
    SPEC's equations of motion.

    \b
    Examples:
      lagcli generate specs/double_pendulum.yaml --lang python -o double_pendulum.py
      lagcli generate specs/double_pendulum.yaml --lang c -o double_pendulum/
      lagcli generate specs/cart_pole.yaml --lang casadi -o cart_pole_casadi.py
      lagcli generate specs/double_pendulum.yaml --lang jax -o double_pendulum_jax.py
      lagcli generate specs/spherical_pendulum.yaml --lang python --form hamiltonian -o sp_h.py
      lagcli generate big_chain.yaml --lang c --variational -o big_chain/
    """
    _run(ctx, lambda: commands.generate(spec, lang, output, form, note=note, variational=variational))


@cli.command()
@click.argument("spec", type=SPEC)
@settings_options(METHODS, "scipy's integrator name, or variational")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter, or hold an input constant (replacing its law); repeatable; "
                   "VALUE may be a constant expression.")
@click.option("--init", "inits", multiple=True, metavar="NAME=VALUE",
              help="Initial value of a coordinate or <q>_dot (repeatable); overrides `initial:`.")
@click.option("--input", "inputs", multiple=True, metavar="NAME=EXPR",
              help="A law for an input, of t, coordinates, velocities, parameters (repeatable; "
                   "overrides the spec's simulate: inputs:), e.g. --input 'F=-k*x - c*x_dot'.")
@click.option("--backend", type=click.Choice(["python", "c"]),
              help="c (compiled driver, cached) is the default when `cc` exists; else python "
                   "(and for runs with events or input laws).")
@step_options
@click.option("-o", "--output", default=None, help="CSV file ('-' or none: stdout).")
@click.option("--events", "events_path", default=None, metavar="FILE.csv",
              help="Write one row per event (t, event, action, state before and after, impulse).")
@click.option("--plot", default=None, metavar="FILE.png|svg|pdf",
              help="Also plot coordinates and drift (needs matplotlib), in the format the extension names.")
@click.option("--columns", default=None, metavar="NAME[,NAME...]",
              help="With --plot: draw these columns, one panel per kind (angles, lengths, velocities, ...).")
@click.option("--phase", "phase", multiple=True, metavar="Q",
              help="With --plot: add the phase portrait (Q_dot against Q) of coordinate Q (repeatable).")
@click.option("--units", "show_units", is_flag=True,
              help="Print each CSV column with its kind and unit (from the spec's unit:s) and exit.")
@quiet_option
@click.pass_context
def simulate(ctx, spec, t_end, dt, method, rtol, atol, sets, inits, inputs, backend, baumgarte, max_steps,
             steps_per_row, output, events_path, plot, columns, phase, show_units):
    """Integrate the equations of motion of SPEC and write the trajectory as CSV.

    \b
    Examples:
      lagcli simulate specs/double_pendulum.yaml -o traj.csv --plot traj.png
      lagcli simulate specs/cart_pole.yaml --plot p.png --columns x,theta,x_dot --phase theta -o c.csv
      lagcli simulate specs/hybrid/bouncing_ball.yaml --events bounces.csv -o ball.csv
      lagcli simulate specs/spherical_pendulum.yaml --method variational --dt 0.01 -o sp.csv
      lagcli simulate tests/data/units_cart_pendulum.yaml --units
    """
    from lagcli.run.options import Request

    if show_units:
        _run(ctx, lambda: write_output(output, commands.column_units(spec)))
        return

    if (columns or phase) and not plot:
        raise click.UsageError("--columns and --phase choose what --plot draws: give --plot FILE.png")
    request = Request(spec, t_end, dt, method, rtol, atol, tuple(sets), tuple(inits), backend,
                      tuple(baumgarte) if baumgarte else None, tuple(inputs), max_steps, steps_per_row)
    chosen = tuple(c.strip() for c in columns.split(",")) if columns else None
    _run(ctx, lambda: commands.simulate(request, output, plot, note=note,
                                        progress=_progress_bar, columns=chosen, phase=tuple(phase),
                                        events=events_path))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--grid", "grids", multiple=True, metavar="NAME=START:STOP:COUNT",
              help="COUNT values of a parameter, input or initial value (repeatable: their product).")
@click.option("--sample", "samples", multiple=True, metavar="NAME=DIST(A,B)",
              help="Random values: uniform(A,B) or normal(MU,SIGMA) (repeatable; with --count).")
@click.option("--count", type=int, help="Number of runs of --sample.")
@click.option("--seed", type=int, help="Seed of --sample's random generator (default 0).")
@click.option("--runs", metavar="TABLE.csv", help="One run per row; the header names the columns.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE", help="A parameter, or an input held constant, for every run (repeatable).")
@click.option("--init", "inits", multiple=True, metavar="NAME=VALUE",
              help="An initial value for every run (repeatable).")
@click.option("--input", "inputs", multiple=True, metavar="NAME=EXPR",
              help="A law for an input in every run, e.g. 'F=-k*x - c*x_dot' (repeatable).")
@click.option("--exceed", "exceed", multiple=True, metavar="NAME=VALUE",
              help="Summary column exceed_NAME: first output time with |NAME| > VALUE (repeatable).")
@settings_options(EXPLICIT_METHODS, "RK45 or DOP853, the compiled driver's")
@click.option("--trajectories", metavar="DIR", help="Also write each run's CSV as DIR/run_<id>.csv.")
@click.option("--workers", type=int, help="Local driver processes (default: every core).")
@click.option("--scheduler", metavar="ADDRESS", help="Run on a Dask cluster, e.g. tcp://127.0.0.1:8786.")
@click.option("-o", "--output", required=True, help="Summary file: .csv, or .parquet (pyarrow).")
@quiet_option
@click.pass_context
def sweep(ctx, spec, grids, samples, count, seed, runs, sets, inits, inputs, exceed, t_end, dt, method, rtol,
          atol, baumgarte, trajectories, workers, scheduler, output):
    """Run SPEC many times (a grid, random samples or a table) and summarise each run.

    One row per run in the summary: the varied values, ok/failed and why, the final
    state, extrema, invariant drift. An interrupted sweep resumes when run again.

    \b
    Examples:
      lagcli sweep specs/double_pendulum.yaml --grid theta1=-3:3:5 --grid theta2=-3:3:5 -o dp.csv
      lagcli sweep specs/double_pendulum.yaml --sample 'm2=uniform(0.5,2)' --count 100 --seed 1 -o mc.csv
      lagcli sweep specs/rolling_disc.yaml --runs speeds.csv --scheduler tcp://127.0.0.1:8786 -o disc.parquet
      lagcli sweep specs/hybrid/cart_pole_lqr.yaml --grid theta=0.1:0.3:3 --input 'F=-k2*theta' -o lqr.csv
    """
    plan = {"grids": grids, "samples": samples, "count": count, "seed": seed, "runs": runs}
    options = {"t_end": t_end, "dt": dt, "method": method, "rtol": rtol, "atol": atol,
               "baumgarte": tuple(baumgarte) if baumgarte else None, "parameters": sets, "initial": inits,
               "exceed": exceed, "output": output, "trajectories": trajectories, "workers": workers,
               "scheduler": scheduler, "inputs": inputs}
    _run(ctx, lambda: commands.sweep(spec, plan, options, note=note,
                                     progress=_count_bar))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--csv", "csv_path", metavar="TRAJ.csv", help="A CSV of `lagcli simulate` (default: run SPEC now).")
@click.option("--t-end", type=float, help="Without --csv: end time (default: the spec's).")
@click.option("--dt", type=float, help="Without --csv: output interval (default: the spec's).")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="A parameter, or an input held constant (repeatable; with --csv, the values the CSV "
                   "was made with).")
@click.option("--init", "inits", multiple=True, metavar="NAME=VALUE", help="Without --csv: an initial value.")
@click.option("--input", "inputs", multiple=True, metavar="NAME=EXPR",
              help="Without --csv: a law for an input, as for simulate (repeatable).")
@click.option("--link", "links", multiple=True, metavar="A:B",
              help="Draw a rod between two points (particle/body names or 'origin'; repeatable).")
@click.option("--trace", "traces", multiple=True, metavar="POINT", help="Draw the path of a point (repeatable).")
@click.option("--fps", type=float, default=25.0, show_default=True, help="Frames per second of simulated time.")
@click.option("--frame", type=float, metavar="T", help="Only the frame at time T, as a PNG, SVG or PDF.")
@click.option("-o", "--output", required=True,
              help="motion.gif, motion.mp4 (ffmpeg) or frame.png, .svg, .pdf (--frame).")
@quiet_option
@click.pass_context
def animate(ctx, spec, csv_path, t_end, dt, sets, inits, inputs, links, traces, fps, frame, output):
    """Draw the motion of SPEC: particles, bodies' axes, springs, rods, traces and the time.

    \b
    Examples:
      lagcli animate specs/double_pendulum.yaml --link origin:P1 --link P1:P2 --trace P2 -o motion.gif
      lagcli simulate specs/rolling_disc.yaml -o disc.csv
      lagcli animate specs/rolling_disc.yaml --csv disc.csv --trace disc --frame 2.5 -o disc.png
    """
    from lagcli.run.options import Request

    request = Request(spec, t_end, dt, sets=tuple(sets), inits=tuple(inits), inputs=tuple(inputs))
    drawing = {"links": links, "traces": traces, "fps": fps, "frame": frame}
    _run(ctx, lambda: commands.animate(spec, csv_path, request, output, drawing,
                                       note=note))


@contextlib.contextmanager
def _count_bar(total: int):
    """A progress bar over `total` runs on stderr when it is a terminal; yields update(done) or None."""
    if not sys.stderr.isatty():
        yield None
        return
    with click.progressbar(length=total, label="runs", file=sys.stderr) as bar:
        def update(done: int) -> None:
            bar.update(done - bar.pos)
        yield update


@cli.command()
@click.argument("name", required=False)
@click.option("--copy", "copy_to", metavar="DIR", help="Copy every bundled spec into DIR.")
@click.option("-o", "--output", default=None, help="With NAME: write the spec to this file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def examples(ctx, name, copy_to, output):
    """List the bundled example specs, print one (NAME), or copy them all (--copy DIR).

    \b
    Examples:
      lagcli examples                          # name and description of each
      lagcli examples double_pendulum -o dp.yaml
      lagcli examples --copy my_specs/ && lagcli derive my_specs/double_pendulum.yaml
    """
    from lagcli.spec import examples as bundled

    def action():
        if copy_to:
            written = bundled.copy_all(copy_to)
            note(f"copied {len(written)} specs into {copy_to}")
        elif name:
            write_output(output, bundled.find(name).read_text(encoding="utf-8"))
        else:
            click.echo(bundled.listing(), nl=False)
    _run(ctx, action)


@cli.command()
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def schema(ctx, output):
    """Print the JSON Schema (draft 2020-12) of spec files: editors complete and check specs with it.

    It is made from the tables `lagcli check` uses; it sees keys and the shapes of values,
    not what expressions mean (docs/spec.md, "Editor support").

    \b
    Examples:
      lagcli schema -o lagcli.schema.json
      # then, as a spec's first line: # yaml-language-server: $schema=lagcli.schema.json
    """
    from lagcli.spec.json_schema import json_schema_text

    def action():
        write_output(output, json_schema_text())
        if output not in (None, "-"):
            note(f"wrote {output}")
    _run(ctx, action)


@cli.group()
def cache():
    """Inspect or empty the cache of compiled drivers and generated modules.

    \b
    Examples:
      lagcli cache info     # where it is, whether it is used, its entries and size
      lagcli cache clear    # remove lagcli's entries (the next runs rebuild them)
    """


@cache.command("info")
@quiet_option
def cache_info():
    """Show the cache directory, whether it is usable, its entries and their size.

    \b
    Example:
      XDG_CACHE_HOME=/tmp/c lagcli cache info
    """
    from lagcli.run import cache_admin

    click.echo(cache_admin.describe(cache_admin.info()), nl=False)


@cache.command("clear")
@quiet_option
def cache_clear():
    """Remove lagcli's cache entries (only those; nothing else in the directory).

    \b
    Example:
      lagcli cache clear
    """
    from lagcli.run import cache_admin

    click.echo(cache_admin.describe_cleared(*cache_admin.clear()), nl=False)


@contextlib.contextmanager
def _progress_bar(t_end: float):
    """A progress bar over [0, t_end] on stderr when it is a terminal; yields update(t) or None."""
    stderr = sys.stderr
    if not stderr.isatty() or t_end <= 0:
        yield None
        return
    with click.progressbar(length=1000, label="simulating", file=stderr) as bar:
        done = 0

        def update(t: float) -> None:
            nonlocal done
            k = min(1000, int(1000 * t / t_end))
            if k > done:
                bar.update(k - done)
                done = k

        yield update


def main() -> NoReturn:
    """The `lagcli` command (the console script, `python -m lagcli`)."""
    collector.for_one_command()
    try:
        cli(prog_name="lagcli")
    except SystemExit as done:
        _end(done.code)
    _end(0)


def _end(code) -> NoReturn:
    """End the process with `code` as Python would (the exit handlers run, the standard
    streams are flushed), without the interpreter's teardown, which frees every object
    one by one: 0.3 s of CPU after `derive` of a double pendulum, 0.7 s after the 40-link
    chain's `derive --json`, 1.8 s after the 100-link one's (bench/README.md). While
    another thread still runs, or a stream cannot be flushed, Python's own exit does it
    all as before (lagcli's commands wait for their threads)."""
    if threading.active_count() > 1:
        sys.exit(code)
    if code is not None and not isinstance(code, int):
        print(code, file=sys.stderr)          # sys.exit("message"): Python prints it, status 1
        code = 1
    atexit._run_exitfuncs()                   # CPython's own exit step (each handler once)
    try:
        for stream in (sys.stdout, sys.stderr):
            stream.flush()
    except (OSError, ValueError):
        sys.exit(code)
    os._exit(code or 0)


# -- analysis commands (lagcli/analysis/, docs/analysis.md) --------------------

def _format(as_json: bool, as_latex: bool = False) -> str:
    if as_json and as_latex:
        raise click.UsageError("choose one output format, not --json and --latex")
    return "json" if as_json else "latex" if as_latex else "text"


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--at", "at", multiple=True, metavar="NAME=VALUE",
              help="Operating value of a coordinate, velocity (q_dot) or parameter (repeatable; "
                   "others 0 / the spec's value). VALUE may use the parameters and the sweep variable.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="A parameter, or an input held at that value (repeatable; as simulate's --set).")
@click.option("--init", "inits", multiple=True, metavar="NAME=VALUE",
              help="A coordinate or <q>_dot of the operating point (repeatable; as simulate's --init).")
@click.option("--independent", multiple=True, metavar="NAME",
              help="An independent coordinate or speed of a constrained system (repeatable; "
                   "default: the best-conditioned choice).")
@click.option("--input", "inputs", multiple=True, metavar="PARAMETER",
              help="Treat this parameter as an input: its column goes into B (repeatable).")
@click.option("--sweep", metavar="NAME=START:STOP:COUNT",
              help="Linearize at COUNT values of NAME (a parameter, or a name the --at values use).")
@click.option("--find-critical", is_flag=True,
              help="With --sweep: find where the number of unstable eigenvalues changes (brentq).")
@click.option("--symbolic", is_flag=True,
              help="A and B as expressions of the parameters (small unconstrained systems).")
@click.option("--closed-loop", "closed", is_flag=True,
              help="Substitute the spec's input laws (simulate: inputs:) first: the closed-loop A.")
@click.option("--json", "as_json", is_flag=True, help="JSON (full precision).")
@click.option("--latex", "as_latex", is_flag=True, help="A LaTeX fragment (amsmath).")
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def linearize(ctx, spec, at, sets, inits, independent, inputs, sweep, find_critical, symbolic, closed, as_json,
              as_latex, output):
    """Linearize SPEC about an operating point: A, B, M, C, K, eigenvalues and a stability verdict.

    \b
    Examples:
      lagcli linearize specs/bead_on_spinning_hoop.yaml --at theta=0
      lagcli linearize specs/cart_pole.yaml --set m=0.2 --set F=1 --init theta=0.1
      lagcli linearize specs/cart_pole.yaml --input F --json
      lagcli linearize specs/cart_pole.yaml --input F --symbolic
      lagcli linearize specs/hybrid/cart_pole_lqr.yaml --closed-loop
      lagcli linearize specs/rolling_disc.yaml --at phi_dot=w --at x_dot=r*w \\
          --sweep w=0:10:101 --find-critical
    """
    fmt = _format(as_json, as_latex)
    _run(ctx, lambda: write_output(output, commands.linearize(spec, at, independent, inputs, sweep,
                                                              find_critical, fmt, symbolic, closed, sets, inits)))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="A parameter, or an input held at that value (repeatable; as simulate's --set).")
@click.option("--init", "inits", multiple=True, metavar="NAME=VALUE",
              help="A coordinate of one more starting point of the numeric search (repeatable; as "
                   "simulate's --init: the --init values together are one point, like a --guess).")
@click.option("--guess", "guesses", multiple=True, metavar="NAME=VALUE[,NAME=VALUE...]",
              help="A starting point of the numeric search (repeatable; default: the spec's "
                   "initial state and the origin).")
@click.option("--json", "as_json", is_flag=True, help="JSON (full precision).")
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def equilibria(ctx, spec, sets, inits, guesses, as_json, output):
    """Equilibria of SPEC (q' = 0: stationary points of V - T0) and their stability.

    \b
    Examples:
      lagcli equilibria specs/bead_on_spinning_hoop.yaml
      lagcli equilibria specs/bead_on_spinning_hoop.yaml --set Omega=3
      lagcli equilibria specs/cartesian_pendulum.yaml --guess x=0.1,y=-1
    """
    _run(ctx, lambda: write_output(output, commands.equilibria(spec, sets, guesses, _format(as_json), inits)))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--momentum", "momenta", multiple=True, metavar="p_NAME=VALUE",
              help="Value of a cyclic coordinate's momentum (repeatable): then the steady motions.")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE", help="Override a parameter (repeatable).")
@click.option("--guess", "guesses", multiple=True, metavar="NAME=VALUE[,NAME=VALUE...]",
              help="A starting point for the steady-motion search (repeatable).")
@click.option("--json", "as_json", is_flag=True, help="JSON.")
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def routh(ctx, spec, momenta, sets, guesses, as_json, output):
    """Routh reduction of SPEC over its cyclic coordinates: Routhian, effective potential,
    reduced equations and, at given momenta, the steady motions and their small oscillations.

    \b
    Examples:
      lagcli routh specs/spherical_pendulum.yaml
      lagcli routh specs/spherical_pendulum.yaml --momentum p_phi=0.5 --guess theta=1
    """
    _run(ctx, lambda: write_output(output, commands.routh(spec, momenta, sets, guesses, _format(as_json))))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--json", "as_json", is_flag=True, help="JSON.")
@click.option("--latex", "as_latex", is_flag=True, help="A LaTeX fragment (amsmath).")
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@quiet_option
@click.pass_context
def hamiltonian(ctx, spec, as_json, as_latex, output):
    """Hamilton's form of SPEC: momenta p = M q' + a, H(q, p, t) and Hamilton's equations.

    \b
    Examples:
      lagcli hamiltonian specs/spherical_pendulum.yaml
      lagcli hamiltonian specs/bead_on_spinning_hoop.yaml --latex
    """
    fmt = _format(as_json, as_latex)
    _run(ctx, lambda: write_output(output, commands.hamiltonian(spec, fmt)))
