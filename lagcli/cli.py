"""The `lagcli` command line: options in, library call, output out, errors to exit codes."""
from __future__ import annotations

import contextlib
import sys
import traceback

import click

from lagcli import __version__, commands
from lagcli.emit import LANGUAGES
from lagcli.errors import LagcliError
from lagcli.numerics import METHODS
from lagcli.output import write_output

SPEC = click.Path(dir_okay=False, path_type=str)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="lagcli")
@click.option("--traceback", "show_traceback", is_flag=True, help="Show the Python traceback of errors.")
@click.pass_context
def cli(ctx: click.Context, show_traceback: bool) -> None:
    """Equations of motion from a spec file, by Lagrange's method."""
    ctx.obj = {"traceback": show_traceback}


def _run(ctx: click.Context, action) -> None:
    """Run `action`, mapping lagcli errors to a message on stderr and the exit status."""
    try:
        action()
    except LagcliError as exc:
        if ctx.obj and ctx.obj.get("traceback"):
            traceback.print_exc()
        click.echo(exc.render(), err=True)
        sys.exit(exc.exit_code)


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
        if fmt == "json":
            text = commands.derive_json(spec, simplify)
        elif fmt == "latex":
            text = commands.derive_latex(spec, simplify, standalone, parts)
        else:
            text = commands.derive_text(spec, simplify, parts)
        write_output(output, text)
    _run(ctx, action)


@cli.command()
@click.argument("spec", type=SPEC)
@click.pass_context
def check(ctx, spec):
    """Validate SPEC and summarise it: coordinates, constraints, DOF."""
    _run(ctx, lambda: click.echo(commands.check_summary(spec), nl=False))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--lang", required=True, type=click.Choice(list(LANGUAGES)),
              help="python: one module (numpy); c: <name>.h, <name>.c, <name>_main.c; "
                   "latex: a standalone document.")
@click.option("-o", "--output", default=None,
              help="Output file ('-' or none: stdout); for --lang c the directory (required).")
@click.pass_context
def generate(ctx, spec, lang, output):
    """Generate code (Python, C) or a LaTeX document from SPEC's equations of motion."""
    _run(ctx, lambda: commands.generate(spec, lang, output))


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--t-end", type=float, help="End time (default: the spec's simulate.t_end, else 10).")
@click.option("--dt", type=float, help="Output interval (default: simulate.dt, else 0.01).")
@click.option("--method", type=click.Choice(list(METHODS)),
              help="scipy's integrator name (default: simulate.method, else DOP853).")
@click.option("--rtol", type=float, help="Relative tolerance (default: simulate.rtol, else 1e-9).")
@click.option("--atol", type=float, help="Absolute tolerance (default: simulate.atol, else 1e-12).")
@click.option("--set", "sets", multiple=True, metavar="NAME=VALUE",
              help="Override a parameter (repeatable); VALUE may be a constant expression.")
@click.option("--init", "inits", multiple=True, metavar="NAME=VALUE",
              help="Initial value of a coordinate or <q>_dot (repeatable); overrides `initial:`.")
@click.option("--backend", type=click.Choice(["python", "c"]),
              help="c (compiled driver, cached) is the default when `cc` exists; else python.")
@click.option("--baumgarte", nargs=2, type=float, metavar="ALPHA BETA",
              help="Constraint stabilisation gains (default 10 10).")
@click.option("-o", "--output", default=None, help="CSV file ('-' or none: stdout).")
@click.option("--plot", default=None, metavar="FILE.png",
              help="Also plot coordinates and drift (needs matplotlib).")
@click.pass_context
def simulate(ctx, spec, t_end, dt, method, rtol, atol, sets, inits, backend, baumgarte, output, plot):
    """Integrate the equations of motion of SPEC and write the trajectory as CSV."""
    from lagcli.simulate.options import Request

    request = Request(spec, t_end, dt, method, rtol, atol, tuple(sets), tuple(inits), backend,
                      tuple(baumgarte) if baumgarte else None)
    _run(ctx, lambda: commands.simulate(request, output, plot, note=lambda text: click.echo(text, err=True),
                                        progress=_progress_bar))


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


def main() -> None:
    cli(prog_name="lagcli")
