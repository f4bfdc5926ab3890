"""Python's cycle collector paused while sympy builds big expressions."""
from __future__ import annotations

import contextlib
import gc

_paused_sections = 0        # sections open now (they nest: a report inside a command)
_freeze_on_resume = False   # the `lagcli` process (`for_one_command`)


@contextlib.contextmanager
def collector_paused():
    """Python's cycle collector off for the duration (and on again after, if it was):
    sympy builds and drops millions of expressions, freed by reference counting, and each
    full collection walks every live one (a quarter of the CPU of the 100-link chain's
    derivation, a fifth of `generate --lang c` at 40 links; the same peak memory without
    it: bench/README.md). No sympy here: `commands` imports it at start-up (lagcli.model
    imports nothing)."""
    global _paused_sections
    enabled = gc.isenabled()
    gc.disable()
    _paused_sections += 1
    try:
        yield
    finally:
        _paused_sections -= 1
        if _freeze_on_resume and _paused_sections == 0:
            gc.freeze()
            gc.enable()
        elif enabled:
            gc.enable()


def for_one_command() -> None:
    """The `lagcli` process runs one command and ends (`lagcli.cli.main`): the collector is
    off from its start, and comes on when a paused section ends, with every object alive
    then frozen (`gc.freeze`: never walked again, never freed: the process ends first).

    Why: what a command builds before and inside those sections (sympy's modules, the
    spec, the derivation, the report) lives until it ends or is freed by reference
    counting, yet the first collection after each section walked all of it: 0.3 s of
    CPU of the 40-link chain's `derive --json`, 0.5 s of `check` of 1 000 coordinates
    (bench/README.md). What runs after a section, such as a simulation's steps (scipy
    leaves a cycle per solver, one per event), is collected as usual.
    tests/test_process_exit.py checks that a longer run freezes no more objects."""
    global _freeze_on_resume
    _freeze_on_resume = True
    gc.disable()
