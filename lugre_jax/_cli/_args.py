"""Argument helpers shared by the subcommands."""

from __future__ import annotations


def comma_choices(text: str, choices, flag: str) -> list[str]:
    """``"a, b"`` -> ``["a", "b"]``, each checked against ``choices``; a ValueError naming ``flag``
    and the valid choices otherwise."""
    items = [s.strip() for s in text.split(",") if s.strip()]
    bad = [s for s in items if s not in choices]
    if bad:
        raise ValueError(f"{flag}: unknown item(s) {bad}; choose from {', '.join(choices)}")
    return items
