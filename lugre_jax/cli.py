"""Command-line entry point ``lugre-jax``: thin dispatch to the subcommands in ``lugre_jax._cli``.

No science here. Each subcommand module defines ``add_parser(subparsers)``, ``run(args) -> int`` and
optionally ``check(args)``, a check of its arguments and output paths that needs neither JAX nor the
package (``lugre_jax_cli`` runs it before importing them; see ``_cli/_args.py``). A ``ValueError`` or
``OSError`` raised for bad user input becomes one line on stderr and exit code 2, without a
traceback; outputs are written atomically, so a failure leaves nothing half-written. No other error
reaches the user as a traceback either: running out of memory is one line with exit code 2, any
other unexpected error one line with exit code 1 (``LUGRE_JAX_TRACEBACK=1`` shows the traceback).
"""

from __future__ import annotations

import contextlib
import importlib
import os
import sys
import time

from ._cli._args import SUBCOMMANDS, build_parser as _build_parser, error_line

# A log (stderr not a terminal) gets one plain progress line per bar at most this often.
LOG_INTERVAL_S = 20.0


def _configure_process(no_cache: bool) -> None:
    """The CLI opts in to the library's process options: float64, the XLA options, one host device
    per core (so batches shard over both cores), and JAX's persistent compilation cache in the
    user's cache directory so a second run does not compile again (``--no-cache`` or
    ``LUGRE_JAX_NO_CACHE=1`` turns it off; ``LUGRE_JAX_CACHE_DIR`` moves it)."""
    from .xla import backend_started, configure

    if backend_started():
        # Called in a process that already ran JAX (a test, a notebook): XLA options can no longer
        # change, so only float64 is switched on.
        configure(one_kernel_loops=False, vector_width=None)
    else:
        configure(host_devices=os.cpu_count() or 1)
    if no_cache or os.environ.get("LUGRE_JAX_NO_CACHE"):
        return
    import jax

    cache = os.environ.get("LUGRE_JAX_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
        "lugre_jax", "jax")
    try:
        os.makedirs(cache, exist_ok=True)
    except OSError:
        return  # an unwritable cache directory costs speed, not correctness
    jax.config.update("jax_compilation_cache_dir", cache)
    # Cache every compilation, the small helpers' too (compile times: docs/performance.md).
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    jax.config.update("jax_persistent_cache_min_entry_size_bytes", -1)


def build_parser():
    """The parser and the subcommand modules (``lugre_jax._cli.NAME``)."""
    return _build_parser(lambda name: importlib.import_module(f"lugre_jax._cli.{name}"))


def _format_duration(s: float | None) -> str:
    if s is None or s != s or s == float("inf"):
        return "?"
    s = int(round(s))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


def _log_lines_class(interval_s: float):
    """A tqdm for logs: instead of a bar redrawn with carriage returns, one plain line (description,
    done/total, percent, elapsed, ETA) when it starts, at most every ``interval_s`` while it runs, and
    when it ends."""
    from tqdm.std import tqdm as std_tqdm

    class LogLines(std_tqdm):
        def __init__(self, *args, **kwargs):
            self._last_line_t = -float("inf")
            self._last_line_n = None
            kwargs["file"] = kwargs.get("file") or sys.stderr
            # tqdm calls display() at most every mininterval; the line rate is display's own
            kwargs["mininterval"] = min(interval_s, 1.0)
            kwargs["miniters"] = 1
            super().__init__(*args, **kwargs)

        def _line(self, force: bool) -> bool:
            now = time.monotonic()
            if not force and now - self._last_line_t < interval_s:
                return False
            if force and self._last_line_n == self.n:
                return False
            elapsed = self._time() - self.start_t if hasattr(self, "start_t") else 0.0
            total = self.total
            done = f"{self.n:,}/{total:,}" if total else f"{self.n:,}"
            pct = f" ({100.0 * self.n / total:.0f} %)" if total else ""
            rate = self.n / elapsed if elapsed > 0 and self.n > 0 else None
            eta = (total - self.n) / rate if total and rate else None
            unit = (self.unit or "").strip()
            desc = f"{self.desc}: " if self.desc else ""
            if not total:  # an open-ended count: no ETA to give
                left = ""
            else:
                left = f", ETA {_format_duration(eta) if self.n < total else '0:00'}"
            self.fp.write(f"{desc}{done}{' ' + unit if unit and unit != 'it' else ''}{pct}, elapsed "
                          f"{_format_duration(elapsed)}{left}\n")
            with contextlib.suppress(Exception):
                self.fp.flush()
            self._last_line_t, self._last_line_n = now, self.n
            return True

        def display(self, msg=None, pos=None):
            if msg == "" or self.disable:  # tqdm clearing a bar: nothing to clear in a log
                return True
            self._line(force=False)
            return True

        def clear(self, nolock=False):
            pass

        def moveto(self, n):
            pass

        def close(self):
            if getattr(self, "disable", True):
                return
            with contextlib.suppress(Exception):
                self._line(force=True)
            self.disable = True
            self._decr_instances(self)

    return LogLines


