"""The reports' own symbols, and how they yield to the user's names.

A report names its own quantities with the textbook letters: T (T2, T1, T0), V, L, M,
Q, F, G, c, the constraints' A, a, d, C, R, the momenta p, h and E... A spec may use the
same letters for its own quantities (a cart mass M, a damping c, a force F, a length L,
a height h): the user's names win. Every surface (the text and LaTeX reports, the
notebook's parts, the page, the analyses' displays) prints the user's symbols as the
user named them, and each of the report's quantities whose letter a spec name (or its
`latex:`) takes is shown in a distinct form instead:

    quantity         letter   text     LaTeX            page (MathML)
    energies         T V L E  Tkin...  \\mathcal{T}...   script 𝒯 𝒱 ℒ ℰ
    matrices,        M F ...  Mmat...  \\mathbf{M}...     bold 𝐌 𝐅 ...
    vectors, others

The report's legend says what each shown form is. A report whose letters no spec name
takes keeps the letters, byte for byte. The analyses follow the same rule: `hamiltonian`'s
H and `routh`'s R (`analysis_letters`), and the linear model's x, u, v, q, A, B, M, C,
K, F, G (`linear_letters`: one letter, one thing in one output). Code targets are not
reports: their identifiers follow their own rules (lagcli/targets/identifiers.py).
"""
from __future__ import annotations

import unicodedata
from dataclasses import dataclass


@dataclass(frozen=True)
class Quantity:
    """One of the reports' own quantities: its letter, what it is, and its yielded forms."""

    letter: str            # the report's letter (text and LaTeX)
    text: str              # the text report's name for it when the letter is the user's
    style: str             # "script" (energies) or "bold" (LaTeX \mathcal / \mathbf, MathML)
    meaning: str           # the legend's words
    family: tuple[str, ...] = ()    # the report's other names built on the letter (T2, T1, T0)

    @property
    def latex(self) -> str:
        command = r"\mathcal" if self.style == "script" else r"\mathbf"
        return f"{command}{{{self.letter}}}"

    @property
    def unicode(self) -> str:
        return styled_letter(self.letter, self.style)


QUANTITIES = {q.letter: q for q in (
    Quantity("T", "Tkin", "script", "the kinetic energy", ("T0", "T1", "T2")),
    Quantity("V", "Vpot", "script", "the potential energy"),
    Quantity("L", "Lag", "script", "the Lagrangian"),
    Quantity("E", "Etot", "script", "the total energy"),
    Quantity("M", "Mmat", "bold", "the mass matrix"),
    Quantity("Q", "Qgen", "bold", "the generalized forces"),
    Quantity("F", "Fvec", "bold", "the forcing of the explicit form"),
    Quantity("G", "Gmat", "bold", "the gyroscopic matrix"),
    Quantity("c", "cvel", "bold", "the velocity terms of the explicit form"),
    Quantity("A", "Amat", "bold", "the constraint matrix"),
    Quantity("a", "avec", "bold", "the velocity coefficients of a constraint row "
                                  "or of the kinetic energy's linear part"),
    Quantity("d", "dterm", "bold", "a constraint's term free of velocities"),
    Quantity("b", "bias", "bold", "the constraint bias"),
    Quantity("C", "Ccon", "bold", "the generalized constraint forces"),
    Quantity("R", "Rcon", "bold", "the constraint force on a particle"),
    Quantity("p", "pmom", "bold", "a conserved momentum"),
    Quantity("h", "hJac", "bold", "the Jacobi integral"),
    Quantity("g", "gap", "bold", "an event's gap function"),
    Quantity("e", "rest", "bold", "an impact's restitution"),
)}
# The letters every report uses; the others only where the report has that section.
ALWAYS = ("T", "V", "L", "M", "Q", "F", "G", "c", "a")


