"""Spec text into generated files: one escaping function per target grammar.

A spec is untrusted, and some of its text reaches generated code and documents:
the description, parameter descriptions, the spec's file name, constraint labels
(names are identifiers checked by the schema; `latex:` strings are checked
against a safe subset by `lagcli.spec.latex_subset`). Every such piece goes
through exactly one of these functions, chosen by where it lands:

    c_comment(text)        inside /* ... */, one line         C source headers
    c_string(text)         a "..." literal, quotes included   C source
    python_comment(text)   after '#', one line                Python module header
    python_string(text)    a '...' literal, quotes included   Python module constants
    latex_comment(text)    after '%', one line                LaTeX header lines
    octave_comment(text)   after '% ', one line               MATLAB/Octave files
    octave_string(text)    a '...' literal (a char row)       MATLAB/Octave files
    rust_comment(text)     after '// ', one line              Rust sources
    rust_string(text)      a "..." literal, quotes included   Rust sources
    latex_text(text)       running text                       LaTeX titles, descriptions
    xml_text(text)         element content                    FMI model description
    xml_attribute(text)    inside "..." of an attribute        FMI model description
    xml_comment(text)      inside <!-- ... -->, one line      FMI model description header
    terminal_text(text)    what a terminal prints             text reports, error messages
    plot_text(text)        a matplotlib title or label        --plot
    html_text(text)        element content or an attribute     the shared page (report -o page.html)

Each defends the rule of its grammar that would let text end its context (a
comment's terminator, a string's quote, a line end) or change how the rest of the
file is read (a trigraph, a line splice, an encoding declaration, a TeX control
sequence), so the output's token structure is the template's whatever the text.
The one-line targets also drop invisible format characters (bidirectional
overrides: "Trojan Source", CVE-2021-42574), which can make a comment look like
code. The templates apply them as Jinja filters (`lagcli.render.templates`);
tests/test_escaping.py checks each against its grammar with random text.
"""
from __future__ import annotations

import re

ELLIPSIS = "..."


def _one_line(text: str) -> str:
    """`text` as one line of printable characters: whitespace runs (newlines, tabs,
    U+0085, U+2028...) become one space, other non-printable characters (controls,
    format characters such as bidi overrides, surrogates, private use) are dropped."""
    return "".join(ch for ch in " ".join(str(text).split()) if ch.isprintable())


def shorten(text: str, limit: int) -> str:
    """At most `limit` (>= 3) characters of `text` as one line, cut at a space when
    one is near, with '...' when cut (for comment headers; apply before escaping)."""
    text = _one_line(text)
    if len(text) <= limit:
        return text
    cut = text[: max(limit - len(ELLIPSIS), 0)]
    space = cut.rfind(" ")
    if space >= len(cut) // 2:
        cut = cut[:space]
    return cut.rstrip() + ELLIPSIS


# -- C ---------------------------------------------------------------------------------

def c_comment(text: str) -> str:
    """One line of text for the inside of a C block comment.

    C99 5.1.1.2 reads trigraphs (phase 1) and backslash-newline splices (phase 2)
    before comments (phase 3), and 6.4.9 ends a block comment at the first `*/`.
    So: one line (no newline to splice or to start a line of code), `*/` and `/*`
    split by a space (`/*` inside a comment is -Wcomment, an error under -Werror),
    `??` split (no trigraph, `??/` is a backslash), no trailing backslash.
    """
    text = _one_line(text)
    text = re.sub(r"\*(?=/)|/(?=\*)", r"\g<0> ", text)
    text = re.sub(r"\?(?=\?)", "? ", text)
    return text.rstrip(" \\")


_C_ESCAPES = {"\\": "\\\\", '"': '\\"', "?": "\\?"}


def c_string(text: str) -> str:
    """A C99 string literal, quotes included, whose bytes are `text` in UTF-8.

    6.4.5: a string literal ends at an unescaped `"` or a newline. Backslash and
    quote are escaped, `?` too (no `??x` trigraph), and every byte outside
    printable ASCII is a 3-digit octal escape (octal stops after 3 digits, a hex
    escape would swallow the following hex digits). Lone surrogates become '?'.
    """
    out = []
    for byte in str(text).encode("utf-8", "replace"):
        ch = chr(byte)
        if ch in _C_ESCAPES:
            out.append(_C_ESCAPES[ch])
        elif 0x20 <= byte < 0x7F:
            out.append(ch)
        else:
            out.append(f"\\{byte:03o}")
    return '"' + "".join(out) + '"'


# -- Python ----------------------------------------------------------------------------

_CODING = re.compile(r"(coding)(?=[:=])", re.IGNORECASE)


