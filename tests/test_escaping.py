"""Spec text never becomes live code or live LaTeX (lagcli/render/escape.py, docs/security.md).

Each escaping function is checked against the grammar it defends, with random
hostile text (hypothesis): Python with its own `tokenize`/`ast`, C with a small
lexer of translation phases 1-3 and a real strict compile, LaTeX with a TeX
tokenizer, XML with ElementTree. Then end to end: a spec whose description and
file name carry C, Python, LaTeX and terminal payloads goes through every command,
and the payloads never run; a `latex:` outside the safe subset is refused.
"""
from __future__ import annotations

import ast
import importlib.util
import io
import json
import re
import shutil
import subprocess
import tokenize
import xml.etree.ElementTree as ElementTree

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from lagcli.render import escape
from lagcli.spec.latex_subset import ONE_ARGUMENT, SYMBOLS, latex_problem

from conftest import ROOT

# Pieces that end or bend a context in one grammar or another.
HOSTILE = ["*/", "/*", "*\\", "\\", "??/", "??=", "??'", "??", "?", "*", "/", "\n", "\r", "\r\n",
           '"""', "'''", '"', "'", "\x00", "\x1b[2J", "\x9b", "\x07", "\b", "\u2028", "\u2029",
           "\x85", "\\\n", "\\ \n", "\x0c", "\x0b", "\t", "#", "coding: utf-7 ", "coding=latin-1",
           "+AAo-", "%", "$", "&", "{", "}", "^^", "^^5c", "~", "_", "^", "\\input", "\\def",
           "\\immediate\\write18", "<", ">", "]]>", "\u202e", "\u200b", "\ud800", "\ufffe", "é",
           "θ", "\u00d7", "\U0001f600", "--", " ", "x"]
hostile_text = st.lists(st.one_of(st.sampled_from(HOSTILE), st.characters()), max_size=40).map("".join)
EXAMPLES = settings(max_examples=200, deadline=None)


# -- Python ------------------------------------------------------------------------------

def _tokens(source: str) -> list[tuple[str, str]]:
    """(type, string) of the tokens of `source` read as a UTF-8 file (encoding cookie honoured)."""
    stream = io.BytesIO(source.encode("utf-8"))
    return [(tokenize.tok_name[t.type], t.string) for t in tokenize.tokenize(stream.readline)
            if t.type not in (tokenize.ENCODING, tokenize.NL, tokenize.NEWLINE, tokenize.ENDMARKER)]


@EXAMPLES
@given(hostile_text)
def test_python_comment_is_one_comment_token(text):
    comment = escape.python_comment(text)
    # lines 1 and 2, where a `coding:` comment would be an encoding declaration
    source = f"# {comment}\n# {comment}\nx = 1\n"
    assert _tokens(source) == [("COMMENT", f"# {comment}"), ("COMMENT", f"# {comment}"),
                               ("NAME", "x"), ("OP", "="), ("NUMBER", "1")]
    namespace: dict = {}
    exec(compile(source.encode("utf-8"), "<generated>", "exec"), namespace)
    assert set(namespace) - {"__builtins__"} == {"x"}


@EXAMPLES
@given(hostile_text)
def test_python_string_round_trips(text):
    literal = escape.python_string(text)
    source = f"# {escape.python_comment(text)}\ns = {literal}\n"
    assert [kind for kind, _ in _tokens(source)] == ["COMMENT", "NAME", "OP", "STRING"]
    (statement,) = ast.parse(source.encode("utf-8")).body
    assert isinstance(statement.value, ast.Constant) and statement.value.value == text


def test_encoding_declaration_is_defused():
    assert escape.python_comment("coding: utf-7 +AAo-import os") == "coding : utf-7 +AAo-import os"
    assert escape.python_comment("CODING=latin-1") == "CODING =latin-1"


# -- C -----------------------------------------------------------------------------------

TRIGRAPHS = {"??=": "#", "??(": "[", "??/": "\\", "??)": "]", "??'": "^", "??<": "{", "??!": "|",
             "??>": "}", "??-": "~"}


def c_phases(source: str) -> str:
    """C99 5.1.1.2 translation phases 1 (trigraphs) and 2 (backslash-newline splices)."""
    source = re.sub(r"\?\?[=(/)'<!>-]", lambda m: TRIGRAPHS[m.group()], source)
    return re.sub(r"\\[ \t]*\n", "", source)   # gcc also splices across trailing blanks


def c_comments(source: str) -> list[str]:
    """The bodies of the block comments of `source` after phases 1-2 (phase 3's rule)."""
    return re.findall(r"/\*(.*?)\*/", c_phases(source), re.DOTALL)


