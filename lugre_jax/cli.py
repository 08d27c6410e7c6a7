"""Command-line entry point ``lugre-jax``: thin dispatch to the subcommands in ``lugre_jax._cli``.

No science here. Each subcommand module defines ``add_parser(subparsers)`` and ``run(args) -> int``.
A ``ValueError``/``OSError`` raised for bad user input becomes one line on stderr and exit code 2,
without a traceback; outputs are written atomically, so a failure leaves nothing half-written.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

# subcommand name -> module under lugre_jax._cli
SUBCOMMANDS = {
    "simulate": "simulate",
    "bench": "bench",
    "identify": "identify",
    "reproduce": "reproduce",
    "diagnose": "diagnose",
    "emps": "emps",
    "sweep": "sweep",
}


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


def build_parser() -> tuple[argparse.ArgumentParser, dict]:
    parser = argparse.ArgumentParser(
        prog="lugre-jax",
        description="LuGre friction: simulate, identify, reproduce the paper, diagnose recordings.",
    )
    parser.add_argument("--no-cache", action="store_true",
                        help="do not use the persistent compilation cache (~/.cache/lugre_jax/jax)")
    sub = parser.add_subparsers(dest="command", required=True)
    modules = {}
    for name, modname in SUBCOMMANDS.items():
        try:
            mod = importlib.import_module(f"lugre_jax._cli.{modname}")
        except ModuleNotFoundError as e:
            if e.name == f"lugre_jax._cli.{modname}":
                continue  # subcommand not built yet
            raise
        mod.add_parser(sub)
        modules[name] = mod
    return parser, modules


def main(argv: list[str] | None = None) -> int:
    """Run one command. ``argv=None`` means this is the program (console script or ``python -m``):
    an interrupted run then ends without interpreter shutdown (see ``_cli._signals``)."""
    from ._cli._signals import EXIT_SIGINT, EXIT_SIGTERM, Terminated, caught, handle_signals, hard_exit

    is_program = argv is None
    argv = list(sys.argv[1:] if argv is None else argv)
    code = None
    with handle_signals():
        try:
            parser, modules = build_parser()  # imports the subcommands (and JAX): seconds, interruptible
            args = parser.parse_args(argv)
            _configure_process(args.no_cache)
            return int(modules[args.command].run(args) or 0)
        except (ValueError, OSError) as e:
            # One line: a message that spans lines (e.g. from a library) is joined.
            msg = " ".join(str(e).split()) or type(e).__name__
            print(f"lugre-jax {argv_command(argv)}: error: {msg}", file=sys.stderr)
            return 2
        except KeyboardInterrupt:
            caught()
            code = EXIT_SIGINT
        except Terminated:
            caught()
            code = EXIT_SIGTERM
    # Reached only after an interrupt; every context manager on the way up has cleaned up.
    print(f"lugre-jax {argv_command(argv)}: interrupted ({'Ctrl-C' if code == EXIT_SIGINT else 'SIGTERM'})",
          file=sys.stderr)
    if is_program:
        hard_exit(code)
    return code


def argv_command(argv: list[str]) -> str:
    """The subcommand named in ``argv`` (for messages raised before or while parsing)."""
    return next((a for a in argv if a in SUBCOMMANDS), "")


if __name__ == "__main__":
    sys.exit(main())
