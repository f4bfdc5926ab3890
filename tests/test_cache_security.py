"""The cache runs only what lagcli built: tampered, damaged or foreign entries are never
executed but rebuilt (with a note on stderr), an unsafe or unusable cache directory is
not used (a private temporary one is), an interrupted build leaves nothing behind, and
`lagcli cache info/clear` report and remove lagcli's entries only.

Every test has its own XDG_CACHE_HOME under tmp_path. The spec is a unit oscillator
(x'' = -x, x(0) = 1): x(pi) = -1 is the independent check that the output is right.
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.run import c_backend, cache
from lagcli.run.rows import parse_csv

from conftest import ROOT

OSCILLATOR = """\
name: osc
coordinates: [x]
parameters: {k: 1.0}
kinetic: x_dot**2/2
potential: k*x**2/2
initial: {x: 1.0}
"""
INTEGRITY = "failed its integrity check"
FALLBACK = "building in a private temporary directory instead"
needs_cc = pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler (cc)")
needs_root = pytest.mark.skipif(os.geteuid() != 0, reason="giving a file to another user needs root")


@pytest.fixture
def home(tmp_path, monkeypatch) -> Path:
    """XDG_CACHE_HOME for this test (the cache root is home / 'lagcli')."""
    home = tmp_path / "xdg"
    monkeypatch.setenv("XDG_CACHE_HOME", str(home))
    return home


@pytest.fixture
def spec(tmp_path) -> Path:
    path = tmp_path / "osc.yaml"
    path.write_text(OSCILLATOR)
    return path


def simulate(spec: Path, backend: str):
    return CliRunner().invoke(cli, ["simulate", str(spec), "--t-end", str(math.pi),
                                    "--dt", str(math.pi), "--backend", backend])


def assert_correct(result) -> None:
    assert result.exit_code == 0, result.output
    header, rows = parse_csv(result.stdout)
    assert rows[-1][header.index("x")] == pytest.approx(-1.0, abs=1e-8)


def entry(home: Path, kind: str) -> Path:
    """The one entry of `kind` ('C driver' or 'Python module') in the cache."""
    (found,) = [p for p in (home / "lagcli").iterdir()
                if not p.name.startswith(".") and json.loads((p / cache.MANIFEST).read_text())["label"].endswith(kind)]
    return found


def rewrite_manifest(directory: Path) -> None:
    """Record the files' current hashes, as someone able to write the entry could."""
    manifest = json.loads((directory / cache.MANIFEST).read_text())
    manifest["files"] = {name: hashlib.sha256((directory / name).read_bytes()).hexdigest()
                         for name in manifest["files"]}
    (directory / cache.MANIFEST).write_text(json.dumps(manifest))


# --- tampered and damaged entries ---------------------------------------------------

@needs_cc
def test_a_replaced_driver_is_not_run_but_rebuilt(home, spec, tmp_path):
    assert_correct(simulate(spec, "c"))
    marker = tmp_path / "ran"
    sim = entry(home, "C driver") / "sim"
    sim.write_text(f"#!/bin/sh\ntouch {marker}\n")          # same name, same mode 0700
    again = simulate(spec, "c")
    assert_correct(again)
    assert not marker.exists()
    assert INTEGRITY in again.stderr and "sim: its content differs" in again.stderr
    warm = simulate(spec, "c")                              # repaired: no note any more
    assert_correct(warm)
    assert INTEGRITY not in warm.stderr


def test_a_replaced_python_module_is_not_run_but_rebuilt(home, spec, tmp_path):
    assert_correct(simulate(spec, "python"))
    marker = tmp_path / "ran"
    module = entry(home, "Python module") / "module.py"
    module.write_text(f"open({str(marker)!r}, 'w').close()\n" + module.read_text())
    again = simulate(spec, "python")
    assert_correct(again)
    assert not marker.exists() and INTEGRITY in again.stderr
    assert "open(" not in module.read_text()                # the entry was rebuilt


