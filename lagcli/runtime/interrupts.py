"""SIGINT, SIGTERM and SIGHUP as one KeyboardInterrupt, raised only where it is safe.

`interrupt_on_termination()` (the CLI holds it while a command runs) makes the three
signals raise KeyboardInterrupt, so SIGTERM and SIGHUP end a run as Ctrl-C does: a
simulation keeps the rows computed so far, and no temporary output file is left.

Inside `with uninterruptible:` the signal waits: the KeyboardInterrupt is raised when
the block ends.  A block of rows is thus written to the output and counted whole
(even when the signal arrives inside a buffered write, which would otherwise drop
the buffer), and a temporary file is never created or renamed half-way.  Blocks are
short: nothing in them waits for anything but the local disk.

A signal set to be ignored (`nohup`), or with a handler of its own, is left alone;
outside the main thread nothing is installed.
"""
from __future__ import annotations

import contextlib
import signal
import threading

SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class _Uninterruptible:
    def __init__(self):
        self.depth, self.pending = 0, None

    def __enter__(self):
        self.depth += 1

    def __exit__(self, *exc) -> None:
        self.depth -= 1
        if self.depth == 0 and self.pending is not None:
            name, self.pending = self.pending, None
            raise KeyboardInterrupt(name)

    def handler(self, number, frame) -> None:
        name = signal.Signals(number).name
        if self.depth:
            self.pending = name
        else:
            raise KeyboardInterrupt(name)


uninterruptible = _Uninterruptible()


@contextlib.contextmanager
def interrupt_on_termination():
    """While active, SIGINT, SIGTERM and SIGHUP raise KeyboardInterrupt (deferred by
    `uninterruptible`)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    for number in SIGNALS:
        if signal.getsignal(number) in (signal.SIG_DFL, signal.default_int_handler):
            previous[number] = signal.signal(number, uninterruptible.handler)
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
