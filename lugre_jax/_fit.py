"""Bounded nonlinear least squares, shared by every subpackage: one solver, one covariance.

Problem: minimise ``1/2*|r(x)|^2`` over ``lower <= x <= upper`` for a residual function ``r``
(standardised residuals ``(model - data)/noise`` when the noise is known).

* Solver: ``optimistix.LevenbergMarquardt`` on unconstrained coordinates ``u`` with ``x = T(u)``
  (:class:`BoxTransform`: a sigmoid onto a finite box, a softplus onto a half-line, the identity on
  an unbounded component; :class:`LogTransform`: ``x = exp(u)`` for positive parameters whose scale
  is unknown; :class:`LogBoxTransform`: a sigmoid box, in log space where asked). Runs with
  ``throw=False``: a failure is a :class:`lugre_jax._results.RESULTS` item (optimistix's codes,
  promoted), never a NaN.
  :func:`least_squares` is jittable and vmappable. Two options for long simulations with flat
  valleys (the EMPS fits): ``ftol`` also stops when an accepted step lowers the loss by less than
  ``ftol`` of it (:class:`LossStop`, scipy's ``ftol`` test), and ``jac_scale`` scales ``u`` by the
  Jacobian's column norms at the start (scipy's ``x_scale="jac"``).
* Covariance: Gauss-Newton, ``C = s^2*(J^T J)^-1`` with ``J = dr/dx`` (forward mode: few parameters,
  many residuals) and ``s^2`` the residual variance ``|r|^2/(n - p)`` (``absolute_sigma=True``:
  ``s^2 = 1``, the residuals already carry their known noise; ``variance_floor``: ``s^2`` never below
  it; ``variance_factor``: times the long-run variance factor of correlated residuals). The
  information ``J^T J`` is inverted after scaling to unit diagonal, so parameters of very different
  magnitude do not fake ill-conditioning; a direction the data do not inform (eigenvalue
  below 1e-12 of the largest) gives its parameters an infinite variance, never a small one. A
  parameter on its bound gets ``se = inf``: the constraint, not the data, holds it there, and the
  Gauss-Newton approximation does not apply (:func:`covariance`).
* :func:`fit` does both and returns a :class:`Fit` (host-side: the covariance uses numpy).
"""

from __future__ import annotations

import abc
import dataclasses
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from ._results import RESULTS, promote, result_name  # noqa: F401  (result_name: re-exported)
from ._types import Array, Bool, Float

ResidualFn = Callable[[Float[Array, " p"]], Float[Array, " n"]]

# Eigenvalues of the unit-diagonal information below this fraction of the largest are uninformed.
EIGEN_CUTOFF = 1e-12
# Fraction of the box within which an estimate counts as on its bound.
AT_BOUND = 1e-6


class AbstractTransform(eqx.Module):
    """A bijection between the parameter domain and R^p (per component)."""

    @abc.abstractmethod
    def to_box(self, u: Float[Array, " p"]) -> Float[Array, " p"]:
        """Parameters from unconstrained coordinates."""

    @abc.abstractmethod
    def from_box(self, x: Float[Array, " p"]) -> Float[Array, " p"]:
        """Unconstrained coordinates of parameters ``x`` (a start on a bound is pulled inside)."""


class BoxTransform(AbstractTransform):
    """``[lower, upper]`` <-> R^p: ``x = lower + (upper - lower)*sigmoid(u)`` on a finite box,
    ``lower + softplus(u)`` / ``upper - softplus(-u)`` on a half-line, ``x = u`` when unbounded.
    ``from_box`` moves a point on (or numerically at) a bound ``edge`` of the range inside, because
    the inverse of a bound is infinite."""

    lower: Float[Array, " p"]
    upper: Float[Array, " p"]
    edge: float = eqx.field(static=True, default=1e-9)

    def _parts(self):
        lo, hi = self.lower, self.upper
        both = jnp.isfinite(lo) & jnp.isfinite(hi)
        lo_only = jnp.isfinite(lo) & ~jnp.isfinite(hi)
        hi_only = ~jnp.isfinite(lo) & jnp.isfinite(hi)
        lo_s = jnp.where(jnp.isfinite(lo), lo, 0.0)
        hi_s = jnp.where(jnp.isfinite(hi), hi, 1.0)
        return both, lo_only, hi_only, lo_s, hi_s

    def to_box(self, u):
        both, lo_only, hi_only, lo_s, hi_s = self._parts()
        boxed = lo_s + (hi_s - lo_s) * jax.nn.sigmoid(u)
        return jnp.where(
            both, boxed, jnp.where(lo_only, lo_s + jax.nn.softplus(u), jnp.where(hi_only, hi_s - jax.nn.softplus(-u), u))
        )

    def from_box(self, x):
        both, lo_only, hi_only, lo_s, hi_s = self._parts()
        t = jnp.clip((x - lo_s) / (hi_s - lo_s), self.edge, 1 - self.edge)
        # softplus^-1(y) = y + log(-expm1(-y)), with y kept positive
        y_lo = jnp.maximum(x - lo_s, self.edge)
        y_hi = jnp.maximum(hi_s - x, self.edge)
        inv_sp = lambda y: y + jnp.log(-jnp.expm1(-y))  # noqa: E731
        return jnp.where(
            both, jnp.log(t) - jnp.log1p(-t), jnp.where(lo_only, inv_sp(y_lo), jnp.where(hi_only, -inv_sp(y_hi), x))
        )


