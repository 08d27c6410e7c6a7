"""One result enumeration for the package: :class:`RESULTS`, an ``equinox.Enumeration``.

It extends diffrax's (which extends optimistix's and lineax's), as diffrax extends optimistix's: a
code from any of those solvers is promoted into it unchanged (``RESULTS.promote(sol.result)``), so
fits, refinements and simulations report in one vocabulary. Items compare with ``==``
(``result == RESULTS.successful``), select with ``RESULTS.where(pred, a, b)``, stack under ``vmap``
and are named by :func:`result_name`. A non-finite simulation is ``RESULTS.nonfinite``.
"""

from __future__ import annotations

import diffrax
import numpy as np


class RESULTS(diffrax.RESULTS):  # pyright: ignore
    """Result codes of lugre_jax: diffrax's, optimistix's and lineax's items (``successful``,
    ``nonlinear_max_steps_reached``, ``nonfinite``, ``max_steps_reached``, ...)."""


def promote(item) -> RESULTS:
    """``item`` (a result of optimistix, diffrax, lineax or this package) as a :class:`RESULTS` item."""
    return item if item._enumeration is RESULTS else RESULTS.promote(item)


def result_codes(item) -> np.ndarray:
    """The integer indices of a (possibly batched) result item, as numpy (for storage and naming)."""
    return np.asarray(item._value)


def result_name(code) -> str:
    """Name of a result item, or of its integer index in :class:`RESULTS` (e.g. ``"successful"``)."""
    if hasattr(code, "_enumeration"):
        code = code._value
    idx = int(np.asarray(code))
    for name, item in RESULTS._name_to_item.items():
        if int(item._value) == idx:
            return name
    return f"unknown({idx})"