def python_comment(text: str) -> str:
    """One line of text for a Python comment (after `# `).

    A comment runs to the end of the physical line (Python reference 2.1.3), so the
    text is one line with no NUL (a syntax error in source). A comment on line 1 or
    2 matching `coding[:=]` is an encoding declaration (2.1.4, PEP 263) and
    `coding: utf-7` would let `+AAo-` start a new line of code: `coding:` becomes
    `coding :`.
    """
    return _CODING.sub(r"\1 ", _one_line(text))


def python_string(text: str) -> str:
    """A Python string literal, quotes included, whose value is `text` (`repr`:
    every quote, backslash, line break and non-printable character escaped)."""
    return repr(str(text))


# -- LaTeX -----------------------------------------------------------------------------

_LATEX_SPECIALS = {"\\": r"\textbackslash{}", "_": r"\_", "%": r"\%", "&": r"\&", "#": r"\#",
                   "$": r"\$", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}",
                   "^": r"\textasciicircum{}", "<": r"\textless{}", ">": r"\textgreater{}",
                   "|": r"\textbar{}"}
_LATEX_UNICODE = {"\u2013": "--", "\u2014": "---", "\u2018": "`", "\u2019": "'", "\u201c": "``",
                  "\u201d": "''", "\u2026": r"\ldots{}"}
_LATIN1_NOT_IN_OT1 = frozenset("\u00d0\u00de\u00f0\u00fe")   # Ð Þ ð þ: no glyph in the default font


def latex_comment(text: str) -> str:
    """One line of text for a LaTeX comment (after `%`).

    TeX drops the rest of the input line after a `%` without reading it as tokens
    (The TeXbook, ch. 8), so one line of visible characters is enough.
    """
    return _one_line(text)


def latex_text(text: str) -> str:
    """`text` as LaTeX running text (a title, a description; in \\mathrm{} only names,
    which are identifiers: the text commands below are not for math mode).

    Each of TeX's special characters (catcodes 0-8, 13, 14: \\ { } $ & # ^ _ ~ %)
    becomes its text command, as do < > | (OT1 prints them as other glyphs), so no
    control sequence, group, math shift or parameter can come from the text. One
    paragraph: whitespace runs become one space (a blank line would start a new
    paragraph), invisible characters are dropped (TeX refuses C0 controls). pdflatex
    reads UTF-8: ASCII and the Latin-1 letters pass, typographic dashes and quotes
    become their TeX ligatures, anything else prints as [U+XXXX].
    """
    out = []
    for ch in _one_line(text):
        if ch in _LATEX_SPECIALS:
            out.append(_LATEX_SPECIALS[ch])
        elif ch in _LATEX_UNICODE:
            out.append(_LATEX_UNICODE[ch])
        elif ch < "\x7f" or ("\u00c0" <= ch <= "\u00ff" and ch not in _LATIN1_NOT_IN_OT1):
            out.append(ch)
        else:
            out.append(f"[U+{ord(ch):04X}]")
    return "".join(out)


# -- MATLAB / Octave --------------------------------------------------------------------

def octave_comment(text: str) -> str:
    """One line of text for a MATLAB/Octave comment (after `% `).

    A `%` comment runs to the end of the line (MATLAB "Add Comments to Code"); a line
    holding only `%{` or `%}` opens or closes a block comment, which the `% ` prefix
    rules out, as it rules out Octave's `#{`. So: one line of visible characters.
    """
    return _one_line(text)


def octave_string(text: str) -> str:
    """A MATLAB/Octave expression whose value is the text `text`, written in ASCII.

    Printable ASCII goes in '...' with `'` doubled (the only special character of a
    single-quoted literal: neither MATLAB nor Octave reads backslash escapes there).
    Any other run of characters is `native2unicode(uint8([...]), 'UTF-8')` of its UTF-8
    bytes, which both read the same way (MATLAB's char is UTF-16, Octave's holds UTF-8),
    so neither the file's encoding nor a control character can change the value.
    """
    parts = []
    for printable, run in _runs(str(text), lambda ch: " " <= ch < "\x7f"):
        if printable:
            parts.append("'" + run.replace("'", "''") + "'")
        else:
            data = " ".join(str(b) for b in run.encode("utf-8", "replace"))
            parts.append(f"native2unicode(uint8([{data}]), 'UTF-8')")
    if not parts:
        return "''"
    return parts[0] if len(parts) == 1 else "[" + ", ".join(parts) + "]"


def _runs(text: str, test):
    """(test(ch), run) for the maximal runs of `text` on which `test` is constant."""
    run, kind = [], None
    for ch in text:
        if run and test(ch) != kind:
            yield kind, "".join(run)
            run = []
        kind = test(ch)
        run.append(ch)
    if run:
        yield kind, "".join(run)


# -- Rust ------------------------------------------------------------------------------

