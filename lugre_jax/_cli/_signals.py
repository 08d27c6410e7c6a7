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

EXIT_SIGINT = 128 + signal.SIGINT  # 130, as a shell reports a Ctrl-C'd command
EXIT_SIGTERM = 128 + signal.SIGTERM  # 143


class Terminated(BaseException):
    """Raised in the main thread by SIGTERM (a BaseException, like KeyboardInterrupt, so that
    ``except Exception`` in library code does not swallow it)."""

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(f"terminated by signal {signum}")
        self.signum = signum


# Raising from a signal handler is not always enough: when the handler happens to run inside a
# callback whose exceptions Python ignores (JAX registers a garbage-collection callback; __del__
# methods, weakref callbacks), the exception is handed to sys.unraisablehook and dropped, and the
# command would run on. Our hook sends the signal again at once (and does not print the copy); a
# slower timer covers an exception swallowed silently (a bare ``except:``). Cleanup that must not
# be cut short runs with the signals held (lugre_jax.io.deferred_signals).
_FALLBACK_RESEND_S = 2.0
_state: dict = {"caught": True, "timers": []}


def _resend_later(signum: int, after_s: float) -> None:
    import threading

    def again():
        if not _state["caught"]:
            os.kill(os.getpid(), signum)

    t = threading.Timer(after_s, again)
    t.daemon = True
    _state["timers"].append(t)
    t.start()


def _on_signal(signum, frame):
    _resend_later(signum, _FALLBACK_RESEND_S)
    if signum == signal.SIGINT:
        raise KeyboardInterrupt
    raise Terminated(signum)


def caught() -> None:
    """Called by ``main`` once the interrupt has reached it: no more re-sending."""
    _state["caught"] = True
    for t in _state["timers"]:
        t.cancel()
    _state["timers"].clear()


def _quiet_unraisable(hook):
    def unraisable(u):
        if isinstance(u.exc_value, (KeyboardInterrupt, Terminated)):
            if not _state["caught"]:  # raised where Python ignores exceptions: send it again, from
                # another thread, so that it is not handled inside this hook (which ignores it too)
                sig = signal.SIGINT if isinstance(u.exc_value, KeyboardInterrupt) else signal.SIGTERM
                _resend_later(sig, 0.02)
            return
        hook(u)

    return unraisable


@contextlib.contextmanager
def handle_signals() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` and SIGINT raises KeyboardInterrupt in the
    main thread (sent again if dropped, see above); the previous handlers are restored afterwards (the
    CLI's ``main`` may run inside a test process). A SIGINT that the parent set to be ignored
    (``nohup``, background jobs) stays ignored."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield  # signal handlers can only be set from the main thread
        return
    _state["caught"] = False
    old_term = signal.signal(signal.SIGTERM, _on_signal)
    old_int = signal.getsignal(signal.SIGINT)
    if old_int is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, _on_signal)
    old_hook = sys.unraisablehook
    sys.unraisablehook = _quiet_unraisable(old_hook)
    try:
        yield
    finally:
        caught()
        signal.signal(signal.SIGTERM, old_term)
        if old_int is not signal.SIG_IGN and old_int is not None:
            signal.signal(signal.SIGINT, old_int)
        sys.unraisablehook = old_hook


def hard_exit(code: int) -> None:
    """Flush the standard streams and end the process now, skipping interpreter shutdown (see the
    module docstring). Only for a process the CLI owns (``main()`` called as the program)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(code)