def styled_letter(letter: str, style: str) -> str:
    """The Unicode mathematical letter (𝐌, 𝒯; ℒ and friends from the letterlike block)."""
    case = "CAPITAL" if letter.isupper() else "SMALL"
    kind = "SCRIPT" if style == "script" else "BOLD"
    try:
        return unicodedata.lookup(f"MATHEMATICAL {kind} {case} {letter.upper()}")
    except KeyError:
        return unicodedata.lookup(f"{kind} {case} {letter.upper()}")


def user_names(model) -> frozenset:
    """Every name the spec gives (coordinates, parameters, inputs, known functions,
    definitions), and the `latex:` the user gave each."""
    names = {s.name for s in (*model.q, *model.parameter_symbols, *model.input_symbols)}
    names |= {name for name, _ in (*model.known, *model.definitions)}
    names |= {latex.strip() for latex in model.coordinate_latex.values() if latex}
    names |= {info.latex.strip() for info in (*model.parameters, *model.inputs) if info.latex}
    return frozenset(names)


def letters_used(d) -> tuple[str, ...]:
    """The report's letters for derivation `d`: those of every report (a: of T1 = a q'
    and of the constraint rows), the constraint rows' A, d and forces C and R, the
    momenta p, h and E, the events' g and e."""
    m = d.model
    used = list(ALWAYS)
    if d.constraints:
        used += ["A", "d", "C"]
    if d.particle_constraint_forces:
        used.append("R")
    if d.ignorable:
        used.append("p")
    if d.jacobi_integral is not None:
        used += ["h", "E"]
    if m.events:
        used += ["g", "e"]
    return tuple(used)


@dataclass(frozen=True)
class Notation:
    """How one derivation's reports show their own quantities: `yielded` are the
    letters a spec name takes (shown in their distinct form), in QUANTITIES order;
    `text_names` their text names (`Quantity.text`, with "_" appended while the spec
    takes that name too)."""

    yielded: tuple[str, ...] = ()
    text_names: tuple[tuple[str, str], ...] = ()

    def text(self, letter: str) -> str:
        return dict(self.text_names).get(letter, letter)

    def latex(self, letter: str) -> str:
        return QUANTITIES[letter].latex if letter in self.yielded else letter

    def unicode(self, letter: str) -> str:
        return QUANTITIES[letter].unicode if letter in self.yielded else letter

    def mathml(self, letter: str) -> str:
        import html     # imported on use: only the page prints MathML (html.entities: ~3 ms)

        return f"<mi>{html.escape(self.unicode(letter))}</mi>"

    @property
    def texts(self) -> dict:
        """{letter: text name} of every quantity (the text template's `n.M`)."""
        return {letter: self.text(letter) for letter in QUANTITIES}

    @property
    def latexes(self) -> dict:
        """{letter: LaTeX} of every quantity (the LaTeX template's `n.M`)."""
        return {letter: self.latex(letter) for letter in QUANTITIES}

    def legend(self, shown) -> list[tuple[str, str, str]]:
        """(letter, shown form, meaning) of each yielded quantity; `shown` is one of
        `text`, `latex`, `unicode`."""
        return [(letter, shown(letter), QUANTITIES[letter].meaning) for letter in self.yielded]

    def sentence(self, text: str) -> str:
        """One of lagcli's sentences (`no_jacobi_reason`) with the report's letters in
        it as the text report shows them."""
        for phrase, letter in SENTENCE_LETTERS.items():
            text = text.replace(phrase, phrase.replace(letter, self.text(letter), 1))
        return text


# The report's letters inside lagcli's own sentences (lagcli.derive.invariants.jacobi_obstacle).
SENTENCE_LETTERS = {"Q'": "Q", "row a": "a", "term d": "d", "L depends": "L"}


def spoken_list(items: list[str]) -> str:
    """["M"] -> "M is", ["M", "L", "c"] -> "M, L and c are"."""
    if len(items) == 1:
        return f"{items[0]} is"
    return f"{', '.join(items[:-1])} and {items[-1]} are"


