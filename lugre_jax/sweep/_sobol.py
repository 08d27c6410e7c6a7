"""Sobol' indices from Saltelli samples, in SALib's conventions, computed in JAX.

Estimators (as ``SALib.analyze.sobol``): outputs standardised (``(Y - mean)/std``), first order
Saltelli et al. 2010 ``S1_j = mean(B*(AB_j - A))/V``, total order Jansen 1999
``ST_j = mean((A - AB_j)**2)/(2V)``, second order Saltelli 2002
``S2_jk = mean(BA_j*AB_k - A*B)/V - S1_j - S1_k``, with ``V`` the variance of ``[A, B]``. Confidence
intervals: ``z(conf_level)`` times the standard deviation (ddof=1) over ``num_resamples`` bootstrap
resamples of the base points. The resample indices are drawn exactly as SALib draws them
(``numpy.random.default_rng(seed).integers(N, size=(N, num_resamples))``), so the same samples,
outputs and seed give SALib's intervals too; the resampled estimators run vectorised in JAX.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from scipy.stats import norm

from ._problem import check_problem

_EPS = float(np.finfo(float).eps)


@dataclasses.dataclass(frozen=True)
class SobolIndices:
    """Sobol' indices of one output. Arrays are NumPy; ``S2``/``S2_conf`` are ``(D, D)`` with the
    upper triangle filled and NaN elsewhere (SALib's layout), or None without second order.

    ``n_groups`` base points were used; ``n_dropped`` were dropped because one of their runs failed
    (a base point's ``D+2`` or ``2D+2`` runs are used together or not at all: the estimators pair
    ``A``, ``B`` and ``AB_j`` of the same base point, so dropping single runs would bias them).
    Behaves like SALib's result dict for reading: ``res["S1"]``, ``res.keys()``.
    """

    names: tuple[str, ...]
    S1: np.ndarray
    S1_conf: np.ndarray
    ST: np.ndarray
    ST_conf: np.ndarray
    S2: np.ndarray | None
    S2_conf: np.ndarray | None
    n_groups: int
    n_dropped: int
    conf_level: float
    num_resamples: int

    _KEYS = ("S1", "S1_conf", "ST", "ST_conf", "S2", "S2_conf")

    def keys(self):
        return [k for k in self._KEYS if getattr(self, k) is not None]

    def __getitem__(self, key: str) -> np.ndarray:
        if key not in self.keys():
            raise KeyError(key)
        return getattr(self, key)

    def __contains__(self, key) -> bool:
        return key in self.keys()

    def items(self):
        return [(k, self[k]) for k in self.keys()]

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict: SALib's keys as lists (S2's unused entries null) and the bookkeeping."""
        out: dict[str, Any] = {"names": list(self.names)}
        for k in self.keys():
            a = np.asarray(self[k], dtype=float)
            out[k] = [[None if np.isnan(x) else float(x) for x in row] for row in a] if a.ndim == 2 else a.tolist()
        out.update(n_groups=self.n_groups, n_dropped=self.n_dropped,
                   drop_rule="whole base-point groups with any failed run", conf_level=self.conf_level,
                   num_resamples=self.num_resamples)
        return out


def _first(A, AB, B, var):
    return jnp.mean(B[:, None] * (AB - A[:, None]), axis=0) / var


def _total(A, AB, B, var):
    return 0.5 * jnp.mean((A[:, None] - AB) ** 2, axis=0) / var


def _second(A, AB, BA, B, var, S1):
    V = jnp.mean(BA[:, :, None] * AB[:, None, :] - (A * B)[:, None, None], axis=0) / var
    return V - S1[:, None] - S1[None, :]


@jax.jit(static_argnames=("second",))
def _estimates(A, B, AB, BA, second: bool):
    y = jnp.concatenate([A, B])
    var = jnp.var(y)
    flat = jnp.ptp(y) <= _EPS  # a constant output has no variance to apportion: indices 0 (SALib)
    safe = jnp.where(var > _EPS, var, 1.0)
    S1 = jnp.where(flat | (var <= _EPS), 0.0, _first(A, AB, B, safe))
    ST = jnp.where(flat | (var <= _EPS), 0.0, _total(A, AB, B, safe))
    S2 = jnp.where(flat | (var <= _EPS), 0.0, _second(A, AB, BA, B, safe, S1)) if second else None
    return S1, ST, S2


@jax.jit(static_argnames=("second",))
def _bootstrap_std(A, B, AB, BA, r, second: bool):
    """Standard deviation (ddof=1) of the estimators over the resamples ``r`` (N, R) of base points."""
    def one(idx):
        return _estimates(A[idx], B[idx], AB[idx], None if BA is None else BA[idx], second)

    # One resample at a time: each gathers (N, D+2) values, so memory stays at one resample's
    # worth, and it is faster than vmapped batches of resamples (docs/sweeps.md, Performance).
    S1, ST, S2 = jax.lax.map(one, r.T)
    std = lambda x: None if x is None else jnp.std(x, axis=0, ddof=1)  # noqa: E731
    # SALib sets an interval to 0 when all resampled A and B outputs are equal.
    Ar, Br = A[r], B[r]
    flat = (jnp.maximum(Ar.max(), Br.max()) - jnp.minimum(Ar.min(), Br.min())) == 0
    return jax.tree.map(lambda s: jnp.where(flat, 0.0, s), (std(S1), std(ST), std(S2)))


def sobol_analyze(problem: dict, Y, *, seed: int, calc_second_order: bool = True, num_resamples: int = 100,
                  conf_level: float = 0.95, ok=None) -> SobolIndices:
    """Sobol' indices of outputs ``Y`` (one per row of :func:`saltelli_sample`, same
    ``calc_second_order``): ``S1``, ``ST`` and, with ``calc_second_order``, ``S2``, each with a
    ``*_conf`` half-width at ``conf_level`` from ``num_resamples`` bootstrap resamples drawn with
    ``seed`` (SALib's draw: the same seed gives SALib's intervals).

    ``ok`` (bool per row, optional) marks runs to trust; rows with ``ok`` False or a non-finite
    ``Y`` drop their whole base-point group (reported as ``n_dropped``), never NaN in the indices.
    Raises ``ValueError`` if the row count does not fit the plan or fewer than 2 groups remain.
    """
    names, _ = check_problem(problem)
    D = len(names)
    step = 2 * D + 2 if calc_second_order else D + 2
    Y = np.asarray(Y, dtype=np.float64).ravel()
    if Y.size == 0 or Y.size % step:
        raise ValueError(f"sobol_analyze: {Y.size} outputs is not a multiple of {step} = rows per base point "
                         f"for {D} names (calc_second_order={calc_second_order}); did sampling use the same setting?")
    if not 0 < conf_level < 1:
        raise ValueError(f"sobol_analyze: conf_level must be in (0, 1), got {conf_level}")
    if int(num_resamples) < 2:
        raise ValueError(f"sobol_analyze: num_resamples must be >= 2, got {num_resamples}")
    good = np.isfinite(Y) if ok is None else np.isfinite(Y) & np.asarray(ok, bool).ravel()
    groups = Y.reshape(-1, step)
    keep = good.reshape(-1, step).all(axis=1)
    n_total = groups.shape[0]
    groups = groups[keep]
    N = groups.shape[0]
    if N < 2:
        raise ValueError(f"sobol_analyze: {N} of {n_total} base points have all their runs ok; need at least 2")
    # Standardised over the rows used (as SALib does over all rows).
    used = groups.ravel()
    groups = (groups - used.mean()) / (used.std() if used.std() > 0 else 1.0)
    A, B = jnp.asarray(groups[:, 0]), jnp.asarray(groups[:, -1])
    AB = jnp.asarray(groups[:, 1:D + 1])
    BA = jnp.asarray(groups[:, D + 1:2 * D + 1]) if calc_second_order else None
    S1, ST, S2 = _estimates(A, B, AB, BA, calc_second_order)
    r = np.random.default_rng(seed).integers(N, size=(N, int(num_resamples)))
    s1c, stc, s2c = _bootstrap_std(A, B, AB, BA, jnp.asarray(r), calc_second_order)
    z = float(norm.ppf(0.5 + conf_level / 2))
    upper = np.triu(np.ones((D, D), bool), 1)
    tri = lambda m: None if m is None else np.where(upper, np.asarray(m), np.nan)  # noqa: E731
    return SobolIndices(tuple(names), np.asarray(S1), z * np.asarray(s1c), np.asarray(ST), z * np.asarray(stc),
                        tri(S2), None if s2c is None else tri(z * s2c), N, n_total - N, float(conf_level),
                        int(num_resamples))
