"""Every command the README and docs/ show is run, as written, and behaves as shown.

- README: the lines of each ```sh block after the set-up block (the set-up block
  creates virtual environments; CI runs it).
- docs/*.md: transcript blocks, where `$ COMMAND` lines are followed by what they print.
  A command whose shown output carries a `hint:` or `error` line must fail with exit
  status 2; every other command must succeed, and when its shown output starts with a
  CSV header, stdout must start with the same header.

Commands run in a fresh folder holding a copy of the bundled specs, with the
installed `lagcli` first on PATH (and as `.venv/bin/lagcli`, as the README's set-up
makes it), and the checkout's `tests/` and `bench/` at hand; `cd` lines move within
that folder.
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = sorted((ROOT / "docs").glob("*.md"))
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.M | re.S)
SETUP = ". .venv/bin/activate"
# Optional tools a docs command may start with: without the tool, the transcript is
# skipped with the reason (the README's test command must pass on a machine without them).
OPTIONAL_TOOLS = {"cargo": "the Rust toolchain", "octave-cli": "GNU Octave", "octave": "GNU Octave",
                  "pdflatex": "TeX Live", "c++": "a C++ compiler", "g++": "a C++ compiler",
                  "chromium": "Chromium", "cc": "a C compiler"}


def missing_tool(command: str) -> str | None:
    """The reason to skip `command` when it starts with an optional tool not installed."""
    tool = command.split()[0] if command.split() else ""
    if tool not in OPTIONAL_TOOLS:
        return None
    found = shutil.which(tool) or (Path.home() / ".cargo" / "bin" / tool).exists()
    return None if found else f"no {tool} ({OPTIONAL_TOOLS[tool]}): this docs example is not run"


def blocks(path: Path):
    """(language, text) of each fenced block of a Markdown file."""
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(path.read_text(encoding="utf-8"))]


def readme_commands() -> list[str]:
    sh = [text for lang, text in blocks(ROOT / "README.md") if lang == "sh"]
    lines = [line.split("  #")[0].strip() for text in sh[1:] for line in text.splitlines()]
    return [line for line in lines if line and not line.startswith("#") and line != SETUP]


def transcripts() -> list[tuple[str, list[tuple[str, list[str]]]]]:
    """(doc name, [(command, shown output lines)]) for every block with `$ ` lines."""
    found = []
    for path in DOCS:
        for index, (_, text) in enumerate(blocks(path)):
            steps: list[tuple[str, list[str]]] = []
            for line in text.splitlines():
                if line.startswith("$ "):
                    steps.append((line[2:].strip(), []))
                elif steps:
                    steps[-1][1].append(line)
            if steps:
                found.append((f"{path.name}[{index}]", steps))
    return found


@pytest.fixture
def workdir(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "specs", tmp_path / "specs")
    for shared in ("tests", "bench"):                  # read by some examples, never written
        (tmp_path / shared).symlink_to(ROOT / shared)
    (tmp_path / ".venv").symlink_to(Path(sys.executable).parent.parent)
    return tmp_path


def environment(tmp_path: Path) -> dict:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}{os.pathsep}{Path.home() / '.cargo' / 'bin'}"
    env["XDG_CACHE_HOME"] = str(tmp_path / "cache")
    return env


def run(command: str, cwd: Path, env: dict) -> subprocess.CompletedProcess:
    return subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def test_readme_commands_run_as_written(workdir: Path):
    env = environment(workdir)
    for command in readme_commands():
        done = run(command, workdir, env)
        assert done.returncode == 0, f"README: {command}\n{done.stderr}"


@pytest.mark.parametrize("name,steps", transcripts(), ids=[n for n, _ in transcripts()])
def test_docs_transcripts_behave_as_shown(workdir: Path, name, steps):
    env, cwd = environment(workdir), workdir
    for command, shown in steps:
        if command.startswith("cd "):
            cwd = cwd / command[3:].strip()
            continue
        reason = missing_tool(command)
        if reason:
            pytest.skip(reason)
        done = run(command, cwd, env)
        fails = any("hint:" in line or "error" in line for line in shown)
        if fails:
            assert done.returncode == 2, f"{name}: {command} should fail\n{done.stdout}{done.stderr}"
            assert "Traceback" not in done.stderr
            assert shown[0] in done.stderr, f"{name}: {command} printed\n{done.stderr}"   # the real message
            continue
        assert done.returncode == 0, f"{name}: {command}\n{done.stderr}"
        if shown and shown[0].startswith("t,"):
            assert done.stdout.splitlines()[0] == shown[0], f"{name}: {command}"


def spec_blocks() -> list[tuple[str, str, str]]:
    """(where, suffix, text) of every complete spec shown in the README and docs/ (a
    block with `coordinates` and something with inertia; the rest are fragments)."""
    found = []
    for path in [ROOT / "README.md", *DOCS]:
        for index, (lang, text) in enumerate(blocks(path)):
            if lang in ("yaml", "toml") and re.search(r"^coordinates", text, re.M) \
                    and re.search(r"^(\[?particles|\[?bodies|kinetic)", text, re.M):
                found.append((f"{path.name}[{index}]", lang, text))
    return found


@pytest.mark.parametrize("where,lang,text", spec_blocks(), ids=[w for w, _, _ in spec_blocks()])
def test_specs_shown_in_docs_are_valid(tmp_path: Path, where, lang, text):
    spec = tmp_path / f"example.{lang}"
    spec.write_text(text, encoding="utf-8")
    done = run(f"lagcli check {spec}", tmp_path, environment(tmp_path))
    assert done.returncode == 0, f"{where}:\n{done.stderr}"
