"""Python's cycle collector paused while sympy builds big expressions."""
from __future__ import annotations

import contextlib
import gc


@contextlib.contextmanager
def collector_paused():
    """Python's cycle collector off for the duration (and on again after, if it was):
    sympy builds and drops millions of expressions, freed by reference counting, and each
    full collection walks every live one (a quarter of the CPU of the 100-link chain's
    derivation, a fifth of `generate --lang c` at 40 links; the same peak memory without
    it: bench/README.md). No sympy here: `commands` imports it at start-up (lagcli.model
    imports nothing)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()
