"""Compiled templates are kept between commands under the cache's trust rules
(`lagcli.run.template_cache`): the same bytes with or without them, nothing of a tampered
entry is run, an unsafe root is not used, and `lagcli cache info/clear` count and remove them."""
from __future__ import annotations

import json
import marshal
import os
import pickle
import subprocess
import sys
from pathlib import Path

from click.testing import CliRunner
from jinja2.bccache import bc_magic

from lagcli.cli import cli
from lagcli.run import cache

ROOT = Path(__file__).resolve().parent.parent
SPEC = ROOT / "specs" / "double_pendulum.yaml"


def generate(home: Path, out: Path) -> subprocess.CompletedProcess:
    """`lagcli generate --lang c` in a fresh process (templates are kept in memory within one)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(home)}
    done = subprocess.run([sys.executable, "-m", "lagcli", "generate", str(SPEC), "--lang", "c", "-o", str(out)],
                          capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    return done


def derive_text(home: Path) -> subprocess.CompletedProcess:
    """`lagcli derive --text` (one template, report/derive.txt.jinja) in a fresh process."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(home)}
    done = subprocess.run([sys.executable, "-m", "lagcli", "derive", str(SPEC), "--text"],
                          capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    return done


def files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def template_entries(home: Path) -> dict[str, float]:
    root = home / "lagcli-templates"
    return {p.name: (p / "template.code").stat().st_mtime_ns for p in sorted(root.iterdir())}


def unsafe_home(tmp_path: Path) -> Path:
    """A cache home others may write to: neither cache may be used there."""
    home = tmp_path / "shared"
    home.mkdir()
    home.chmod(0o777)
    return home


def test_a_second_command_reads_the_compiled_templates_and_writes_the_same_bytes(tmp_path):
    home = tmp_path / "xdg"
    generate(home, tmp_path / "cold")
    kept = template_entries(home)
    assert len(kept) >= 3                        # model.c, model.h, main.c at least
    generate(home, tmp_path / "warm")
    assert template_entries(home) == kept        # read, not compiled and written again
    generate(unsafe_home(tmp_path), tmp_path / "uncached")
    assert files(tmp_path / "warm") == files(tmp_path / "cold") == files(tmp_path / "uncached")


def test_code_that_differs_from_its_manifest_is_never_run(tmp_path):
    home = tmp_path / "xdg"
    cold = derive_text(home)
    marker = tmp_path / "ran"
    hostile = compile(f"open({str(marker)!r}, 'w').close()", "<hostile>", "exec")
    for entry in (home / "lagcli-templates").iterdir():
        code = entry / "template.code"
        blob = code.read_bytes()[len(bc_magic):]
        checksum = pickle.loads(blob)                           # Jinja's own check would pass
        code.write_bytes(bc_magic + pickle.dumps(checksum, 2) + marshal.dumps(hostile))
    done = derive_text(home)
    assert not marker.exists()
    assert "failed its integrity check" in done.stderr and "its content differs" in done.stderr
    assert done.stdout == cold.stdout
    assert "lagcli:" not in derive_text(home).stderr    # the rebuilt entry is read quietly


def test_an_entry_others_may_read_or_write_is_not_used(tmp_path):
    home = tmp_path / "xdg"
    cold = derive_text(home)
    (entry,) = sorted((home / "lagcli-templates").iterdir())[:1]
    (entry / "template.code").chmod(0o644)
    manifest = json.loads((entry / cache.MANIFEST).read_text())
    assert manifest["label"] == "compiled template"
    done = derive_text(home)
    assert "not private to its owner" in done.stderr
    assert done.stdout == cold.stdout


def test_an_unsafe_root_is_not_used_and_not_mentioned(tmp_path):
    home = unsafe_home(tmp_path)
    done = derive_text(home)
    assert "lagcli:" not in done.stderr          # no note: `derive` uses no run cache, nothing to say
    assert not (home / "lagcli-templates").exists()


def test_cache_info_and_clear_count_the_compiled_templates(tmp_path, monkeypatch):
    home = tmp_path / "xdg"
    derive_text(home)
    count = len(template_entries(home))
    monkeypatch.setenv("XDG_CACHE_HOME", str(home))
    runner = CliRunner()
    shown = runner.invoke(cli, ["cache", "info"])
    assert shown.exit_code == 0
    assert f"compiled templates: {count}, " in shown.stdout and str(home / "lagcli-templates") in shown.stdout
    cleared = runner.invoke(cli, ["cache", "clear"])
    assert cleared.exit_code == 0 and f"removed {count} compiled templates" in cleared.stdout
    assert list((home / "lagcli-templates").iterdir()) == []
    assert "compiled templates" not in runner.invoke(cli, ["cache", "info"]).stdout
