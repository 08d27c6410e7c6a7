"""Sampling plans in SALib's conventions: Saltelli's cross-sampled Sobol' points, Latin hypercube,
full grid. Points come from ``scipy.stats.qmc`` (maintained, scrambled with the seed), never from a
hand-written sequence.
"""

from __future__ import annotations

import abc

import equinox as eqx
import numpy as np
from scipy.stats import qmc

from ._problem import check_problem, scale


def _is_power_of_two(n: int) -> bool:
    return n >= 1 and (n & (n - 1)) == 0


def saltelli_sample(problem: dict, N: int, *, seed: int, calc_second_order: bool = True) -> np.ndarray:
    """Saltelli's scheme (2002, 2010) on a scrambled Sobol' sequence: ``N*(D+2)`` points (``N*(2D+2)``
    with ``calc_second_order``), shape ``(rows, D)``, in the box ``problem["bounds"]``.

    Rows come in groups of ``D+2`` (or ``2D+2``), one group per base point: ``A``, ``AB_1..AB_D``
    (``A`` with column ``j`` from ``B``), [``BA_1..BA_D``], ``B``; the same layout and, for the same
    integer ``seed``, the same numbers as ``SALib.sample.sobol.sample`` (``scipy.stats.qmc.Sobol``
    of dimension ``2D``, scrambled). ``N`` must be a power of two (the balance properties of a
    Sobol' sequence hold for ``2**m`` points).
    """
    names, bounds = check_problem(problem)
    if isinstance(N, bool) or not isinstance(N, (int, np.integer)) or not _is_power_of_two(int(N)):
        raise ValueError(f"saltelli_sample: N must be a power of two (Sobol' balance), got {N!r}")
    D, N = len(names), int(N)
    base = qmc.Sobol(d=2 * D, scramble=True, seed=seed).random(N)
    A, B = base[:, :D], base[:, D:]
    eye = np.eye(D, dtype=bool)
    AB = np.where(eye[None], B[:, None, :], A[:, None, :])  # (N, D, D): row j of group i = A_i with B_ij
    blocks = [A[:, None, :], AB]
    if calc_second_order:
        blocks.append(np.where(eye[None], A[:, None, :], B[:, None, :]))
    blocks.append(B[:, None, :])
    return scale(np.concatenate(blocks, axis=1).reshape(-1, D), bounds)


def latin_hypercube(problem: dict, n: int, *, seed: int) -> np.ndarray:
    """``n`` points of a Latin hypercube (``scipy.stats.qmc.LatinHypercube``), shape ``(n, D)``."""
    names, bounds = check_problem(problem)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"latin_hypercube: n must be a positive integer, got {n!r}")
    return scale(qmc.LatinHypercube(d=len(names), seed=seed).random(int(n)), bounds)


def grid_sample(problem: dict, levels: int | list[int]) -> np.ndarray:
    """Full factorial grid, ``levels`` evenly spaced values per name including both bounds (one
    count for all, or one per name); shape ``(prod(levels), D)``, the last name varying fastest."""
    names, bounds = check_problem(problem)
    lv = [levels] * len(names) if isinstance(levels, (int, np.integer)) else list(levels)
    if len(lv) != len(names) or not all(isinstance(k, (int, np.integer)) and not isinstance(k, bool) and k >= 2 for k in lv):
        raise ValueError(f"grid_sample: levels must be an integer >= 2 or one per name ({len(names)}), got {levels!r}")
    axes = [np.linspace(lo, hi, int(k)) for (lo, hi), k in zip(bounds, lv)]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=-1)


class AbstractSampler(eqx.Module):
    """A sampling plan: ``sampler.sample(problem, n, seed) -> (rows, D)``."""

    @abc.abstractmethod
    def sample(self, problem: dict, n: int, seed: int) -> np.ndarray:
        ...

    @abc.abstractmethod
    def check_n(self, n: int, n_vars: int) -> str | None:
        """What is wrong with ``n`` for this plan (None if fine)."""


class Saltelli(AbstractSampler):
    """Sobol' indices plan: ``n`` base points (a power of two), ``n*(D+2)`` or ``n*(2D+2)`` runs."""

    calc_second_order: bool = False

    def sample(self, problem, n, seed):
        return saltelli_sample(problem, n, seed=seed, calc_second_order=self.calc_second_order)

    def check_n(self, n, n_vars):
        return None if _is_power_of_two(n) else f"expected a power of two for the sobol sampler, got {n}"

    def group_size(self, n_vars: int) -> int:
        return 2 * n_vars + 2 if self.calc_second_order else n_vars + 2


class LatinHypercube(AbstractSampler):
    """``n`` Latin hypercube points."""

    def sample(self, problem, n, seed):
        return latin_hypercube(problem, n, seed=seed)

    def check_n(self, n, n_vars):
        return None if n >= 1 else f"expected a positive number of points, got {n}"


class Grid(AbstractSampler):
    """A full grid of ``n`` levels per name (``levels`` overrides per name); ``seed`` is unused."""

    levels: tuple[int, ...] | None = None

    def sample(self, problem, n, seed):
        return grid_sample(problem, list(self.levels) if self.levels else n)

    def check_n(self, n, n_vars):
        if self.levels:
            if len(self.levels) != n_vars or not all(k >= 2 for k in self.levels):
                return f"expected {n_vars} grid levels >= 2 (one per name), got {list(self.levels)}"
            return None
        return None if n >= 2 else f"expected at least 2 grid levels per name, got {n}"
