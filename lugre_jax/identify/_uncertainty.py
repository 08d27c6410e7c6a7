"""Uncertainty of identified static friction parameters (Li et al., Electronics 2020, 9, 284, section
4.2 reports point estimates only; we add the classical least-squares statistics).

For standardised residuals ``r_i(x) = (F(v_i; x) - tau_i) / se_i`` with independent Gaussian errors of
standard deviation ``se_i``, the Fisher information is ``I = J^T J`` with ``J = dr/dx`` (computed here
by forward-mode JAX differentiation: few parameters, many residuals). Its inverse is

* the Cramer-Rao lower bound on the covariance of any unbiased estimator when evaluated at the true
  parameters with the true noise level (:func:`crlb`), and
* the asymptotic covariance of the least-squares estimate when evaluated at the estimate
  (:func:`standard_errors`); there we multiply by ``max(1, chi2/dof)`` so that a misfit or a
  too-optimistic noise estimate widens the errors rather than being ignored.

Units: whatever the parameters' units are (N*m, deg/s, N*m*s/deg for the Stribeck set).
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from .._types import Array, Float

POOR_RELATIVE_SE = 0.20  # a parameter with SE above 20 % of its value is "poorly determined"
STRONG_CORRELATION = 0.95


def jacobian(residual_fn: Callable, x: Float[Array, " p"]) -> np.ndarray:
    """``d residual / d x`` at ``x`` (forward mode), as a float64 numpy array of shape (n, p)."""
    return np.asarray(jax.jacfwd(residual_fn)(jnp.asarray(x, dtype=jnp.float64)))


def fisher_information(residual_fn: Callable, x: Float[Array, " p"]) -> np.ndarray:
    """Fisher information ``J^T J`` of standardised residuals (unit-variance errors) at ``x``."""
    J = jacobian(residual_fn, x)
    return J.T @ J


def _inverse(info: np.ndarray) -> tuple[np.ndarray, float]:
    """Inverse and condition number of a symmetric information matrix, scaled to unit diagonal first
    so that parameters of very different magnitude do not fake ill-conditioning. Directions the data
    do not inform (eigenvalues below 1e-12 of the largest) get infinite variance, never zero."""
    d = np.sqrt(np.clip(np.diag(info), 1e-300, None))
    scaled = info / np.outer(d, d)
    w, U = np.linalg.eigh(scaled)
    cond = float(w[-1] / w[0]) if w[0] > 0 else float("inf")
    keep = w > 1e-12 * w[-1]
    inv = (U[:, keep] / w[keep]) @ U[:, keep].T / np.outer(d, d)
    null_weight = np.sum(U[:, ~keep] ** 2, axis=1)
    lost = null_weight > 1e-6
    if lost.any():
        inv = inv.copy()
        inv[lost, :] = np.inf
        inv[:, lost] = np.inf
    return inv, cond


@dataclasses.dataclass(frozen=True)
class Uncertainty:
    """Standard errors and the diagnostics behind them (arrays ordered as ``names``)."""

    names: tuple[str, ...]
    x: np.ndarray
    se: np.ndarray
    covariance: np.ndarray
    correlation: np.ndarray
    condition_number: float  # of the unit-diagonal Fisher information (= of the correlation matrix)
    chi2_dof: float  # sum of squared standardised residuals / degrees of freedom
    dof: int
    poorly_determined: tuple[str, ...]
    statement: str

    def to_json(self) -> dict:
        return dict(
            standard_errors=dict(zip(self.names, self.se.tolist())),
            relative_standard_errors={n: _rel(s, x) for n, s, x in zip(self.names, self.se, self.x)},
            correlation=self.correlation.tolist(),
            condition_number=self.condition_number,
            chi2_per_dof=self.chi2_dof,
            dof=self.dof,
            poorly_determined=list(self.poorly_determined),
            statement=self.statement,
        )


def _rel(se, x):
    return float(abs(se) / abs(x)) if x != 0 else float("inf")


def identifiability_statement(names: Sequence[str], x, se, corr, cond: float, at_bound: Sequence[str] | None = None) -> tuple[tuple[str, ...], str]:
    """Plain-language verdict: which parameters the data pin down poorly, and why."""
    poor, parts = [], []
    for n, xi, si in zip(names, x, se):
        r = _rel(si, xi)
        if not np.isfinite(si) or r > POOR_RELATIVE_SE:
            poor.append(n)
            txt = "undefined" if not np.isfinite(r) else (">1000%" if r > 10 else f"{100 * r:.0f}%")
            parts.append(f"{n} is poorly determined (relative SE {txt})")
    for n, xi in zip(names, x):
        if at_bound is not None and n in at_bound:
            parts.append(f"{n} = {xi:.4g} sits on its bound (the unconstrained optimum may lie outside the range; its SE is only indicative)")
    p = len(names)
    for i in range(p):
        for j in range(i + 1, p):
            if np.isfinite(corr[i, j]) and abs(corr[i, j]) > STRONG_CORRELATION:
                parts.append(f"{names[i]} and {names[j]} are strongly correlated (r = {corr[i, j]:+.3f}): the data constrain a combination of them")
    if not np.isfinite(cond) or cond > 1e6:
        parts.append(f"the information matrix is near-singular (condition number {cond:.2g})")
    if not parts:
        return (), f"all parameters well determined (largest relative SE {100 * max(_rel(s, v) for s, v in zip(se, x)):.1f}%, condition number {cond:.2g})"
    return tuple(poor), "; ".join(parts)


def standard_errors(
    residual_fn: Callable,
    x: Float[Array, " p"],
    names: Sequence[str],
    *,
    absolute_sigma: bool = False,
    bounds: tuple | None = None,
) -> Uncertainty:
    """Standard errors of a weighted least-squares estimate ``x`` from the Fisher information.

    ``residual_fn(x)`` must return standardised residuals ``(model - data)/se``. With
    ``absolute_sigma=False`` (default) the covariance is multiplied by ``max(1, chi2/dof)``.
    ``bounds=(lo, hi)`` lets the statement flag estimates that sit on a bound.
    """
    x = np.asarray(x, dtype=np.float64)
    J = jacobian(residual_fn, x)
    r = np.asarray(residual_fn(jnp.asarray(x)))
    info = J.T @ J
    cov, cond = _inverse(info)
    dof = int(r.size - x.size)
    chi2_dof = float(np.sum(r**2) / dof) if dof > 0 else float("nan")
    if not absolute_sigma:
        cov = cov * (max(1.0, chi2_dof) if np.isfinite(chi2_dof) else np.nan)
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    if dof <= 0:
        se = np.full_like(se, np.nan)
    d = np.sqrt(np.clip(np.diag(cov), 1e-300, None))
    with np.errstate(invalid="ignore"):
        corr = np.where(np.isfinite(np.outer(d, d)), cov / np.outer(d, d), np.nan)
    at_bound = None
    if bounds is not None:
        lo, hi = (np.asarray(b, dtype=np.float64) for b in bounds)
        tol = 1e-6 * np.maximum(hi - lo, 1e-300)
        at_bound = [n for n, xi, a, b in zip(names, x, lo, hi) if xi - a < tol[list(names).index(n)] or b - xi < tol[list(names).index(n)]]
    poor, text = identifiability_statement(names, x, se, corr, cond, at_bound)
    if dof <= 0:
        text = f"no degrees of freedom left ({r.size} data for {x.size} parameters): standard errors undefined; " + text
    return Uncertainty(tuple(names), x, se, cov, corr, cond, chi2_dof, dof, poor, text)


def crlb(model_fn: Callable, x_true, velocity, noise_se) -> np.ndarray:
    """Cramer-Rao bound (covariance matrix) for estimating ``x_true`` from observations
    ``model_fn(x, velocity) + noise`` with independent Gaussian noise of standard deviation
    ``noise_se`` (scalar or per point; for averaged data the standard error of each mean)."""
    v = jnp.asarray(velocity, dtype=jnp.float64)
    s = jnp.broadcast_to(jnp.asarray(noise_se, dtype=jnp.float64), v.shape)
    info = fisher_information(lambda x: model_fn(x, v) / s, x_true)
    inv, _ = _inverse(info)
    return inv
