"""Spec text made safe for each output (stand-in: the "escape" work replaces this module).

    latex_text(text) -> str   text mode of LaTeX: specials escaped, one line, compiles
"""
from __future__ import annotations


def latex_text(text: str) -> str:
    """`text` for LaTeX text mode (the printer's escaping: specials, non-ASCII)."""
    from lagcli.emit.latex_printer import escape_text

    return escape_text(" ".join(str(text).split()))
