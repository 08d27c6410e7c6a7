"""Argument helpers shared by the subcommands: the parser, help formatting, list-valued options.

This module and each subcommand's ``add_parser`` import only the standard library, so the command
line can be parsed (``--help``, argument errors, output-path checks) before JAX and the package load:
``lugre_jax_cli`` loads them on their own, and imports the package only when work starts.
"""

from __future__ import annotations

import argparse
import re
import sys
from typing import Callable

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


def build_parser(import_module: Callable[[str], object]) -> tuple[argparse.ArgumentParser, dict]:
    """The ``lugre-jax`` parser and the subcommand modules, each imported by ``import_module(name)``
    (a name of :data:`SUBCOMMANDS`' values)."""
    parser = argparse.ArgumentParser(
        prog="lugre-jax",
        description="LuGre friction: simulate, identify, reproduce the paper, diagnose recordings.\n\n"
                    "Outputs: every output path is checked before any work starts; a file is replaced "
                    "atomically; a folder must be new, empty, or an earlier result of the same command "
                    "(it holds a MANIFEST.json; sweep: the same SPEC, which resumes). --quiet silences "
                    "progress; progress bars are drawn on a terminal only, a log gets plain lines.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--no-cache", action="store_true",
                        help="do not use the persistent compilation cache (~/.cache/lugre_jax/jax)")
    sub = parser.add_subparsers(dest="command", required=True)
    modules = {}
    for name, modname in SUBCOMMANDS.items():
        mod = import_module(modname)
        mod.add_parser(sub)
        modules[name] = mod
    return parser, modules


def error_line(command: str, exc: BaseException, prefix: str | None = None) -> str:
    """The one stderr line of a failed command: ``lugre-jax CMD: error: MESSAGE`` (a message that
    spans lines, e.g. from a library, is joined)."""
    msg = " ".join(str(exc).split())
    if prefix:
        msg = f"{prefix}: {msg}" if msg else prefix
    return f"lugre-jax {command}: error: {msg or type(exc).__name__}"


class HelpFormatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    """Descriptions keep their line breaks; every option with a help text shows its default (an
    option whose default is None or False shows none: it is off unless given)."""

    def _get_help_string(self, action):
        h = action.help or ""
        # identity, not ==: a default of 0 equals False but is a value to show
        off = action.default is None or action.default is False or action.default == argparse.SUPPRESS
        if "%(default)" in h or off or not action.option_strings:
            return h
        return h + " (default: %(default)s)"


def add_quiet(p: argparse.ArgumentParser, what: str = "progress") -> None:
    """The one quiet flag of every command: ``--quiet`` (``--no-progress`` is kept as a hidden alias)."""
    p.add_argument("--quiet", action="store_true",
                   help=f"no {what} on stderr (bars on a terminal, plain lines with totals and ETA in a log)")
    p.add_argument("--no-progress", dest="quiet", action="store_true", help=argparse.SUPPRESS)


def show_progress(args) -> bool:
    """Progress is shown unless ``--quiet`` (as a bar on a terminal, as plain lines otherwise)."""
    return not getattr(args, "quiet", False)


def stderr_is_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def check_input(path, expected: str, kind: str = "file", flag: str | None = None) -> None:
    """Raise ``ValueError`` (naming the path, and ``flag`` if given) unless ``path`` exists as a file
    (``kind`` "file"), a folder ("folder") or either ("any"): a mistyped input path is answered
    before the package loads; its content is checked by the loader."""
    import os

    where = f"{flag} {path}" if flag else f"{path}"
    if not os.path.exists(path):
        raise ValueError(f"{where}: no such {'file or folder' if kind == 'any' else kind}; expected {expected}")
    if kind == "file" and os.path.isdir(path):
        raise ValueError(f"{where}: is a folder; expected {expected}")
    if kind == "folder" and not os.path.isdir(path):
        raise ValueError(f"{where}: is not a folder; expected {expected}")


_ROLE = re.compile(r":(?:func|class|meth|mod|data|attr):`~?([^`]+)`")


def plain(text: str | None) -> str:
    """A docstring as plain help text: RST roles and double backticks removed (``x`` -> x)."""
    if not text:
        return ""
    return _ROLE.sub(r"\1", text).replace("``", "")


def comma_choices(text: str, choices, flag: str) -> list[str]:
    """``"a, b"`` -> ``["a", "b"]``, each checked against ``choices``; a ValueError naming ``flag``
    and the valid choices otherwise."""
    items = [s.strip() for s in text.split(",") if s.strip()]
    bad = [s for s in items if s not in choices]
    if bad:
        raise ValueError(f"{flag}: unknown item(s) {bad}; choose from {', '.join(choices)}")
    if not items:
        raise ValueError(f"{flag}: empty list; choose from {', '.join(choices)}")
    return items
