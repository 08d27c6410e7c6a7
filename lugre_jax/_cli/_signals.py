"""Ctrl-C and SIGTERM for the CLI: both become exceptions in the main thread, so ``finally`` blocks and
context managers remove temporaries, then the command ends with one line and exit code 130 / 143.

Why not Python's defaults: SIGTERM's default kills the process without running any cleanup (temporary
files stay behind), and after a KeyboardInterrupt the interpreter's normal shutdown can crash (exit
139) while XLA's worker threads still run a dispatched computation whose buffers are being torn down.
:func:`hard_exit` therefore ends a process that was interrupted without interpreter shutdown, after
cleanup has run and the streams are flushed.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
from typing import Iterator

from ..io._atomic import deferred_signals as deferred_signals  # noqa: F401  (re-export)

EXIT_SIGINT = 128 + signal.SIGINT  # 130, as a shell reports a Ctrl-C'd command
EXIT_SIGTERM = 128 + signal.SIGTERM  # 143


class Terminated(BaseException):
    """Raised in the main thread by SIGTERM (a BaseException, like KeyboardInterrupt, so that
    ``except Exception`` in library code does not swallow it)."""

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(f"terminated by signal {signum}")
        self.signum = signum


def _on_term(signum, frame):
    raise Terminated(signum)


@contextlib.contextmanager
def handle_signals() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` and SIGINT raises KeyboardInterrupt; the
    previous handlers are restored afterwards (the CLI's ``main`` may run inside a test process). A
    SIGINT that the parent set to be ignored (``nohup``, background jobs) stays ignored."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield  # signal handlers can only be set from the main thread
        return
    old_term = signal.signal(signal.SIGTERM, _on_term)
    old_int = signal.getsignal(signal.SIGINT)
    if old_int is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old_term)
        if old_int is not signal.SIG_IGN and old_int is not None:
            signal.signal(signal.SIGINT, old_int)


def hard_exit(code: int) -> None:
    """Flush the standard streams and end the process now, skipping interpreter shutdown (see the
    module docstring). Only for a process the CLI owns (``main()`` called as the program)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(code)
