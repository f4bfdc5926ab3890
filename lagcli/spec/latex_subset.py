"""The LaTeX a spec's `latex:` strings may use: a small, safe subset of math mode.

A `latex:` string is printed as a symbol inside formulas (`\\dot{...}`, `...^{2}`),
unescaped, so it is checked instead: tokenized the way TeX reads it (control words,
control symbols, characters) and parsed as a list of math atoms. Allowed:

    characters      letters, digits, spaces and  _ ^ ' , . + - ( ) [ ] / | * = < > : ; !
    groups          { ... }, balanced
    symbols         Greek letters (\\alpha ... \\omega, \\varepsilon, \\vartheta, \\varphi,
                    \\varpi, \\varrho, \\varsigma, \\Gamma ... \\Omega), \\ell \\hbar \\imath
                    \\jmath \\prime \\infty \\partial \\nabla \\circ \\ast \\star \\dagger \\ddagger
    one argument    accents \\hat \\bar \\dot \\ddot \\dddot \\tilde \\vec \\check \\breve \\acute
                    \\grave \\mathring \\widehat \\widetilde \\overline \\underline;
                    fonts \\mathrm \\mathbf \\mathit \\mathsf \\mathtt \\mathcal \\boldsymbol
    spacing         \\, \\: \\; \\!

`_`, `^` and the one-argument commands need an argument (one character, one symbol
or a { group }); an atom has at most one subscript and one superscript. Everything
else is refused: commands that read or write files or redefine TeX (\\input,
\\openout, \\write, \\def, \\catcode...), `^^` character codes, the specials
% # $ & ~ and \\\\, non-ASCII characters (write \\theta, not θ: pdflatex has no
glyph for them in math), unbalanced braces, more than MAX_LENGTH characters. So
every accepted string compiles inside `$...$` and can do nothing but typeset.
"""
from __future__ import annotations

import re

MAX_LENGTH = 200

GREEK = frozenset("""alpha beta gamma delta epsilon varepsilon zeta eta theta vartheta iota kappa
    lambda mu nu xi pi varpi rho varrho sigma varsigma tau upsilon phi varphi chi psi omega
    Gamma Delta Theta Lambda Xi Pi Sigma Upsilon Phi Psi Omega""".split())
SYMBOLS = GREEK | frozenset("ell hbar imath jmath prime infty partial nabla circ ast star "
                            "dagger ddagger".split())
ACCENTS = frozenset("hat bar dot ddot dddot tilde vec check breve acute grave mathring "
                    "widehat widetilde overline underline".split())
FONTS = frozenset("mathrm mathbf mathit mathsf mathtt mathcal boldsymbol".split())
ONE_ARGUMENT = ACCENTS | FONTS
SPACING = frozenset(r"\, \: \; \!".split())
CHARACTERS = frozenset("_^',.+-()[]/|*=<>:;! {}")

HINT = ("a latex: string may use letters, digits, spaces, _ ^ ' , . + - ( ) [ ] / | * = < > : ; ! "
        "and balanced { }, Greek letters (\\alpha ... \\Omega, \\varphi...), \\ell \\hbar \\prime "
        "\\infty \\partial \\nabla, accents (\\hat \\bar \\dot \\vec \\tilde...) and fonts "
        "(\\mathrm \\mathbf \\mathcal \\boldsymbol...) with one argument; see docs/spec.md, "
        "\"LaTeX symbols\"")

_TOKEN = re.compile(r"\\[A-Za-z]+|\\.?|.", re.DOTALL)


class LatexRefused(ValueError):
    """A `latex:` string outside the subset: `message` says why, `position` where (0-based)."""

    def __init__(self, message: str, position: int):
        super().__init__(message)
        self.message = message
        self.position = position


def latex_problem(text: str) -> str | None:
    """Why `text` is not in the subset (a sentence naming the first problem), or None."""
    try:
        check_latex(text)
    except LatexRefused as refused:
        return f"{refused.message} (at character {refused.position + 1})"
    return None