@EXAMPLES
@given(hostile_text)
def test_c_comment_stays_a_comment(text):
    body = escape.c_comment(text)
    assert "\n" not in body and "\r" not in body and not body.endswith("\\")
    assert "*/" not in body and "/*" not in body and not re.search(r"\?\?[=(/)'<!>-]", body)
    header = f"/* Generated from {body}: model.\n * {body}\n */\nint x;\n"
    assert c_phases(header).endswith("*/\nint x;\n")
    (comment,) = c_comments(header)
    assert "/*" not in comment                       # -Wcomment, an error under -Werror


def c_string_value(literal: str) -> bytes:
    """The bytes of a C string literal (the escapes c_string uses), checking it is one literal."""
    assert literal[0] == literal[-1] == '"'
    body = c_phases(literal)[1:-1]
    out, i = bytearray(), 0
    while i < len(body):
        ch = body[i]
        assert ch not in '"\n' and ch.isascii() and ch.isprintable(), repr(body)
        if ch != "\\":
            out.append(ord(ch))
            i += 1
        elif body[i + 1] in "01234567":
            out.append(int(body[i + 1:i + 4], 8))
            i += 4
        else:
            assert body[i + 1] in '\\"?', repr(body)
            out.append(ord(body[i + 1]))
            i += 2
    return bytes(out)


@EXAMPLES
@given(hostile_text)
def test_c_string_round_trips(text):
    assert c_string_value(escape.c_string(text)) == text.encode("utf-8", "replace")


TRICKY = ["*\\ int pwn = 1; /*", "*/ int pwn = 1; /*", "a ??/\nint pwn;", "x \\", "end *", "/ *",
          "??=define X", "\x00\x1b[2J\u202e\u2028", '"""\'\'\'', "caf\u00e9 \u03b8 \U0001f600"]


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_c_escapes_compile_strictly(tmp_path):
    comments = "".join(f"/* {escape.c_comment(t)} */\n/* from {escape.c_comment(t)}: x.\n * "
                       f"{escape.c_comment(t)}\n */\n" for t in TRICKY)
    strings = ", ".join(escape.c_string(t) for t in TRICKY)
    source = (comments + "#include <stdio.h>\nstatic const char *const s[] = {" + strings + "};\n"
              "int main(void) { size_t i, j; for (i = 0; i < sizeof s / sizeof *s; i++) {\n"
              "  for (j = 0; s[i][j]; j++) printf(\"%02x\", (unsigned char)s[i][j]);\n"
              "  printf(\"\\n\"); } return 0; }\n")
    (tmp_path / "t.c").write_text(source, encoding="utf-8")
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic", "t.c", "-o", "t"],
                   cwd=tmp_path, check=True, capture_output=True)
    out = subprocess.run(["./t"], cwd=tmp_path, check=True, capture_output=True, text=True).stdout
    assert out.split("\n")[:-1] == [t.encode("utf-8").split(b"\0")[0].hex() for t in TRICKY]  # C strings end at NUL


# -- LaTeX -------------------------------------------------------------------------------

# What latex_text itself writes: text commands (with their `{}`) and escaped specials.
LATEX_EMITTED = re.compile(r"\\(textbackslash|textasciitilde|textasciicircum|textless|textgreater"
                           r"|textbar|ldots)\{\}|\\[_%&#${}]")


@EXAMPLES
@given(hostile_text)
def test_latex_text_has_no_live_tex(text):
    tex = escape.latex_text(text)
    rest = LATEX_EMITTED.sub("", tex)
    assert not set(rest) & set("\\{}$&#^_%~"), rest   # no other control sequence, group, math...
    assert all(ch.isprintable() for ch in tex) and "\n" not in tex


@EXAMPLES
@given(hostile_text)
def test_latex_comment_is_one_line(text):
    comment = escape.latex_comment(text)
    assert all(ch.isprintable() for ch in comment)
    assert comment.splitlines() in ([comment], [])


