"""Options every `lagcli` command shares, and the conventions of command-line tools they keep.

- `-q/--quiet` on every command: notes and warnings on stderr are not shown (errors are);
  commands print their notes through `note`, which honours it.
- `--lang` values are case-insensitive, and `matlab` names the Octave target (`LanguageChoice`).
- SPEC `-` is standard input (lagcli/spec/files.py reads it; `SPEC_HELP` says so in --help).
"""
from __future__ import annotations

import click

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
