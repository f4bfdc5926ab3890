"""Where the chunks of a sweep run: local driver processes, or a Dask cluster.

Both take chunks (a list of run lines each) and yield `(chunk index, results)` as
chunks finish, in whatever order; the caller sorts by run id, so the summary has the
same bytes whatever the number of workers or the scheduling.

- `local_chunks`: a thread per worker (default: every core), each feeding its chunk
  to its own driver process (`lagcli.sweep.driver.run_batch`); the threads only wait
  on pipes, the integration happens in the driver processes.
- `dask_chunks`: `distributed.Client(address)`; the driver's bytes are scattered to
  the workers once (broadcast), and each task stores them in the worker's own lagcli
  cache (`worker_program`: the same checked, private cache entries as a local build,
  made once per worker process) before running its chunk there. A worker that dies
  loses its tasks to the scheduler, which runs them again elsewhere; a task whose
  driver died is retried (`retries`). The workers need lagcli installed (the same
  version: the task function is `lagcli.sweep.executors.run_on_worker`) and a Linux
  (or the same platform as the client) to execute the binary; no compiler.
"""
from __future__ import annotations

import concurrent.futures
import hashlib
import os
import threading

from lagcli.errors import SimulationError, UsageError
from lagcli.sweep.driver import run_batch

DASK_RETRIES = 3
_programs: dict[str, str] = {}          # per worker process: digest -> executable path
_programs_lock = threading.Lock()


def default_workers() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def local_chunks(program: str, arguments: list[str], chunks: list[list[str]], workers: int | None):
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers or default_workers()) as pool:
        futures = {pool.submit(run_batch, program, arguments, chunk): k for k, chunk in enumerate(chunks)}
        try:
            for future in concurrent.futures.as_completed(futures):
                yield futures[future], future.result()[1]
        finally:
            for future in futures:
                future.cancel()


def dask_chunks(address: str, binary: bytes, arguments: list[str], chunks: list[list[str]]):
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise UsageError("--scheduler needs dask.distributed: pip install 'lagcli[sweep]'") from None
    try:
        client = Client(address, timeout="30s", set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise SimulationError(f"--scheduler {address}: cannot connect to the Dask scheduler ({exc})\n"
                              "  hint: start one with `dask scheduler` and workers with "
                              "`dask worker ADDRESS` (docs/sweep.md)") from None
    with client:
        shipped = client.scatter(binary, broadcast=True)
        futures = client.map(run_on_worker, [shipped] * len(chunks), [arguments] * len(chunks), chunks,
                             range(len(chunks)), retries=DASK_RETRIES, pure=False)
        try:
            for future, (index, results) in as_completed(futures, with_results=True, loop=client.loop):
                yield index, results
        finally:
            client.cancel(futures)


def run_on_worker(binary: bytes, arguments: list[str], lines: list[str], index: int):
    """A Dask task: run one chunk with the shipped driver; (chunk index, results)."""
    return index, run_batch(worker_program(binary), arguments, lines)[1]


def worker_program(binary: bytes) -> str:
    """The path to execute `binary` from, stored once per process in the lagcli cache."""
    from lagcli.run import cache

    key = hashlib.sha256(b"lagcli sweep driver\0" + binary).hexdigest()[:32]
    with _programs_lock:
        if key not in _programs:
            entry = cache.load(key, executable="sim")
            if entry is None:
                with cache.new_entry(key) as work:
                    (work / "sim").write_bytes(binary)
                    entry = cache.publish(work, key, "lagcli sweep: shipped driver", executable="sim")
            _programs[key] = entry.program
        return _programs[key]