def notation_of(d, also: tuple[str, ...] = ()) -> Notation:
    """The notation of the reports of derivation `d`: a letter of the report yields when
    the spec names something with it (or with a name of its family: T2 for T). `also`:
    letters a surface uses beyond the report's (the notebook's E and b)."""
    taken = user_names(d.model)
    used = (*letters_used(d), *also)
    yielded = tuple(letter for letter in QUANTITIES
                    if letter in used and taken & {letter, *QUANTITIES[letter].family})
    texts = []
    for letter in yielded:
        name = QUANTITIES[letter].text
        while name in taken:
            name += "_"
        texts.append((letter, name))
    return Notation(yielded, tuple(texts))


# -- the letters of a linear model (`lagcli linearize`, `Linearization`) ---------------
#
#     x' = A x + B u                 x: state, u: inputs
#     M v' + C v + K q = F u         v: independent speeds, q: independent coordinates,
#                                    F: the second-order form's input matrix
#
# One letter, one thing in one output: a letter the spec uses for a name of its own
# (a coordinate x, an input F, a parameter K) yields to the next candidate; a matrix
# with no candidate left is written `A_lin` (LaTeX: bold A).
LINEAR_CANDIDATES = {
    "x": ("x", "z", "s", "w"),
    "u": ("u", "w", "e", "r"),
    "v": ("v", "w", "s", "r"),
    "q": ("q", "r", "p"),
    "A": ("A",), "B": ("B",), "M": ("M",), "C": ("C",), "K": ("K",), "G": ("G",),
    "F": ("F", "H", "E"),
}


def linear_letters(names) -> dict[str, str]:
    """{role: shown letter} of a linear model's own letters (LINEAR_CANDIDATES), none of
    them one of `names` (the spec's names in that output) nor another role's letter."""
    taken = set(names)
    letters = {}
    for role, candidates in LINEAR_CANDIDATES.items():
        letter = next((c for c in candidates if c not in taken), None)
        if letter is None:
            letter = role + "_lin"
            while letter in taken:
                letter += "_"
        taken.add(letter)
        letters[role] = letter
    return letters


def linear_latex_letters(letters: dict[str, str]) -> dict[str, str]:
    """The same letters in LaTeX (a yielded matrix bold)."""
    return {role: rf"\mathbf{{{role}}}" if "_lin" in letter else letter for role, letter in letters.items()}


# The analyses' own scalars: the Hamiltonian H (`lagcli hamiltonian`) and the Routhian R
# (`lagcli routh`), which yield like the report's letters.
ANALYSIS_QUANTITIES = {q.letter: q for q in (
    Quantity("H", "Ham", "script", "the Hamiltonian"),
    Quantity("R", "Routh", "script", "the Routhian"),
)}


def analysis_letters(d) -> dict[str, dict[str, str]]:
    """{"text": {letter: name}, "latex": {letter: LaTeX}} of the analyses' H and R and of
    the report's letters their displays use (M, a, T, V): each one the letter itself
    unless the spec names something with it."""
    taken = user_names(d.model)
    report = notation_of(d)
    text = {letter: report.text(letter) for letter in "MaTV"}
    latex = {letter: report.latex(letter) for letter in "MaTV"}
    for letter, quantity in ANALYSIS_QUANTITIES.items():
        text[letter] = quantity.text if letter in taken else letter
        latex[letter] = quantity.latex if letter in taken else letter
    return {"text": text, "latex": latex}


def linear_equations(n: dict[str, str], inputs: bool, times: str = " ") -> tuple[str, str]:
    """The two equations of a linear model in the letters `n` ("x' = A x + B u",
    "M v' + C v + K q = F u"), `times` between factors (LaTeX: a thin space)."""
    def product(matrix: str, vector: str) -> str:
        return f"{n[matrix]}{times}{n[vector]}"

    first = f"{n['x']}' = {product('A', 'x')}" + (f" + {product('B', 'u')}" if inputs else "")
    second = (f"{n['M']}{times}{n['v']}' + {product('C', 'v')} + {product('K', 'q')} = "
              + (product("F", "u") if inputs else "0"))
    return first, second
