"""The `lagcli` command line: options in, library call, output out, errors to exit codes."""
from __future__ import annotations

import sys
import traceback

import click

from lagcli import __version__, commands
from lagcli.errors import LagcliError
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
        click.echo(f"error: {exc}" if exc.exit_code != 2 or "\n" not in str(exc) else str(exc), err=True)
        sys.exit(exc.exit_code)


@cli.command()
@click.argument("spec", type=SPEC)
@click.option("--text", "fmt", flag_value="text", default=True, help="Readable sectioned report (default).")
@click.option("--latex", "fmt", flag_value="latex", help="LaTeX (a fragment; see --standalone).")
@click.option("--json", "fmt", flag_value="json", help="JSON with the contract's keys.")
@click.option("--standalone", is_flag=True, help="With --latex: a complete document for pdflatex.")
@click.option("--simplify/--no-simplify", default=True, show_default=True,
              help="Tidy small expressions (trigsimp) for display.")
@click.option("-o", "--output", default=None, help="Output file ('-' or none: stdout).")
@click.pass_context
def derive(ctx, spec, fmt, standalone, simplify, output):
    """Derive the equations of motion of SPEC and report them."""
    def action():
        if fmt == "json":
            text = commands.derive_json(spec, simplify)
        elif fmt == "latex":
            text = commands.derive_latex(spec, simplify, standalone)
        else:
            text = commands.derive_text(spec, simplify)
        write_output(output, text)
    _run(ctx, action)


@cli.command()
@click.argument("spec", type=SPEC)
@click.pass_context
def check(ctx, spec):
    """Validate SPEC and summarise it: coordinates, constraints, DOF."""
    _run(ctx, lambda: click.echo(commands.check_summary(spec), nl=False))


def main() -> None:
    cli(prog_name="lagcli")
