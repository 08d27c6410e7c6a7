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
}


def _maybe_enable_host_devices(argv: list[str]) -> None:
    # XLA reads this flag once, when its backend starts (first array or device query). Two host
    # devices let the batched simulator shard lanes over both cores (measured 2.2x at 10,000 lanes on
    # 2 cores; it only works if nothing started the backend at import, see tests/test_import.py).
    if "XLA_FLAGS" not in os.environ or "host_platform_device_count" not in os.environ["XLA_FLAGS"]:
        n = os.cpu_count() or 1
        os.environ["XLA_FLAGS"] = (
            os.environ.get("XLA_FLAGS", "") + f" --xla_force_host_platform_device_count={n}"
        ).strip()


def build_parser() -> tuple[argparse.ArgumentParser, dict]:
    parser = argparse.ArgumentParser(
        prog="lugre-jax",
        description="LuGre friction: simulate, identify, reproduce the paper, diagnose recordings.",
    )
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
    argv = list(sys.argv[1:] if argv is None else argv)
    _maybe_enable_host_devices(argv)
    parser, modules = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(modules[args.command].run(args) or 0)
    except (ValueError, OSError) as e:
        print(f"lugre-jax {args.command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"lugre-jax {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