def test_latex_text_is_readable():
    assert escape.latex_text("a_b%c&d#e$f{g}h") == r"a\_b\%c\&d\#e\$f\{g\}h"
    assert escape.latex_text("100% of k_0, caf\u00e9 \u2013 ok") == "100\\% of k\\_0, caf\u00e9 -- ok"


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex not installed")
def test_latex_text_compiles(tmp_path):
    """Every printable Latin-1 character and the hostile pieces as running text (and names,
    which are identifiers, in \\mathrm as multiplier labels are)."""
    texts = ["".join(chr(c) for c in range(0x20, 0x100)), *HOSTILE, "".join(HOSTILE)]
    body = "\n\n".join(escape.latex_text(t) for t in texts) + r" $\lambda_{\mathrm{%s}}$" % (
        escape.latex_text("roll_x_2"))
    (tmp_path / "t.tex").write_text(f"% {escape.latex_comment(''.join(HOSTILE))}\n\\documentclass{{article}}"
                                    f"\\begin{{document}}\n{body}\n\\end{{document}}\n", encoding="utf-8")
    subprocess.run(["pdflatex", "-no-shell-escape", "-halt-on-error", "-interaction=nonstopmode", "t.tex"],
                   cwd=tmp_path, check=True, capture_output=True, timeout=120)


ACCEPTED = [r"\theta_1", r"\hat{\mathbf{r}}", "m_{\\mathrm{bob}}", "x'", r"\varphi^{2}_{k}", "x''_1",
            r"\boldsymbol{\omega}", r"\mathrm{d}\, x", r"{x^2}^3", r"\dot{\hat x}", r"x_\alpha", "F_{x, y}"]


@pytest.mark.parametrize("latex", ACCEPTED)
def test_latex_subset_accepts(latex):
    assert latex_problem(latex) is None


@pytest.mark.skipif(shutil.which("pdflatex") is None, reason="pdflatex not installed")
def test_latex_subset_examples_compile(tmp_path):
    """Accepted symbols compile where lagcli puts them: alone, accented, squared, indexed."""
    symbols = (ACCEPTED + [f"\\{name}" for name in sorted(SYMBOLS)]
               + [f"\\{name} a" for name in sorted(ONE_ARGUMENT)] + [r"\, \: \; \! [a]/|*=<>:;!"])
    assert all(latex_problem(s) is None for s in symbols)
    body = "\n".join(f"${s}$ $\\dot{{{s}}}$ ${{{s}}}^{{2}}$ $\\left({s}\\right)_{{1}}$\n" for s in symbols)
    (tmp_path / "s.tex").write_text("\\documentclass{article}\\usepackage{amsmath}\\begin{document}\n"
                                    + body + "\\end{document}\n")
    subprocess.run(["pdflatex", "-no-shell-escape", "-halt-on-error", "-interaction=nonstopmode", "s.tex"],
                   cwd=tmp_path, check=True, capture_output=True, timeout=120)


@pytest.mark.parametrize("latex, problem", [
    (r"\input{/etc/passwd}", r"command \input"), (r"\immediate\openout1=x", r"command \immediate"),
    (r"\def\x{}", r"command \def"), (r"\catcode`\#=11", r"command \catcode"),
    (r"x\write18{ls}", r"command \write"), ("x^^5cinput", "'^^'"), ("a%b", "'%'"), ("#1", "'#'"),
    ("$", "'$'"), ("a&b", "'&'"), ("~", "'~'"), (r"a\\b", "line break"), ("{x", "unbalanced"),
    ("x}", "unbalanced"), ("x\x00", "control character"), ("x\x1b", "control character"),
    ("θ", r"\theta"), ("x" * 201, "longer than 200"), ("", "empty"), ("x_", "needs an argument"),
    (r"\hat", "needs an argument"), ("x_1_2", "double subscript"), (r"\mathbb{R}", r"command \mathbb"),
])
def test_latex_subset_refuses(latex, problem):
    assert problem in (latex_problem(latex) or "accepted")


# tokens as TeX reads them in math mode: control words/symbols, then single characters
TEX_TOKEN = re.compile(r"\\[A-Za-z]+|\\.|.", re.DOTALL)


@EXAMPLES
@given(st.lists(st.sampled_from(list("ab1 _^',.+-(){}[]%#$&~\\\n") +
                                [r"\input", r"\alpha", r"\hat", r"\mathrm", r"\def", "^^"]),
                max_size=12).map("".join))
def test_latex_subset_accepts_only_safe_tokens(latex):
    if latex_problem(latex) is not None:
        return
    depth = 0
    for token in TEX_TOKEN.findall(latex):
        assert token not in ("%", "#", "$", "&", "~", "\n", r"\\", r"\input", r"\def"), latex
        depth += {"{": 1, "}": -1}.get(token, 0)
        assert depth >= 0, latex
    assert depth == 0 and "^^" not in latex


# -- XML and terminals -------------------------------------------------------------------

@EXAMPLES
@given(hostile_text)
def test_xml_round_trips(text):
    kept = "".join(ch for ch in text if not re.match(escape._NOT_XML_CHAR, ch))
    element = ElementTree.fromstring(f'<a v="{escape.xml_attribute(text)}">{escape.xml_text(text)}</a>')
    assert element.get("v") == kept and (element.text or "") == kept