def rust_comment(text: str) -> str:
    """One line of text for a Rust line comment (after `// `).

    A line comment runs to the end of the line (Rust reference, "Comments"); `///` and
    `//!` would make it a doc comment (an attribute: misplaced, a compile error), so a
    leading `/` or `!` gets a space before it. Bidirectional-override characters are
    a deny-by-default lint in comments; `_one_line` drops them with every other
    invisible character.
    """
    text = _one_line(text)
    return " " + text if text[:1] in ("/", "!") else text


def rust_string(text: str) -> str:
    """A Rust string literal, quotes included, whose value is `text`: backslash and
    quote escaped, printable ASCII as it is, everything else as `\\u{XXXX}`
    (a lone surrogate, which no Rust string can hold, as U+FFFD)."""
    out = []
    for ch in str(text):
        if ch in '\\"':
            out.append("\\" + ch)
        elif " " <= ch < "\x7f":
            out.append(ch)
        else:
            code = ord(ch) if not 0xD800 <= ord(ch) <= 0xDFFF else 0xFFFD
            out.append(f"\\u{{{code:x}}}")
    return '"' + "".join(out) + '"'


# -- XML -------------------------------------------------------------------------------

# XML 1.0 section 2.2: Char ::= #x9 | #xA | #xD | [#x20-#xD7FF] | [#xE000-#xFFFD] | [#x10000-#x10FFFF].
# Kept as text: `re` compiles it on first use and caches it (compiling this class costs
# ~7 ms, which every command paid at import while only the FMU's model description uses it).
_NOT_XML_CHAR = "[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"


def _xml_escape(text: str, entities: dict) -> str:
    from xml.sax.saxutils import escape   # imported here: it pulls in urllib (16 ms of every command)

    return escape(text, entities)


def xml_text(text: str) -> str:
    """`text` as XML character data: `&` and `<` escaped (XML 1.0 2.4), `>` too
    (no `]]>`), CR as a reference (end-of-line handling, 2.11, would make it a
    newline), characters XML 1.0 forbids (2.2: most C0 controls, surrogates,
    U+FFFE/FFFF) dropped."""
    return _xml_escape(re.sub(_NOT_XML_CHAR, "", str(text)), {"\r": "&#13;"})


def xml_attribute(text: str) -> str:
    """`text` for the inside of a double-quoted XML attribute value: as `xml_text`,
    plus `"` (ends the value) and tab/newline/CR as character references
    (attribute-value normalisation, 3.3.3, would turn them into spaces)."""
    return _xml_escape(re.sub(_NOT_XML_CHAR, "", str(text)),
                       {'"': "&quot;", "'": "&apos;", "\t": "&#9;", "\n": "&#10;", "\r": "&#13;"})


def xml_comment(text: str) -> str:
    """One line of text for the inside of an XML comment: XML 1.0 2.5 forbids `--`
    in a comment and a `-` just before its closing `-->`, so every `-` followed by
    another (or ending the text) gets a space after it; characters XML forbids are
    dropped."""
    return re.sub(r"-(?=-|$)", "- ", re.sub(_NOT_XML_CHAR, "", _one_line(text)))


# -- terminals -------------------------------------------------------------------------

def terminal_text(text: str) -> str:
    """`text` for a terminal: no control characters, so no escape sequence (ESC,
    CSI U+009B), carriage return or backspace can move the cursor, recolour or
    retitle the terminal. Newlines and tabs are kept, other line breaks (U+0085,
    U+2028...) become spaces, invisible format characters (bidi overrides) are dropped."""
    return "".join(_terminal_char(ch) for ch in str(text).replace("\r\n", "\n"))


def _terminal_char(ch: str) -> str:
    if ch in "\t\n":
        return ch
    if ch.isspace():
        return " "
    return ch if ch.isprintable() else ""


# -- matplotlib ------------------------------------------------------------------------

def plot_text(text: str) -> str:
    """`text` for a matplotlib title or label: one line, and every `$` escaped
    (`\\$`), since text between two `$` is parsed as mathtext (a parse error
    would stop the plot)."""
    return _one_line(text).replace("$", r"\$")


# -- HTML ------------------------------------------------------------------------------

def html_text(text: str) -> str:
    """`text` inside an HTML element or a quoted attribute: &, <, >, both quotes as
    character references (no markup, no end of the attribute), control and invisible
    format characters dropped (newlines and tabs kept)."""
    import html

    return html.escape(terminal_text(text), quote=True)


# The Jinja filters of the template environment (lagcli.render.templates).
FILTERS = {f.__name__: f for f in (c_comment, c_string, python_comment, python_string,
                                   latex_comment, latex_text, octave_comment, octave_string,
                                   rust_comment, rust_string, xml_text, xml_attribute, xml_comment,
                                   terminal_text, plot_text)}
