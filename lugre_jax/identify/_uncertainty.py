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

import jax.numpy as jnp
import numpy as np

from .._fit import at_bounds, covariance, information_inverse, jacobian
from .._types import Array, Float

POOR_RELATIVE_SE = 0.20  # a parameter with SE above 20 % of its value is "poorly determined"
STRONG_CORRELATION = 0.95


def fisher_information(residual_fn: Callable, x: Float[Array, " p"]) -> np.ndarray:
    """Fisher information ``J^T J`` of standardised residuals (unit-variance errors) at ``x``."""
    J = jacobian(residual_fn, x)
    return J.T @ J


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
            parts.append(f"{n} = {xi:.4g} sits on its bound (the constraint, not the data, holds it there: no "
                         "standard error; the unconstrained optimum may lie outside the range)")
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
    ``bounds=(lo, hi)``: an estimate on a bound gets an infinite standard error and the statement
    says so (:func:`lugre_jax._fit.covariance`).
    """
    x = np.asarray(x, dtype=np.float64)
    r = np.asarray(residual_fn(jnp.asarray(x)))
    on_bound = None if bounds is None else at_bounds(x, *bounds)
    c = covariance(jacobian(residual_fn, x), r, absolute_sigma=absolute_sigma, variance_floor=1.0,
                   at_bound=on_bound)
    at_bound = None if on_bound is None else [n for n, b in zip(names, on_bound) if b]
    poor, text = identifiability_statement(names, x, c.standard_errors, c.correlation, c.condition_number, at_bound)
    if c.dof <= 0:
        text = f"no degrees of freedom left ({r.size} data for {x.size} parameters): standard errors undefined; " + text
    return Uncertainty(tuple(names), x, c.standard_errors, c.covariance, c.correlation, c.condition_number,
                       c.chi2_dof, c.dof, poor, text)


def crlb(model_fn: Callable, x_true, velocity, noise_se) -> np.ndarray:
    """Cramer-Rao bound (covariance matrix) for estimating ``x_true`` from observations
    ``model_fn(x, velocity) + noise`` with independent Gaussian noise of standard deviation
    ``noise_se`` (scalar or per point; for averaged data the standard error of each mean)."""
    v = jnp.asarray(velocity, dtype=jnp.float64)
    s = jnp.broadcast_to(jnp.asarray(noise_se, dtype=jnp.float64), v.shape)
    info = fisher_information(lambda x: model_fn(x, v) / s, x_true)
    inv, _ = information_inverse(info)
    return inv