@EXAMPLES
@given(hostile_text)
def test_xml_comment_stays_one_comment(text):
    inside = escape.xml_comment(text)
    root = ElementTree.fromstring(f"<a><!-- {inside} --><b/></a>")   # parses: no `--` inside
    assert [child.tag for child in root] == ["b"] and "\n" not in inside


@EXAMPLES
@given(hostile_text)
def test_terminal_text_has_no_control_characters(text):
    shown = escape.terminal_text(text)
    assert all(ch in "\t\n" or ch.isprintable() or ch == " " for ch in shown), repr(shown)
    assert "\x1b" not in shown and "\x9b" not in shown and "\r" not in shown


@EXAMPLES
@given(hostile_text, st.integers(min_value=3, max_value=50))
def test_shorten(text, limit):
    short = escape.shorten(text, limit)
    assert len(short) <= limit and "\n" not in short


# -- end to end --------------------------------------------------------------------------

def hostile_spec(tmp_path, latex: str = r"\theta"):
    """A valid spec in a file whose name and description carry payloads for every target."""
    c_payload = f'*\\ int pwn = system("touch {tmp_path}/pwned_c"); /* */ int pwn2 = 1; /*'
    py_payload = f'coding: utf-7 +AAo-__import__("os").system("touch {tmp_path}/pwned_py")'
    tex_payload = r"\immediate\write18{touch pwned_tex}\input{/etc/passwd}}{ ^^5c"
    xml_payload = '--> <!-- "/><ScalarVariable name="pwn"/> &amp; ]]> <?pi?>'
    description = f"{py_payload} ??/ \\ {c_payload} \"\"\" ''' {tex_payload} \x1b]0;owned\x07\x1b[2J"
    text = ("name: hostile\n"
            f"description: {_yaml_string(description)}\n"
            f"coordinates: [{{name: theta, latex: {_yaml_string(latex)}}}]\n"
            f"parameters: {{k: {{value: 1.0, description: {_yaml_string(tex_payload + xml_payload)}}}}}\n"
            "kinetic: theta_dot**2/2\npotential: k*theta**2/2\n"
            "simulate: {t_end: 0.2, dt: 0.1}\n")
    path = tmp_path / "evil *\\ \"q' ??- .yaml"
    path.write_text(text, encoding="utf-8")
    return path


def _yaml_string(text: str) -> str:
    """A YAML double-quoted scalar (JSON strings are YAML)."""
    return json.dumps(text)


def _pwned(tmp_path) -> list[str]:
    return sorted(p.name for p in tmp_path.rglob("pwned*"))


@pytest.fixture
def run(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)

    def invoke(*args):
        from lagcli.cli import cli
        try:
            runner = CliRunner(mix_stderr=False)
        except TypeError:
            runner = CliRunner()
        return runner.invoke(cli, [str(a) for a in args])
    return invoke


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_hostile_spec_c(tmp_path, run):
    spec = hostile_spec(tmp_path)
    result = run("generate", spec, "--lang", "c", "-o", tmp_path / "out")
    assert result.exit_code == 0, result.output
    sources = sorted(p.name for p in (tmp_path / "out").glob("*.c"))   # model, driver, runtime
    subprocess.run(["cc", "-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic",
                    *sources, "-o", "hostile", "-lm"],
                   cwd=tmp_path / "out", check=True, capture_output=True)
    subprocess.run(["./hostile"], cwd=tmp_path / "out", check=True, capture_output=True)
    result = run("simulate", spec, "--backend", "c")
    assert result.exit_code == 0, result.output + result.stderr
    assert _pwned(tmp_path) == []


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_hostile_spec_fmu(tmp_path, run):
    fmpy = pytest.importorskip("fmpy")
    from fmpy.validation import validate_fmu

    spec = hostile_spec(tmp_path)
    result = run("generate", spec, "--lang", "fmu", "-o", tmp_path / "hostile.fmu")
    assert result.exit_code == 0, result.output
    assert validate_fmu(str(tmp_path / "hostile.fmu")) == []
    description = fmpy.read_model_description(str(tmp_path / "hostile.fmu"), validate=True)
    variables = {v.name: v for v in description.modelVariables}
    assert "pwn" not in variables
    assert variables["k"].description.endswith('--> <!-- "/><ScalarVariable name="pwn"/> &amp; ]]> <?pi?>')
    assert _pwned(tmp_path) == []


