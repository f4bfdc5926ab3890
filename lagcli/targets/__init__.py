"""Output languages of `lagcli generate`: a Derivation in, {file name: text} out.

    python   lagcli/targets/python.py   templates/python/module.py.jinja      one module, carrying
                                     lagcli/runtime/run_rules.py verbatim (and, with events,
                                     python_events.py: lagcli's event loop, verbatim)
    c        lagcli/targets/c.py        templates/c/model.{h,c}.jinja, main.c  the model and its driver,
                                     plus lagcli/runtime/c/ copied as it is
    latex    lagcli/report/latex.py    templates/latex/document.tex.jinja     one document
    fmu      lagcli/targets/fmu.py      templates/fmu/*.jinja                  one FMI 2.0 zip (bytes):
                                     the C model compiled, lagcli/runtime/fmi2/ beside it
    octave   lagcli/targets/octave.py   templates/octave/*.m.jinja             MATLAB/Octave functions + a script
    rust     lagcli/targets/rust.py     templates/rust/*.jinja                 a crate, plus
                                     lagcli/runtime/rust/ode.rs copied as it is
    casadi   lagcli/targets/casadi.py   templates/casadi/module.py.jinja    one module of CasADi
                                     Functions (SX), casadi imported by it only
    jax      lagcli/targets/jax.py      templates/jax/module.py.jinja       one module of pure
                                     jax.numpy functions, jax imported by it only

How to add a code target (say Julia) — a printer configuration and templates
(lagcli/targets/octave.py and rust.py were made this way, 120-150 lines each; casadi.py
and jax.py, 60-80 lines, reuse the Python literals and escapes):

1. Printer: in `lagcli/targets/julia.py`, subclass `slots.SlotPrinter` and sympy's
   printer for the language (`class JuliaPrinter(SlotPrinter, JuliaCodePrinter)`),
   setting only what differs as class attributes: `index_base = 1` and `subscript`
   (how `y[i]`, `p[j]` are written: Octave's `y(1)`), `power_format`, `sqrt_function`,
   `literal`, `imports`. A language that calls functions as methods overrides
   `_print_sqrt` and the receiver rule (Rust: `x.sqrt()`, `(2.0_f64).sin()`). Symbols
   print as those slots and the printer refuses any symbol without one. Try it on
   sign, Abs, Min, Max, atan2, rationals and powers: sympy's printers differ there
   (Rust's prints `min(a, b, c)` and integers as integers; rust.py overrides them).
2. Context: `codegen.generated_context(d, JuliaPrinter, layout, initial, initial_notes)`
   runs the shared pipeline (collect -> tidy -> one CSE -> print every function body) and
   returns strings only: the bodies, matrix rows, stabilisation and residual terms,
   the `Interface` (`about.py`: names, defaults, the CSV `header`, the `fields`, units
   through `i.layout`, version, spec file; all read from `layout`, the system's
   `lagcli.interface.Layout`, which the target function receives) and the shared
   numerics. A target never computes a layout or a column order of its own. Where spec names become
   identifiers of the target (struct fields, constants), map them with
   `identifiers.identifiers(names, KEYWORDS, "Julia")` (keywords get a `_`).
3. Templates: `templates/julia/<file>.jl.jinja`, rendered with `templates.render`; they
   lay out the pre-printed strings (macros for repeated statements; indices of their
   own arrays in the language's base), document the interface at the top and hold no
   dates or host names. Spec text goes through the target's escapes, added to
   `lagcli/render/escape.py` (and its FILTERS) with a property test against the grammar.
   Code that is the same for every model (an integrator, a driver) is not a template:
   put it under `lagcli/runtime/julia/`, list it in `lagcli/runtime/__init__.py` (as
   `rust_runtime_files`) and add its files to the output, as `c.c_files` does with
   `c_runtime_files()` (and to `[tool.setuptools.package-data]`). File names may hold a
   folder (`src/lib.rs`): `System.generate` creates it. A target whose output must stay
   one file pastes its runtime code in verbatim instead, as the Python module does with
   `lagcli/runtime/run_rules.py` (`python_run_rules()`, passed to its template as
   `run_rules`): still one copy of the rules per language.
4. Register: add a `Language` to `LANGUAGES` below (module path, function name, whether the
   output is a directory) and the name to the `--lang` choice follows automatically.
5. Tests: run the generated code at seeded random states against the Derivation
   (see tests/test_codegen_python.py, test_codegen_octave.py, test_codegen_rust.py),
   plus golden files (tests/test_golden_codegen.py: add the language to LANGS).
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass

from lagcli.errors import EmitError


@dataclass(frozen=True)
class Language:
    """An output language of `generate`: where its code is and what its output is."""

    name: str
    module: str           # imported on use, by name: generating C must not import the LaTeX
                          # printer, and the registry imports no report (latex is one of them)
    function: str         # module.function(derivation, layout, initial, initial_notes) -> {file name: text}
    directory: bool       # the output is a directory of several files (-o DIR required)
    embeds_initial: bool = True   # the output holds a default initial state (`initial=`)
    binary: bool = False          # the one output file is bytes, not text (the FMU's zip)
    variational: bool = False     # carries the variational integrator (`variational=` option)


def _python_files(d, layout, initial=None, initial_notes=(), variational=None) -> dict[str, str]:
    from lagcli.targets.python import python_module

    return {f"{layout.name}.py": python_module(d, layout, initial, initial_notes, variational)}


LANGUAGES = {
    "python": Language("python", __name__, "_python_files", directory=False, variational=True),
    "c": Language("c", "lagcli.targets.c", "c_files", directory=True, variational=True),
    "octave": Language("octave", "lagcli.targets.octave", "octave_files", directory=True),
    "rust": Language("rust", "lagcli.targets.rust", "rust_files", directory=True),
    "latex": Language("latex", "lagcli.report.latex", "latex_files", directory=False, embeds_initial=False),
    "fmu": Language("fmu", "lagcli.targets.fmu", "fmu_files", directory=False, binary=True),
    "casadi": Language("casadi", "lagcli.targets.casadi", "casadi_files", directory=False),
    "jax": Language("jax", "lagcli.targets.jax", "jax_files", directory=False),
}


def generate(derivation, lang: str, initial=None, initial_notes=(), layout=None,
             variational: bool | None = None) -> dict[str, str]:
    """{file name: text} of `derivation` in the output language `lang`. `initial`: the
    default state [q..., q'...] generated code embeds, made consistent by the caller
    (None: the spec's `initial:` as given), `initial_notes` what was solved for; `layout`:
    the system's run interface (`lagcli.interface.Layout`; None: `layout_of(derivation)`).
    `variational` (python, c): the variational integrator's functions, True always,
    None for a small system only (lagcli/targets/discrete_code.py, `included`)."""
    try:
        language = LANGUAGES[lang]
    except KeyError:
        raise EmitError(f"unknown output language {lang!r}; known: {', '.join(LANGUAGES)}") from None
    if variational and not language.variational:
        from lagcli.errors import UsageError

        raise UsageError(f"--variational: the variational integrator is generated for --lang "
                         f"{' and '.join(n for n, k in LANGUAGES.items() if k.variational)} only (not {lang})")
    if lang != "latex":
        _refuse_hybrid(derivation, lang)
    return program_sources(derivation, lang, initial, initial_notes, layout, variational, spec_laws=True)


SPEC_LAWS_IN_TABLE = ("c",)     # targets whose run table runs the spec's laws (generate only)


def program_sources(derivation, lang: str, initial=None, initial_notes=(), layout=None,
                    variational: bool | None = True, spec_laws: bool = False) -> dict[str, str]:
    """`generate` for the programs of a run (the System's: the Python module, the C driver):
    the smooth equations, whatever events or laws the run layer adds around them, with the
    variational integrator's functions whatever the system's size (a run may ask for them).
    Every target reads what it says of the system from `layout` (the System's, built once;
    made here when the caller has none). `spec_laws` (`generate`): the C driver's table runs
    the spec's input laws (a run's driver gets the run's laws substituted instead)."""
    from lagcli.interface import layout_of

    language = LANGUAGES[lang]
    options = {"variational": variational} if language.variational else {}
    if spec_laws and lang in SPEC_LAWS_IN_TABLE:
        options["spec_laws"] = True
    return getattr(importlib.import_module(language.module), language.function)(
        derivation, layout if layout is not None else layout_of(derivation), initial, initial_notes, **options)


def _refuse_hybrid(derivation, lang: str) -> None:
    """Generated code does not carry events or the spec's input laws yet: refuse rather than
    drop them (lagcli simulate runs them: events and expression laws on both backends, a
    held contact on the Python backend)."""
    model = derivation.model
    # c, fmu, octave and python carry events (event_code.py, octave_hybrid.py, python_events.py)
    events = model.events if lang not in ("c", "fmu", "octave", "python") else ()
    laws = model.laws if lang not in ("python", "octave", "fmu", "casadi", "jax", "c") else ()
    rest = any(e.rest for e in model.events)      # held contacts: lagcli simulate (Python backend) only
    keys = [key for key, used in (("events:", events), ("an event's rest: true", rest),
                                  ("simulate: inputs:", laws)) if used]
    if keys:
        from lagcli.errors import UsageError

        backends = "--backend python only" if rest else "--backend python or c"
        raise UsageError(f"{model.source}: --lang {lang} does not implement {' and '.join(keys)} yet; "
                        "the generated code would silently ignore them\n"
                        f"  hint: `lagcli simulate` runs them ({backends}); remove them from a copy "
                        "of the spec to generate the smooth equations")
