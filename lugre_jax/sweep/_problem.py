"""SALib's ``problem`` dict, checked once: ``{"num_vars": D, "names": [...], "bounds": [[lo, hi], ...]}``."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def check_problem(problem: Any, where: str = "problem") -> tuple[list[str], np.ndarray]:
    """``(names, bounds (D, 2))`` of a SALib problem dict; a ``ValueError`` naming the key otherwise.

    ``num_vars`` is optional (SALib fills it in); when given it must equal ``len(names)``. Every
    bound must be finite with ``lo < hi``. SALib's ``groups`` and ``dists`` are not supported.
    """
    if not isinstance(problem, dict):
        raise ValueError(f"{where}: expected an object with 'names' and 'bounds', got {type(problem).__name__}")
    # SALib itself adds "sample_scaled" (and reads "outputs"); groups and non-uniform dists are not
    # supported here, so they are refused rather than ignored.
    extra = sorted(k for k in set(problem) - {"num_vars", "names", "bounds", "outputs", "sample_scaled"}
                   if not (k in ("groups", "dists") and problem[k] is None))
    if extra:
        raise ValueError(f"{where}: unsupported key '{extra[0]}' (expected num_vars, names, bounds)")
    names = problem.get("names")
    if not isinstance(names, (list, tuple)) or not names or not all(isinstance(n, str) and n for n in names):
        raise ValueError(f"{where}.names: expected a non-empty list of strings, got {names!r}")
    if len(set(names)) != len(names):
        dup = next(n for n in names if list(names).count(n) > 1)
        raise ValueError(f"{where}.names: '{dup}' appears twice")
    if "num_vars" in problem and problem["num_vars"] != len(names):
        raise ValueError(f"{where}.num_vars: {problem['num_vars']!r} but names has {len(names)} entries")
    bounds = problem.get("bounds")
    if not isinstance(bounds, (list, tuple, np.ndarray)) or len(bounds) != len(names):
        raise ValueError(f"{where}.bounds: expected {len(names)} pairs [lo, hi] (one per name)")
    out = np.empty((len(names), 2))
    for i, b in enumerate(bounds):
        ok = (isinstance(b, (list, tuple, np.ndarray)) and len(b) == 2
              and all(isinstance(x, (int, float, np.number)) and not isinstance(x, bool) and math.isfinite(x) for x in b))
        if not ok:
            raise ValueError(f"{where}.bounds[{i}] ({names[i]}): expected [lo, hi] of two finite numbers, got {b!r}")
        if not b[0] < b[1]:
            raise ValueError(f"{where}.bounds[{i}] ({names[i]}): expected lo < hi, got [{b[0]}, {b[1]}]")
        out[i] = b
    return list(names), out


def scale(unit: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """Points of the unit cube (n, D) -> the box ``bounds`` (D, 2), as SALib's ``scale_samples``."""
    return unit * (bounds[:, 1] - bounds[:, 0]) + bounds[:, 0]