def test_hostile_spec_python(tmp_path, run):
    spec = hostile_spec(tmp_path)
    result = run("generate", spec, "--lang", "python", "-o", tmp_path / "hostile_module.py")
    assert result.exit_code == 0, result.output
    module_spec = importlib.util.spec_from_file_location("hostile_module", tmp_path / "hostile_module.py")
    module = importlib.util.module_from_spec(module_spec)
    module_spec.loader.exec_module(module)
    assert module.SPEC_FILE == spec.name
    assert run("simulate", spec, "--backend", "python").exit_code == 0
    assert _pwned(tmp_path) == []


@pytest.mark.parametrize("lang", ["casadi", "jax"])
def test_hostile_spec_casadi_jax(tmp_path, run, lang):
    """The CasADi and JAX modules use the Python escapes: the module imports, its
    constants hold the text as given, and nothing in the text runs."""
    pytest.importorskip(lang, reason=f"{lang} is not installed (pip install 'lagcli[{lang}]')")
    spec = hostile_spec(tmp_path)
    result = run("generate", spec, "--lang", lang, "-o", tmp_path / f"hostile_{lang}.py")
    assert result.exit_code == 0, result.output
    module_spec = importlib.util.spec_from_file_location(f"hostile_{lang}", tmp_path / f"hostile_{lang}.py")
    module = importlib.util.module_from_spec(module_spec)
    module_spec.loader.exec_module(module)
    assert module.SPEC_FILE == spec.name and module.STATE == ["theta", "theta_dot"]
    assert _pwned(tmp_path) == []


def test_hostile_spec_text_reports(tmp_path, run):
    spec = hostile_spec(tmp_path)
    for args in (("derive", spec, "--text"), ("check", spec)):
        result = run(*args)
        assert result.exit_code == 0, result.output
        assert "\x1b" not in result.stdout and "\x07" not in result.stdout
        assert "]0;owned" in result.stdout          # the text itself is still shown


def test_hostile_spec_latex(tmp_path, run):
    spec = hostile_spec(tmp_path)
    result = run("derive", spec, "--latex", "--standalone", "-o", tmp_path / "hostile.tex")
    assert result.exit_code == 0, result.output
    tex = (tmp_path / "hostile.tex").read_text(encoding="utf-8")
    for word in (r"\input", r"\write", r"\immediate", "^^"):
        assert word not in tex
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex not installed")
    subprocess.run(["pdflatex", "-no-shell-escape", "-halt-on-error", "-interaction=nonstopmode",
                    "hostile.tex"], cwd=tmp_path, check=True, capture_output=True, timeout=120)
    assert _pwned(tmp_path) == [] and not list(tmp_path.glob("pwned_tex*"))


def test_plot_title_is_not_mathtext(tmp_path, run):
    pytest.importorskip("matplotlib")
    spec = tmp_path / "x$\\frac$.yaml"   # two dollars: mathtext would parse it
    spec.write_text("coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\ninitial: {x: 1}\n")
    result = run("simulate", spec, "--t-end", "0.1", "--backend", "python", "--plot", "p.png", "-o", "out.csv")
    assert result.exit_code == 0, result.output + result.stderr
    assert (tmp_path / "p.png").stat().st_size > 0
    assert escape.plot_text("a$b$ \\$") == "a\\$b\\$ \\\\$"


def test_error_messages_reach_the_terminal_without_controls(tmp_path, run):
    (tmp_path / "keys.yaml").write_text('coordinates: [x]\nkinetic: x_dot**2/2\n"\\e]0;owned\\a\\e[2J": 1\n')
    result = run("check", "keys.yaml")
    assert result.exit_code == 2 and "unknown key" in result.stderr
    assert "\x1b" not in result.stderr and "\x07" not in result.stderr and "]0;owned" in result.stderr


def test_latex_outside_the_subset_is_refused(tmp_path, run):
    spec = hostile_spec(tmp_path, latex=r"\input{/etc/passwd}")
    result = run("derive", spec, "--latex")
    assert result.exit_code == 2 and result.stdout == ""
    assert f"{spec.name}:3:" in result.stderr
    assert r"coordinates[0].latex: command \input is not allowed" in result.stderr
    assert "hint: a latex: string may use" in result.stderr


def test_doc_example_passes(tmp_path, run):
    """The example of docs/spec.md, "LaTeX symbols", is accepted as written."""
    doc = (ROOT / "docs" / "spec.md").read_text(encoding="utf-8")
    section = doc.split("## LaTeX symbols", 1)[1]
    (tmp_path / "example.yaml").write_text(section.split("```yaml\n", 1)[1].split("```", 1)[0])
    result = run("check", "example.yaml")
    assert result.exit_code == 0, result.output
