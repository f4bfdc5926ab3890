"""Where `-o` writes (lagcli/render/output.py): regular files replaced atomically with their
mode kept, FIFOs and devices written as streams, symlinks followed, and bad targets
refused (exit status 2) before any work starts; the bounded copy `--plot` keeps.

Streaming, signals and memory of `lagcli simulate` are in tests/test_simulate_cli.py.
"""
from __future__ import annotations

import os
import stat
import threading

import pytest
from click.testing import CliRunner

from lagcli.cli import cli
from lagcli.render.output import TEMP_SUFFIX, write_output
from lagcli.run.rows import Decimated, parse_csv

from conftest import spec_path


@pytest.fixture(autouse=True)
def _shared_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "xdg-cache"))


def invoke(*args):
    return CliRunner().invoke(cli, [*map(str, args)])


def read_fifo(path, sink: list) -> threading.Thread:
    def read():
        with open(path, "rb") as fifo:
            sink.append(fifo.read())
    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    return reader


def temporaries(directory) -> list[str]:
    return [p.name for p in directory.iterdir() if p.name.endswith(TEMP_SUFFIX)]


def test_a_fifo_receives_the_csv_and_stays_a_fifo(tmp_path):
    fifo = tmp_path / "rows"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader = read_fifo(fifo, received)
    result = invoke("simulate", spec_path("double_pendulum"), "--t-end", "0.2", "--dt", "0.1", "-o", fifo)
    reader.join(timeout=60)
    assert result.exit_code == 0, result.stderr
    header, rows = parse_csv(received[0].decode())
    assert header[:3] == ["t", "theta1", "theta2"] and [r[0] for r in rows] == pytest.approx([0, 0.1, 0.2])
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode) and temporaries(tmp_path) == []


def test_dev_null_stays_a_character_device():
    before = os.stat("/dev/null")
    if not stat.S_ISCHR(before.st_mode):
        pytest.skip("/dev/null is not a character device on this machine (replaced by an older lagcli?)")
    result = invoke("simulate", spec_path("double_pendulum"), "--t-end", "0.1", "-o", "/dev/null")
    assert result.exit_code == 0, result.stderr
    after = os.stat("/dev/null")
    assert stat.S_ISCHR(after.st_mode) and after.st_ino == before.st_ino and after.st_rdev == before.st_rdev


def test_a_symlink_keeps_pointing_at_its_replaced_target(tmp_path):
    (tmp_path / "data").mkdir()
    target = tmp_path / "data" / "eom.txt"
    target.write_text("old\n")
    link = tmp_path / "latest.txt"
    link.symlink_to(target)
    write_output(str(link), "new\n")
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_text() == "new\n" and temporaries(tmp_path / "data") == []


def test_a_dangling_symlink_creates_its_target(tmp_path):
    link = tmp_path / "out.csv"
    link.symlink_to(tmp_path / "real.csv")
    write_output(str(link), "x\n")
    assert link.is_symlink() and (tmp_path / "real.csv").read_text() == "x\n"


def test_an_existing_file_keeps_its_mode_and_a_new_one_follows_the_umask(tmp_path):
    kept = tmp_path / "private.csv"
    kept.write_text("old\n")
    kept.chmod(0o600)
    result = invoke("simulate", spec_path("double_pendulum"), "--t-end", "0.1", "-o", kept)
    assert result.exit_code == 0, result.stderr
    assert stat.S_IMODE(kept.stat().st_mode) == 0o600 and kept.read_text().startswith("t,")
    mask = os.umask(0o022)
    try:
        write_output(str(tmp_path / "new.txt"), "x")
    finally:
        os.umask(mask)
    assert stat.S_IMODE((tmp_path / "new.txt").stat().st_mode) == 0o644


def _no_work(monkeypatch):
    """Make any derivation or integration fail the test: bad targets are refused first."""
    import lagcli.commands
    import lagcli.system

    def forbidden(*args, **kwargs):
        raise AssertionError("work started before the output was checked")

    monkeypatch.setattr(lagcli.commands, "_run_request", forbidden)     # a run (warm or cold)
    monkeypatch.setattr(lagcli.commands, "_derive", forbidden)
    monkeypatch.setattr(lagcli.system, "load", forbidden)               # a System: the derivation


