"""Output languages of `lagcli generate`: a Derivation in, {file name: text} out.

    python   lagcli/emit/python.py   templates/python/module.py.jinja      one module
    c        lagcli/emit/c.py        templates/c/model.{h,c}.jinja, main.c  three files
    latex    lagcli/emit/latex.py    templates/latex/document.tex.jinja     one document

How to add an output language (say Julia):

1. Printer: in `lagcli/emit/julia.py`, subclass `codegen.SlotPrinter` and sympy's
   printer for the language (`class JuliaPrinter(codegen.SlotPrinter, JuliaCodePrinter)`),
   setting only what differs: `power_format`, `sqrt_function`, literals. Symbols are
   printed as slots (t, y[i], p[j]; mind 1-based arrays: override `codegen.slots`'s
   strings) and the printer refuses any symbol without one.
2. Context: `codegen.collect(d)` -> `codegen.eliminate(...)` (the one CSE) ->
   `codegen.print_block(...)` for each function body; pass these pre-printed strings and
   `codegen.interface(d, outputs)` (names, defaults, version, spec file) to the templates.
3. Templates: `templates/julia/<file>.jl.jinja`, rendered with `templates.render`; they
   document the interface at the top and hold no dates or host names.
4. Register: add a `Language` to `LANGUAGES` below (module path, function name, whether the
   output is a directory) and the name to the `--lang` choice follows automatically.
5. Tests: run the generated code at seeded random states against the Derivation
   (see tests/test_codegen_python.py), plus a golden file (tests/test_golden_codegen.py).
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass

from lagcli.errors import EmitError


@dataclass(frozen=True)
class Language:
    name: str
    module: str           # imported on use: generating C must not import the LaTeX printer
    function: str         # module.function(derivation) -> {file name: text}
    directory: bool       # the output is a directory of several files (-o DIR required)


def _python_files(d) -> dict[str, str]:
    from lagcli.emit.python import python_module

    return {f"{d.model.name}.py": python_module(d)}


def _latex_files(d) -> dict[str, str]:
    from lagcli.emit.latex import latex_document

    return {f"{d.model.name}.tex": latex_document(d)}


LANGUAGES = {
    "python": Language("python", __name__, "_python_files", directory=False),
    "c": Language("c", "lagcli.emit.c", "c_files", directory=True),
    "latex": Language("latex", __name__, "_latex_files", directory=False),
}


def generate(derivation, lang: str) -> dict[str, str]:
    """{file name: text} of `derivation` in the output language `lang`."""
    try:
        language = LANGUAGES[lang]
    except KeyError:
        raise EmitError(f"unknown output language {lang!r}; known: {', '.join(LANGUAGES)}") from None
    return getattr(importlib.import_module(language.module), language.function)(derivation)