@needs_cc
@pytest.mark.parametrize("damage", ["truncated binary", "bad meta.json", "meta.json without keys",
                                    "meta.json with a broken layout"])
def test_a_damaged_driver_entry_is_rebuilt(home, spec, damage):
    assert_correct(simulate(spec, "c"))
    directory = entry(home, "C driver")
    if damage == "truncated binary":
        data = (directory / "sim").read_bytes()
        (directory / "sim").write_bytes(data[: len(data) // 2])
    elif damage == "bad meta.json":
        (directory / "meta.json").write_text("{not json")
    elif damage == "meta.json without keys":   # consistent with the manifest, but useless
        (directory / "meta.json").write_text(json.dumps({"name": "osc"}))
        rewrite_manifest(directory)
    else:                                      # every key, but a layout that does not read back
        meta = json.loads((directory / "meta.json").read_text())
        (directory / "meta.json").write_text(json.dumps({**meta, "states": "osc"}))
        rewrite_manifest(directory)
    again = simulate(spec, "c")
    assert_correct(again)
    assert INTEGRITY in again.stderr and "Traceback" not in again.output
    assert INTEGRITY not in simulate(spec, "c").stderr


def _entry_with_script(tmp_path: Path) -> tuple[str, Path, Path]:
    """A published entry holding an executable script that would create a marker file."""
    key, marker = "0" * 32, tmp_path / "ran"
    with cache.new_entry(key) as work:
        (work / "sim").write_text(f"#!/bin/sh\ntouch {marker}\n")
        (work / "meta.json").write_text("{}")
        cache.publish(work, key, "test entry", executable="sim")
    return key, cache.cache_root() / key, marker


def _chown_all(directory: Path, uid: int) -> None:
    for path in [directory, *directory.iterdir()]:
        os.chown(path, uid, -1)


DAMAGES = {
    "no manifest": lambda d: (d / cache.MANIFEST).unlink(),
    "garbled manifest": lambda d: (d / cache.MANIFEST).write_text("[1, 2"),
    "manifest of another version": lambda d: (d / cache.MANIFEST).write_text(
        (d / cache.MANIFEST).read_text().replace(json.dumps(cache.__version__), '"0.0.0"')),
    "file missing": lambda d: (d / "meta.json").unlink(),
    "unexpected file": lambda d: ((d / "extra").write_text("x"), (d / "extra").chmod(0o600)),
    "entry readable by others": lambda d: d.chmod(0o755),
    "entry writable by the group": lambda d: d.chmod(0o770),
    "file writable by others": lambda d: (d / "sim").chmod(0o777),
    "binary is a symlink": lambda d: ((d / "sim").rename(d.parent / "real"),   # same bytes, elsewhere
                                      (d / "sim").symlink_to(d.parent / "real")),
    "binary is a fifo": lambda d: ((d / "sim").unlink(), os.mkfifo(d / "sim", 0o600)),
    "entry is a symlink": lambda d: (d.rename(d.with_name("elsewhere")), d.symlink_to(d.with_name("elsewhere"))),
}


@pytest.mark.parametrize("damage", list(DAMAGES))
def test_load_rejects_and_removes_unexpected_entries(home, tmp_path, damage):
    from lagcli.errors import RunNote

    key, directory, marker = _entry_with_script(tmp_path)
    assert cache.load(key, "sim") is not None               # intact: accepted
    DAMAGES[damage](directory)
    with pytest.warns(RunNote, match=INTEGRITY):            # the CLI shows it with its notes
        assert cache.load(key, "sim") is None
    assert not os.path.lexists(directory) and not marker.exists()


@needs_root
def test_an_entry_of_another_user_is_rejected_even_with_a_matching_manifest(home, tmp_path):
    from lagcli.errors import RunNote

    key, directory, marker = _entry_with_script(tmp_path)
    _chown_all(directory, 65534)
    with pytest.warns(RunNote, match=r"belongs to another user \(uid 65534\)"):
        assert cache.load(key, "sim") is None


@needs_cc
def test_the_driver_run_is_the_file_that_was_checked(home, spec, tmp_path):
    """A file swapped in after the check is not what runs (the check/use race)."""
    assert_correct(simulate(spec, "c"))
    compiler = c_backend.find_compiler()
    cached = c_backend.lookup(c_backend.cache_key(str(spec), spec.read_bytes(), compiler))
    marker, sim = tmp_path / "ran", entry(home, "C driver") / "sim"
    swapped = sim.with_name("swapped")
    swapped.write_text(f"#!/bin/sh\ntouch {marker}\n")
    swapped.chmod(0o700)
    os.replace(swapped, sim)
    done = subprocess.run([cached.binary, "--t-end", "0"], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.startswith("t,x,x_dot")
    assert not marker.exists()


# --- an unsafe or unusable cache directory ------------------------------------------

def _make_world_writable(home: Path) -> None:
    (home / "lagcli").mkdir(parents=True)
    (home / "lagcli").chmod(0o777)


def _make_a_file(home: Path) -> None:
    home.mkdir()
    (home / "lagcli").write_text("not a directory")


def _make_read_only(home: Path) -> None:
    (home / "lagcli").mkdir(parents=True, mode=0o500)


def _make_parent_world_writable(home: Path) -> None:
    (home / "lagcli").mkdir(parents=True, mode=0o700)
    home.chmod(0o777)


def _give_to_another_user(home: Path) -> None:
    (home / "lagcli").mkdir(parents=True, mode=0o700)
    os.chown(home / "lagcli", 65534, 65534)


def _link_to_another_users_directory(home: Path) -> None:
    home.mkdir()
    (home / "theirs").mkdir(mode=0o700)
    os.chown(home / "theirs", 65534, 65534)
    (home / "lagcli").symlink_to(home / "theirs")


ROOTS = {
    "world-writable": (_make_world_writable, "other users can write to it (mode 0777)"),
    "a file": (_make_a_file, "it is not a directory"),
    "parent world-writable": (_make_parent_world_writable, "is writable by other users"),
    "read-only": (_make_read_only, "it is not writable"),
    "another user's": (_give_to_another_user, "it belongs to another user (uid 65534)"),
    "a symlink to another user's": (_link_to_another_users_directory, "it belongs to another user (uid 65534)"),
}


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_cc)])
@pytest.mark.parametrize("case", list(ROOTS))
def test_an_unusable_cache_directory_is_not_used(home, spec, case, backend):
    make, reason = ROOTS[case]
    if "another user's" in case and os.geteuid() != 0:
        pytest.skip("giving a directory to another user needs root")
    make(home)
    before = sorted(os.listdir(home / "lagcli")) if (home / "lagcli").is_dir() else None
    result = simulate(spec, backend)
    assert_correct(result)
    if case == "read-only" and os.geteuid() == 0:
        return                                 # root may write anyway: the cache is simply used
    assert FALLBACK in result.stderr and reason in result.stderr
    assert "Traceback" not in result.output
    if before is not None:
        assert sorted(os.listdir(home / "lagcli")) == before