class LogTransform(AbstractTransform):
    """Positive parameters of unknown scale: ``x = exp(u)`` (the solver's steps are relative)."""

    def to_box(self, u):
        return jnp.exp(u)

    def from_box(self, x):
        return jnp.log(x)


class LogBoxTransform(AbstractTransform):
    """A finite box per component, in log space for the components flagged ``log``:
    ``x = exp(y)`` there and ``x = y`` elsewhere, with ``y`` from the sigmoid of
    :class:`BoxTransform` onto ``[log lower, log upper]`` (resp. ``[lower, upper]``), so a range
    spanning decades gets relative steps. Built host-side from the bounds in parameter units."""

    box: BoxTransform  # in log units for the ``log`` components
    log: Bool[Array, " p"]

    def __init__(self, lower, upper, log, edge: float = 1e-9):
        log = np.asarray(log, bool)
        lo, hi = np.asarray(lower, np.float64), np.asarray(upper, np.float64)
        with np.errstate(divide="ignore", invalid="ignore"):
            lo = np.where(log, np.log(np.maximum(lo, 1e-300)), lo)
            hi = np.where(log, np.log(hi), hi)
        self.box = BoxTransform(jnp.asarray(lo), jnp.asarray(hi), edge)
        self.log = jnp.asarray(log)

    def to_box(self, u):
        y = self.box.to_box(u)
        return jnp.where(self.log, jnp.exp(jnp.where(self.log, y, 0.0)), y)

    def from_box(self, x):
        return self.box.from_box(self._inner(x))

    def _inner(self, x):
        return jnp.where(self.log, jnp.log(jnp.maximum(x, 1e-300)), x)

    def at_bounds(self, x, tol: float = AT_BOUND) -> np.ndarray:
        """:func:`at_bounds` of ``x`` in the box's (log) units."""
        return at_bounds(self._inner(jnp.asarray(x)), self.box.lower, self.box.upper, tol)


class LossStop(optx.AbstractLeastSquaresSolver):
    """Levenberg-Marquardt (``optimistix.LevenbergMarquardt(rtol, atol)``) that also stops when an
    accepted step lowers the loss by less than ``ftol`` times it (scipy's ``ftol`` test). For
    objectives with flat valleys, where the Cauchy test on the parameters' steps does not end while
    the loss no longer changes."""

    rtol: float
    atol: float
    ftol: float
    norm: Callable = eqx.field(static=True, default=optx.max_norm)

    @property
    def _inner(self):
        return optx.LevenbergMarquardt(rtol=self.rtol, atol=self.atol, norm=self.norm)

    def init(self, fn, y, args, options, f_struct, aux_struct, tags):
        return self._inner.init(fn, y, args, options, f_struct, aux_struct, tags), jnp.array(False)

    def step(self, fn, y, args, options, state, tags):
        inner, _ = state
        y, new, aux = self._inner.step(fn, y, args, options, inner, tags)
        before = 0.5 * jnp.sum(inner.f_info.residual**2)
        after = 0.5 * jnp.sum(new.f_info.residual**2)
        # the first accepted step only evaluates the start: no decrease to judge
        judged = (new.num_accepted_steps > inner.num_accepted_steps) & (inner.num_accepted_steps >= 1)
        return y, (new, judged & (before - after <= self.ftol * before)), aux

    def terminate(self, fn, y, args, options, state, tags):
        inner, small = state
        done, result = self._inner.terminate(fn, y, args, options, inner, tags)
        return done | small, result

    def postprocess(self, fn, y, aux, args, options, state, tags, result):
        return self._inner.postprocess(fn, y, aux, args, options, state[0], tags, result)