@pytest.mark.parametrize("command", [
    ("simulate", "--t-end", "1e6", "-o", "{missing}/traj.csv"),
    ("simulate", "--t-end", "1e6", "-o", "{dir}"),
    ("simulate", "--t-end", "1e6", "-o", "{dir}/traj.csv", "--plot", "{missing}/traj.png"),
    ("simulate", "--t-end", "1e6", "-o", "{dir}/traj.csv", "--plot", "{dir}"),
    ("derive", "-o", "{missing}/eom.txt"),
    ("derive", "--json", "-o", "{dir}"),
    ("generate", "--lang", "python", "-o", "{missing}/dp.py"),
    ("generate", "--lang", "latex", "-o", "{dir}"),
    ("generate", "--lang", "c", "-o", "{missing}/deeper/dp_c"),
    ("generate", "--lang", "c", "-o", "{dir}/a_file"),
])
def test_a_bad_target_fails_with_exit_2_before_any_work(tmp_path, monkeypatch, command):
    _no_work(monkeypatch)
    (tmp_path / "a_file").write_text("keep\n")
    paths = {"missing": tmp_path / "missing", "dir": tmp_path}
    name, *options = command
    options = [o.format(**paths) for o in options]
    result = invoke(name, spec_path("double_pendulum"), *options)
    assert result.exit_code == 2, result.output
    bad = next(o for o in options if "missing" in o or o == str(tmp_path) or o.endswith("a_file"))
    assert f"cannot write {bad}" in result.stderr or f"into {bad}" in result.stderr
    assert "Traceback" not in result.output and result.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]
    assert (tmp_path / "a_file").read_text() == "keep\n"


def test_generate_c_creates_its_directory_but_not_its_parents(tmp_path):
    result = invoke("generate", spec_path("double_pendulum"), "--lang", "c", "-o", tmp_path / "dp_c")
    assert result.exit_code == 0, result.output
    written = {p.name for p in (tmp_path / "dp_c").iterdir()}
    assert {"double_pendulum.c", "double_pendulum.h", "double_pendulum_main.c"} <= written


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    import lagcli.system
    from lagcli.errors import SpecError

    target = tmp_path / "eom.txt"
    target.write_text("old\n")

    def fails(path):
        assert temporaries(tmp_path)            # the output is open while the work runs
        raise SpecError([])

    monkeypatch.setattr(lagcli.system, "load", fails)
    result = invoke("derive", spec_path("double_pendulum"), "-o", target)
    assert result.exit_code == 2
    assert target.read_text() == "old\n" and temporaries(tmp_path) == []


def test_the_plot_copy_is_bounded_even_and_ends_with_the_last_row():
    copy = Decimated(limit=10)
    copy.begin(["t", "x"])
    for start in range(0, 1000, 7):                  # blocks of rows, as the C driver's pipe gives
        copy.add_csv("".join(f"{k},{k * k}\n" for k in range(start, min(start + 7, 1000))))
    kept = [int(line.split(",")[0]) for line in copy.trajectory().lines]
    assert copy.rows == 1000 and copy.last_time == 999
    assert len(kept) <= 2 * 10 + 1 and kept[0] == 0 and kept[-1] == 999
    steps = {b - a for a, b in zip(kept[:-1], kept[1:-1])}
    assert steps == {copy.stride} and copy.stride == 64
    short = Decimated(limit=10)
    short.begin(["t"])
    for k in range(15):
        short.add_row([k])
    assert [float(v) for v in short.trajectory().lines] == list(range(15))   # short runs: every row


def test_dev_stdout_onto_a_file_appends_where_stdout_is(tmp_path):
    """`-o /dev/stdout > file`: written through this process's descriptor 1 (sharing its
    offset), so the file is neither truncated nor overwritten by later prints."""
    import subprocess
    import sys

    from conftest import ROOT

    code = ("from lagcli.render.output import write_output\nprint('before', flush=True)\n"
            "write_output('/dev/stdout', 'rows\\n')\nprint('after')\n")
    target = tmp_path / "log.txt"
    with open(target, "w") as stdout:
        done = subprocess.run([sys.executable, "-c", code], stdout=stdout, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 0
    assert target.read_text() == "before\nrows\nafter\n"


def test_a_signal_inside_an_uninterruptible_block_waits_for_its_end():
    """SIGTERM while a block of rows is written: raised once the block is whole."""
    import signal

    from lagcli.runtime.interrupts import interrupt_on_termination, uninterruptible

    done = []
    with interrupt_on_termination():
        with pytest.raises(KeyboardInterrupt, match="SIGTERM"):
            with uninterruptible:
                os.kill(os.getpid(), signal.SIGTERM)
                done.append("the rest of the block")
        with pytest.raises(KeyboardInterrupt, match="SIGHUP"):
            os.kill(os.getpid(), signal.SIGHUP)
    assert done == ["the rest of the block"]
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


def test_an_ignored_hangup_stays_ignored():
    import signal

    from lagcli.runtime.interrupts import interrupt_on_termination

    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)        # as under nohup
    try:
        with interrupt_on_termination():
            assert signal.getsignal(signal.SIGHUP) == signal.SIG_IGN
            assert signal.getsignal(signal.SIGTERM) != signal.SIG_DFL
    finally:
        signal.signal(signal.SIGHUP, previous)