@contextlib.contextmanager
def _progress_for_logs(enabled: bool):
    """When stderr is not a terminal, the subcommands' tqdm bars (``tqdm.auto.tqdm``) print plain
    lines instead (see :func:`_log_lines_class`); restored afterwards (``main`` may run in a test)."""
    if not enabled or sys.stderr.isatty():
        yield
        return
    try:
        import tqdm.auto as auto
    except ImportError:
        yield
        return
    old = auto.tqdm
    auto.tqdm = _log_lines_class(LOG_INTERVAL_S)
    try:
        yield
    finally:
        auto.tqdm = old


def main(argv: list[str] | None = None) -> int:
    """Run one command. ``argv=None`` means this is the program (console script or ``python -m``):
    an interrupted run then ends without interpreter shutdown (see ``_cli._signals``)."""
    from ._cli._signals import EXIT_SIGINT, EXIT_SIGTERM, Terminated, caught, handle_signals, hard_exit

    is_program = argv is None
    argv = list(sys.argv[1:] if argv is None else argv)
    code = None
    command = argv_command(argv)
    with handle_signals():
        try:
            parser, modules = build_parser()
            args = parser.parse_args(argv)
            mod = modules[args.command]
            if hasattr(mod, "check"):
                mod.check(args)  # arguments and output paths, before any work
            _configure_process(args.no_cache)
            with _progress_for_logs(not getattr(args, "quiet", False)):
                return int(mod.run(args) or 0)
        except (ValueError, OSError) as e:
            print(error_line(command, e), file=sys.stderr)
            return 2
        except MemoryError as e:
            print(error_line(command, e, "out of memory (the machine's memory is too small for this input; "
                                         "reduce its size or split it)"), file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            caught()
            code = EXIT_SIGINT
        except Terminated:
            caught()
            code = EXIT_SIGTERM
        except Exception as e:  # a defect, not bad input: still one line, unless asked for the traceback
            if os.environ.get("LUGRE_JAX_TRACEBACK"):
                raise
            if "RESOURCE_EXHAUSTED" in str(e):  # XLA's out-of-memory error
                print(error_line(command, e, "out of memory (the machine's memory is too small for this input; "
                                             "reduce its size or split it)"), file=sys.stderr)
                return 2
            print(error_line(command, e, f"internal error ({type(e).__name__}); please report it with the "
                                         "command, and set LUGRE_JAX_TRACEBACK=1 for the traceback"),
                  file=sys.stderr)
            return 1
    # Reached only after an interrupt; every context manager on the way up has cleaned up.
    print(f"lugre-jax {command}: interrupted ({'Ctrl-C' if code == EXIT_SIGINT else 'SIGTERM'})",
          file=sys.stderr)
    if is_program:
        hard_exit(code)
    return code


def argv_command(argv: list[str]) -> str:
    """The subcommand named in ``argv`` (for messages raised before or while parsing)."""
    return next((a for a in argv if a in SUBCOMMANDS), "")


if __name__ == "__main__":
    sys.exit(main())