def least_squares(residual_fn: ResidualFn, x0: Float[Array, " p"], transform: AbstractTransform, *,
                  rtol: float = 1e-10, atol: float = 1e-12, max_steps: int = 200,
                  jac: str | None = None, ftol: float | None = None,
                  jac_scale: bool = False) -> tuple[Float[Array, " p"], optx.Solution]:
    """Levenberg-Marquardt on ``u = transform.from_box(x0)``; returns ``(x, solution)`` with
    ``x = transform.to_box(solution.value)`` and the solver's ``result``/``stats``. ``jac="fwd"``
    asks optimistix for a forward-mode Jacobian (cheaper through a long ``lax.scan``); ``ftol``
    adds the loss-decrease stop of :class:`LossStop`. ``jac_scale=True`` solves in ``w = d*u`` with
    ``d`` the column norms of the Jacobian at the start, so that the solver's damping (a multiple of
    the identity) weighs every parameter by its effect on the residuals (scipy's ``x_scale="jac"``,
    from the start only); ``solution.value`` is then ``w``. Jittable."""
    u0 = transform.from_box(x0)
    if jac_scale:
        d = jnp.linalg.norm(jax.jacfwd(lambda u: residual_fn(transform.to_box(u)))(u0), axis=0)
        d = jnp.where(d > 0, d, 1.0)
    else:
        d = jnp.ones_like(u0)
    fn = lambda w, _: residual_fn(transform.to_box(w / d))  # noqa: E731
    options = {} if jac is None else dict(jac=jac)
    solver = optx.LevenbergMarquardt(rtol=rtol, atol=atol) if ftol is None else LossStop(rtol, atol, ftol)
    sol = optx.least_squares(fn, solver, u0 * d, options=options, max_steps=max_steps, throw=False)
    return transform.to_box(sol.value / d), sol


def jacobian(residual_fn: ResidualFn, x) -> np.ndarray:
    """``d residual / d x`` at ``x`` (forward mode), as a float64 numpy array of shape (n, p)."""
    return np.asarray(jax.jacfwd(residual_fn)(jnp.asarray(x, dtype=jnp.float64)))


def information_inverse(info) -> tuple[np.ndarray, float]:
    """Inverse and condition number of a symmetric information matrix ``J^T J``, scaled to unit
    diagonal first; parameters touched by an uninformed direction (eigenvalue below
    ``EIGEN_CUTOFF`` of the largest) get infinite variance and covariances."""
    info = np.asarray(info, dtype=np.float64)
    d = np.sqrt(np.clip(np.diag(info), 1e-300, None))
    scaled = info / np.outer(d, d)
    w, U = np.linalg.eigh(scaled)
    cond = float(w[-1] / w[0]) if w[0] > 0 else float("inf")
    keep = w > EIGEN_CUTOFF * w[-1]
    inv = (U[:, keep] / w[keep]) @ U[:, keep].T / np.outer(d, d)
    null_weight = np.sum(U[:, ~keep] ** 2, axis=1)
    lost = null_weight > 1e-6
    if lost.any():
        inv = inv.copy()
        inv[lost, :] = np.inf
        inv[:, lost] = np.inf
    return inv, cond


def at_bounds(x, lower, upper, tol: float = AT_BOUND) -> np.ndarray:
    """Which components of ``x`` lie within ``tol`` of their box's width from a finite bound
    (a half-line's width is taken as ``max(1, |x|)``)."""
    x, lo, hi = (np.asarray(a, dtype=np.float64) for a in (x, lower, upper))
    width = np.where(np.isfinite(hi - lo), hi - lo, np.maximum(1.0, np.abs(x)))
    tol = tol * np.maximum(width, 1e-300)
    return (np.isfinite(lo) & (x - lo < tol)) | (np.isfinite(hi) & (hi - x < tol))


@dataclasses.dataclass(frozen=True)
class Covariance:
    """Gauss-Newton covariance of a least-squares estimate (arrays ordered as the parameters)."""

    covariance: np.ndarray
    standard_errors: np.ndarray
    correlation: np.ndarray
    condition_number: float  # of the unit-diagonal information (= of the correlation matrix)
    chi2_dof: float  # |r|^2 / (n - p); NaN without degrees of freedom
    dof: int


