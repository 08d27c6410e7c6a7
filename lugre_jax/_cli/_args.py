"""Argument helpers shared by the subcommands: help formatting and list-valued options."""

from __future__ import annotations

import argparse
import re


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
