"""The `lagcli` process ends without the interpreter's teardown (`lagcli.cli._end`), and
nothing of a normal exit is lost: every byte of the output arrives, exit handlers run,
the exit status is the command's, a thread still running is waited for. Its cycle
collector is off until the derivation is built (`lagcli.model.collector.for_one_command`),
and what runs after is collected as usual."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from lagcli.cli import cli

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from bench.codegen import spec_text  # noqa: E402  (the bench's chain, written once)
SPEC = ROOT / "specs" / "double_pendulum.yaml"


def python(code: str, tmp_path: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp_path / "cache")}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, env=env, timeout=600)


def lagcli(*args: str, tmp_path: Path) -> subprocess.CompletedProcess:
    return python(f"import sys; sys.argv = ['lagcli', *{list(args)!r}]\nfrom lagcli.cli import main\nmain()",
                  tmp_path)


def test_a_big_output_through_a_pipe_arrives_whole(tmp_path):
    spec = tmp_path / "chain14.yaml"
    spec.write_text(spec_text(14))
    done = lagcli("derive", "--json", str(spec), tmp_path=tmp_path)
    assert done.returncode == 0, done.stderr
    in_process = CliRunner().invoke(cli, ["derive", "--json", str(spec)])      # no process exit at all
    assert len(done.stdout) > 65536                                            # more than a pipe holds
    assert done.stdout == in_process.stdout_bytes


def test_exit_handlers_run_and_the_status_is_the_commands(tmp_path):
    marker = tmp_path / "handler ran"
    code = (f"import atexit; atexit.register(lambda: open({str(marker)!r}, 'w').close())\n"
            f"import sys; sys.argv = ['lagcli', 'check', {str(tmp_path / 'missing.yaml')!r}]\n"
            "from lagcli.cli import main\nmain()")
    done = python(code, tmp_path)
    assert done.returncode == 2 and b"cannot read the spec" in done.stderr and b"Traceback" not in done.stderr
    assert marker.exists()


def test_a_thread_still_running_is_waited_for(tmp_path):
    marker = tmp_path / "thread ended"
    code = ("import threading, time\n"
            f"threading.Thread(target=lambda: (time.sleep(1.0), open({str(marker)!r}, 'w').close())).start()\n"
            f"import sys; sys.argv = ['lagcli', 'check', {str(SPEC)!r}]\n"
            "from lagcli.cli import main\nmain()")
    done = python(code, tmp_path)
    assert done.returncode == 0, done.stderr
    assert marker.exists()


def test_an_exit_with_a_message_prints_it_with_status_1(tmp_path):
    code = ("import sys\nfrom lagcli import cli as face\n"
            "face.cli = lambda **kw: sys.exit('no such luck')\nface.main()")
    done = python(code, tmp_path)
    assert done.returncode == 1 and done.stderr.strip() == b"no such luck"


def _collector_at_exit(args: list[str], tmp_path: Path, cache: str = "cache") -> dict:
    """The cycle collector as `lagcli ARGS` leaves it: on, frozen objects, cycles left."""
    code = ("import atexit, gc, os, sys\n"
            "atexit.register(lambda: os.write(2, f'@on={gc.isenabled()} frozen={gc.get_freeze_count()} '\n"
            "                                     f'cycles={gc.collect()}@'.encode()))\n"
            f"sys.argv = ['lagcli', *{args!r}]\n"
            "from lagcli.cli import main\nmain()")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CACHE_HOME": str(tmp_path / cache)}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    found = done.stderr.decode().split("@")[1].split()
    return {key: value for key, value in (item.split("=") for item in found)}


def test_the_collector_comes_on_after_the_derivation_with_what_it_built_frozen(tmp_path):
    """`collector.for_one_command`: off from the start, on (everything alive frozen) once
    the spec's paused sections end."""
    state = _collector_at_exit(["check", str(SPEC)], tmp_path)
    assert state["on"] == "True" and int(state["frozen"]) > 10_000


def test_a_longer_run_freezes_no_more_objects(tmp_path):
    """The steps of a run happen with the collector on (scipy leaves a cycle per solver,
    one per event): ten times the bouncing ball's time and bounces freezes what the
    derivation left, no more."""
    def frozen(t_end: float) -> int:
        args = ["simulate", str(ROOT / "specs" / "hybrid" / "bouncing_ball.yaml"), "--t-end", str(t_end),
                "--backend", "python", "-o", str(tmp_path / "ball.csv")]
        state = _collector_at_exit(args, tmp_path, f"cache{t_end}")
        assert state["on"] == "True"
        return int(state["frozen"])
    short, long = frozen(2), frozen(20)
    assert abs(long - short) <= short // 100, (short, long)


def test_a_run_of_the_cached_driver_leaves_no_cycles(tmp_path):
    """A warm run reads the compiled driver's rows with the collector off all along (no
    derivation): safe while it makes no cycles, however many rows and events."""
    from lagcli.run import c_backend

    if c_backend.find_compiler() is None:
        pytest.skip("no C compiler: the cached driver needs one (cc, gcc or clang)")

    def cycles(t_end: float) -> int:
        args = ["simulate", str(ROOT / "specs" / "hybrid" / "bouncing_ball.yaml"), "--t-end", str(t_end),
                "-o", str(tmp_path / "ball.csv")]
        _collector_at_exit(args, tmp_path, "c-cache")            # builds the driver
        state = _collector_at_exit(args, tmp_path, "c-cache")    # runs the cached one
        assert state["on"] == "False"
        return int(state["cycles"])
    assert cycles(20) <= cycles(2) + 50