def covariance(jac, residual, *, absolute_sigma: bool = False, variance_floor: float = 0.0,
               variance_factor: float = 1.0, at_bound=None) -> Covariance:
    """The covariance ``s^2*(J^T J)^-1`` of an estimate from its Jacobian ``jac`` (n, p) and
    residuals (n,). ``absolute_sigma=False`` (default): ``s^2 = max(variance_floor, |r|^2/dof)``;
    with ``absolute_sigma=True``: ``s^2 = 1``; either times ``variance_factor`` (the long-run
    variance factor of serially correlated residuals, 1 for white ones). ``at_bound`` (p bools,
    e.g. from :func:`at_bounds`): those parameters' standard errors are ``inf``. No degrees of
    freedom left: standard errors NaN.
    """
    J = np.asarray(jac, dtype=np.float64)
    r = np.asarray(residual, dtype=np.float64)
    p = J.shape[1]
    cov, cond = information_inverse(J.T @ J)
    dof = int(r.size - p)
    chi2_dof = float(np.sum(r**2) / dof) if dof > 0 else float("nan")
    if not absolute_sigma:
        cov = cov * (max(variance_floor, chi2_dof) if np.isfinite(chi2_dof) else np.nan)
    cov = cov * variance_factor
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    if dof <= 0:
        se = np.full_like(se, np.nan)
    if at_bound is not None:
        se = np.where(np.asarray(at_bound, bool), np.inf, se)
    d = np.sqrt(np.clip(np.diag(cov), 1e-300, None))
    with np.errstate(invalid="ignore"):
        corr = np.where(np.isfinite(np.outer(d, d)), cov / np.outer(d, d), np.nan)
    return Covariance(cov, se, corr, cond, chi2_dof, dof)


@dataclasses.dataclass(frozen=True)
class Fit:
    """A bounded least-squares estimate: ``params``, their ``standard_errors`` (``inf`` on a bound
    or along an uninformed direction), the solver's ``result`` (a :class:`lugre_jax._results.RESULTS`
    item),
    ``loss = 1/2*|r|^2`` at ``params``, the solver's ``n_steps`` and the :class:`Covariance`."""

    params: np.ndarray
    standard_errors: np.ndarray
    result: RESULTS
    loss: float
    n_steps: int
    covariance: Covariance

    @property
    def successful(self) -> bool:
        return bool(self.result == RESULTS.successful)

    def to_json(self) -> dict:
        return dict(params=self.params.tolist(), standard_errors=self.standard_errors.tolist(),
                    result=result_name(self.result), loss=self.loss, n_steps=self.n_steps,
                    chi2_per_dof=self.covariance.chi2_dof, dof=self.covariance.dof,
                    condition_number=self.covariance.condition_number)


def fit(residual_fn: ResidualFn, x0, lower=None, upper=None, *, transform: AbstractTransform | None = None,
        absolute_sigma: bool = False, variance_floor: float = 0.0, rtol: float = 1e-10, atol: float = 1e-12,
        max_steps: int = 200, jac: str | None = None, ftol: float | None = None, jac_scale: bool = False) -> Fit:
    """Fit ``residual_fn`` from ``x0`` within ``[lower, upper]`` (default unbounded) and estimate the
    covariance there (see the module doc). ``transform`` defaults to ``BoxTransform(lower, upper)``;
    pass ``LogTransform()`` for positive parameters of unknown scale. ``ftol``: also stop when an
    accepted step lowers the loss by less than ``ftol`` times it (:class:`LossStop`); ``jac_scale``:
    see :func:`least_squares`."""
    x0 = jnp.asarray(x0, dtype=jnp.float64)
    p = x0.shape[-1]
    lo = jnp.full(p, -jnp.inf) if lower is None else jnp.asarray(lower, dtype=jnp.float64)
    hi = jnp.full(p, jnp.inf) if upper is None else jnp.asarray(upper, dtype=jnp.float64)
    if transform is None:
        transform = BoxTransform(lo, hi)
        x0 = jnp.clip(x0, lo, hi)
    x, sol = least_squares(residual_fn, x0, transform, rtol=rtol, atol=atol, max_steps=max_steps, jac=jac,
                           ftol=ftol, jac_scale=jac_scale)
    x = np.asarray(x)
    r = np.asarray(residual_fn(jnp.asarray(x)))
    cov = covariance(jacobian(residual_fn, x), r, absolute_sigma=absolute_sigma, variance_floor=variance_floor,
                     at_bound=at_bounds(x, lo, hi))
    return Fit(x, cov.standard_errors, promote(sol.result), float(0.5 * np.sum(r**2)), int(sol.stats["num_steps"]),
               cov)