def check_latex(text: str) -> None:
    """Raise `LatexRefused` unless `text` is in the subset (see the module docstring)."""
    if not text.strip():
        raise LatexRefused("LaTeX symbol is empty", 0)
    if len(text) > MAX_LENGTH:
        raise LatexRefused(f"LaTeX symbol is longer than {MAX_LENGTH} characters", MAX_LENGTH)
    if "^^" in text:
        raise LatexRefused("'^^' (TeX's character-code notation) is not allowed", text.index("^^"))
    tokens = [(m.group(), m.start()) for m in _TOKEN.finditer(text)]
    for token, position in tokens:
        _check_token(token, position)
    _Parser(tokens, len(text)).math_list()


def _check_token(token: str, position: int) -> None:
    if token.isascii() and token.isalnum() or token in CHARACTERS or token in SPACING:
        return
    if token.startswith("\\"):
        if token == "\\\\":
            raise LatexRefused("a line break '\\\\' is not allowed", position)
        if len(token) == 1:
            raise LatexRefused("a lone backslash is not allowed", position)
        if token[1:] not in SYMBOLS | ONE_ARGUMENT:
            raise LatexRefused(f"command {token} is not allowed", position)
        return
    code = f"U+{ord(token):04X}"
    if not token.isprintable():
        raise LatexRefused(f"control character {code} is not allowed", position)
    if not token.isascii():
        raise LatexRefused(f"character '{token}' ({code}) is not allowed: write it as a command, "
                           "e.g. \\theta for θ", position)
    raise LatexRefused(f"character '{token}' is not allowed", position)


class _Parser:
    """Math list := atom*, atom := nucleus? (_ arg | ^ arg | ')*, arg := token | { list }."""

    def __init__(self, tokens: list[tuple[str, int]], end: int):
        self.tokens = tokens
        self.i = 0
        self.end = end

    def peek(self) -> str | None:
        return self.tokens[self.i][0] if self.i < len(self.tokens) else None

    def position(self) -> int:
        return self.tokens[self.i][1] if self.i < len(self.tokens) else self.end

    def take(self) -> str:
        token = self.tokens[self.i][0]
        self.i += 1
        return token

    def skip_spaces(self) -> None:
        while self.peek() == " ":
            self.i += 1

    def math_list(self, closing: bool = False) -> None:
        """Atoms up to the end (or up to the `}` that closes a group, when `closing`)."""
        while True:
            self.skip_spaces()
            token = self.peek()
            if token is None:
                if closing:
                    raise LatexRefused("unbalanced braces: a '{' is not closed", self.end)
                return
            if token == "}":
                if not closing:
                    raise LatexRefused("unbalanced braces: '}' without '{'", self.position())
                self.take()
                return
            self.atom()

    def atom(self) -> None:
        if self.peek() not in ("_", "^", "'"):
            self.argument(nucleus=True)
        has_sub = has_sup = False
        while True:
            self.skip_spaces()
            token, position = self.peek(), self.position()
            if token == "_" and has_sub or token in ("^", "'") and has_sup:
                kind = "subscript" if token == "_" else "superscript"
                raise LatexRefused(f"double {kind}: group it, e.g. x_{{12}} or {{x^2}}^3", position)
            if token not in ("_", "^", "'"):
                return
            self.take()
            if token == "_":
                has_sub = True
                self.argument(after="'_'")
            elif token == "^":
                has_sup = True
                self.argument(after="'^'")

    def argument(self, after: str = "", nucleus: bool = False) -> None:
        """One token or a { group }; a one-argument command takes its own argument."""
        self.skip_spaces()
        token, position = self.peek(), self.position()
        if token is None or token in ("}", "_", "^", "'") or (token in SPACING and not nucleus):
            raise LatexRefused(f"{after} needs an argument: one character, one command or a {{ group }}",
                               position)
        self.take()
        if token == "{":
            self.math_list(closing=True)
        elif token[1:] in ONE_ARGUMENT:
            if after and not nucleus:
                raise LatexRefused(f"{token} as the argument of {after} needs braces: {{{token}{{...}}}}",
                                   position)
            self.argument(after=token)