def test_a_symlink_to_a_private_directory_of_ones_own_is_used(home, spec, tmp_path):
    (tmp_path / "mine").mkdir(mode=0o700)
    home.mkdir()
    (home / "lagcli").symlink_to(tmp_path / "mine")
    result = simulate(spec, "python")
    assert_correct(result)
    assert FALLBACK not in result.stderr and len(os.listdir(tmp_path / "mine")) == 1


def test_quiet_silences_the_caches_remarks(home, spec):
    # the cache's notes go through the CLI's one notes mechanism: -q hides them (issue 25)
    _make_world_writable(home)
    loud = simulate(spec, "python")
    assert_correct(loud)
    assert FALLBACK in loud.stderr
    quiet = CliRunner().invoke(cli, ["simulate", "-q", str(spec), "--t-end", str(math.pi),
                                     "--dt", str(math.pi), "--backend", "python"])
    assert_correct(quiet)
    assert quiet.stderr == ""
    assert quiet.stdout == loud.stdout


def test_the_temporary_directory_is_removed_at_exit(home, spec, tmp_path):
    _make_world_writable(home)
    temporary = tmp_path / "tmp"
    temporary.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(home), "TMPDIR": str(temporary)}
    done = subprocess.run([sys.executable, "-m", "lagcli", "simulate", str(spec), "--backend", "python",
                           "--t-end", "0"], capture_output=True, text=True, env=env)
    assert done.returncode == 0 and FALLBACK in done.stderr
    assert list(temporary.iterdir()) == []


