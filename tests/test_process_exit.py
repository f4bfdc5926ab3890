"""The `lagcli` process ends without the interpreter's teardown (`lagcli.cli._end`), and
nothing of a normal exit is lost: every byte of the output arrives, exit handlers run,
the exit status is the command's, a thread still running is waited for."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

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
