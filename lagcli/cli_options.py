"""Options every `lagcli` command shares, and the conventions of command-line tools they keep.

- `-q/--quiet` on every command: notes and warnings on stderr are not shown (errors are);
  commands print their notes through `note`, which honours it.
- `--lang` values are case-insensitive, and `matlab` names the Octave target (`LanguageChoice`).
- SPEC `-` is standard input (lagcli/spec/files.py reads it; `SPEC_HELP` says so in --help).
- The run settings of `simulate` and `sweep` (`settings_options`): their --help quotes the
  defaults of the run interface (`lagcli.interface.Settings`, `RunSettings`), never a
  number of its own.
"""
from __future__ import annotations

import re

import click

from lagcli.interface import DEFAULT_BAUMGARTE, STEP_BUDGET_BASE, STEP_BUDGET_PER_OUTPUT, RunSettings

LANGUAGE_ALIASES = {"matlab": "octave"}     # another name users look for -> the target's name


def _set_quiet(ctx: click.Context, _param, value: bool) -> None:
    if value:
        root = ctx.find_root()
        root.obj = {**(root.obj or {}), "quiet": True}


def quiet_option(command):
    """`-q/--quiet`: no notes or warnings on stderr, only errors."""
    return click.option("-q", "--quiet", is_flag=True, expose_value=False, callback=_set_quiet,
                        is_eager=True, help="No notes or warnings on stderr (errors still print).")(command)


def quiet() -> bool:
    """Whether the running command was given `--quiet`."""
    ctx = click.get_current_context(silent=True)
    obj = ctx.find_root().obj if ctx is not None else None
    return bool(obj and obj.get("quiet"))


def note(text: str) -> None:
    """A remark for the user on stderr (what was written, what was repaired), unless --quiet."""
    if not quiet():
        click.echo(text, err=True)


class LanguageChoice(click.Choice):
    """The targets of `generate --lang`, in any letter case, and their aliases (`matlab`)."""

    def __init__(self, languages):
        super().__init__([*languages, *LANGUAGE_ALIASES], case_sensitive=False)

    def convert(self, value, param, ctx):
        chosen = super().convert(value, param, ctx)
        return LANGUAGE_ALIASES.get(chosen, chosen)


def number_text(value: float) -> str:
    """A default as --help shows it: 10, 0.01, 1e-9 (the shortest `g` form, exponent unpadded)."""
    return re.sub(r"e([+-])0*(\d)", lambda m: "e" + m.group(1).replace("+", "") + m.group(2), format(value, "g"))


def settings_options(methods, method_help: str):
    """--t-end, --dt, --method (one of `methods`), --rtol, --atol and --baumgarte, each
    saying its default: the spec's `simulate:` value, else the run interface's."""
    s = RunSettings()
    alpha, beta = DEFAULT_BAUMGARTE
    options = [
        click.option("--t-end", type=float, help=f"End time (default: the spec's simulate.t_end, "
                                                 f"else {number_text(s.t_end)})."),
        click.option("--dt", type=float, help=f"Output interval (default: simulate.dt, else {number_text(s.dt)})."),
        click.option("--method", type=click.Choice(list(methods)),
                     help=f"{method_help} (default: simulate.method, else {s.method})."),
        click.option("--rtol", type=float, help=f"Relative tolerance (default: simulate.rtol, "
                                                f"else {number_text(s.rtol)})."),
        click.option("--atol", type=float, help=f"Absolute tolerance (default: simulate.atol, "
                                                f"else {number_text(s.atol)})."),
        click.option("--baumgarte", nargs=2, type=float, metavar="ALPHA BETA",
                     help=f"Constraint stabilisation gains (default {number_text(alpha)} {number_text(beta)})."),
    ]

    def decorate(command):
        for option in reversed(options):
            command = option(command)
        return command
    return decorate


def step_options(command):
    """--max-steps and --steps-per-row of `simulate`, with the run interface's defaults."""
    budget = f"{STEP_BUDGET_BASE} + {STEP_BUDGET_PER_OUTPUT} per output interval"
    command = click.option("--steps-per-row", type=int, metavar="K",
                           help=f"--method variational: K fixed steps of DT/K between rows "
                                f"(default {RunSettings().steps_per_row}).")(command)
    return click.option("--max-steps", type=int, metavar="N",
                        help=f"Stop with an error after N integrator steps (default {budget}).")(command)