# --- interrupted builds -------------------------------------------------------------

@needs_cc
def test_a_failing_build_leaves_no_work_directory(home, spec, monkeypatch):
    def broken(*args):
        raise RuntimeError("the compiler exploded")

    monkeypatch.setattr(c_backend.toolchain, "compile_program", broken)
    result = simulate(spec, "c")
    assert isinstance(result.exception, RuntimeError)
    assert list((home / "lagcli").iterdir()) == []


FAKE_CC = """#!/bin/sh
if [ "$1" = --version ]; then echo "fake cc 1.0"; exit 0; fi
sleep 120
"""


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_signal_during_the_compile_leaves_no_work_directory(home, spec, tmp_path, signum):
    """A compiler that hangs; the signal arrives while the work directory exists."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "cc").write_text(FAKE_CC)
    (bin_dir / "cc").chmod(0o755)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(home),
           "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"}
    proc = subprocess.Popen([sys.executable, "-m", "lagcli", "simulate", str(spec), "--backend", "c"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    root = home / "lagcli"
    try:
        deadline = time.monotonic() + 120
        while not (root.is_dir() and os.listdir(root)) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert root.is_dir() and os.listdir(root), proc.communicate()
        proc.send_signal(signum)
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 1, stderr           # SIGTERM and SIGHUP end the run like Ctrl-C
    assert "Traceback" not in stderr
    assert os.listdir(root) == []


# --- lagcli cache info / clear ------------------------------------------------------

def test_cache_info_and_clear(home, spec):
    assert_correct(simulate(spec, "python"))
    root = home / "lagcli"
    (root / "notes.txt").write_text("mine")                  # not lagcli's: kept
    (root / "mine").mkdir()
    (root / f".{'a' * 32}.leftover").mkdir()                  # an interrupted run's work dir
    (root / ("b" * 32)).mkdir(mode=0o700)                     # an entry without its manifest
    runner = CliRunner()
    shown = runner.invoke(cli, ["cache", "info"])
    assert shown.exit_code == 0
    assert f"cache directory: {root}" in shown.stdout and "usable: yes" in shown.stdout
    assert "entries: 2," in shown.stdout and "osc: Python module" in shown.stdout
    assert f"{'b' * 32}  " in shown.stdout and "damaged: rebuilt on next use" in shown.stdout
    assert "left over by interrupted runs: 1" in shown.stdout
    cleared = runner.invoke(cli, ["cache", "clear"])
    assert cleared.exit_code == 0 and "removed 3 cache directories" in cleared.stdout
    assert sorted(os.listdir(root)) == ["mine", "notes.txt"]
    assert "entries: 0," in runner.invoke(cli, ["cache", "info"]).stdout


def test_cache_info_says_when_the_directory_is_not_used(home):
    _make_world_writable(home)
    shown = CliRunner().invoke(cli, ["cache", "info"])
    assert shown.exit_code == 0 and "usable: no: other users can write to it (mode 0777)" in shown.stdout


def test_cache_help_shows_examples():
    for args in (["cache", "--help"], ["cache", "info", "--help"], ["cache", "clear", "--help"]):
        result = CliRunner().invoke(cli, args)
        assert result.exit_code == 0 and "lagcli cache" in result.stdout
