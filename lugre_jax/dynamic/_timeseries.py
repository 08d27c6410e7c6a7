"""Dynamic LuGre parameters (``sigma0``, ``sigma1``) from time-series recordings by gradient through
the simulator, their Fisher-information standard errors, and an excitation design that makes them
identifiable. Extends section 4.2.5 of Li et al., Electronics 2020, 9, 284, which estimates sigma0
from one pre-sliding step (eq. 17) and sigma1 from a rule of thumb (eq. 18).

* Model: a parameterised :class:`~lugre_jax.System` ``build(p)``; the recording is the joint angle
  [deg] sampled on the simulator's grid with white measurement noise of known standard deviation
  ``noise_deg``. Residuals ``r(p) = (theta_model(p) - theta_meas)/noise_deg``.
* Fit: the package's Levenberg-Marquardt (:func:`lugre_jax._fit.least_squares`) on ``log p``
  (positivity), Jacobian by forward mode (``jax.jacfwd`` / ``jac="fwd"``): for <= 10 parameters one
  forward pass per parameter is cheaper than reverse mode through a long ``lax.scan``
  (docs/performance.md, "Derivatives").
* Uncertainty: Fisher information ``F = J^T J`` of the whitened residuals at the estimate, standard
  errors ``sqrt(diag(F^-1))`` (Cramer-Rao bound for unbiased estimators); an eigenvalue of ``F`` near
  zero (relative SE >> 1) means the recording does not determine that direction.
* Design: ``log det F`` (D-optimality) of a vmapped grid of excitations evaluated at a nominal
  parameter value; the best grid point is the recommended experiment.

Units: sigma0 N*m/deg, sigma1 N*m*s/deg, angle deg, time s, torque N*m.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from .._fit import LogTransform, information_inverse, least_squares
from .._simulation import RESULT_OK, FixedStep, System, simulate


def theta_response(build: Callable[[jax.Array], System], p, duration_s: float, sample_hz: float):
    """Joint angle [deg] of ``build(p)`` on the grid ``0, 1/sample_hz, ..., duration_s`` and the
    result code (non-zero = failed)."""
    sol = simulate(build(p), duration_s, sample_hz, stepping=FixedStep())
    return sol.theta, sol.result


def fisher_information(build, p, duration_s: float, sample_hz: float, noise_deg: float):
    """``F = J^T J / noise_deg^2`` [1/unit(p)^2] with ``J = d theta / d p`` by forward mode."""
    jac = jax.jacfwd(lambda q: theta_response(build, q, duration_s, sample_hz)[0])(jnp.asarray(p, float))
    return jac.T @ jac / noise_deg**2


def standard_errors_from_fisher(F) -> np.ndarray:
    """``sqrt(diag(F^-1))``; ``inf`` for parameters along a direction the Fisher matrix does not
    inform (the package's one covariance, :func:`lugre_jax._fit.information_inverse`)."""
    inv, _ = information_inverse(F)
    return np.sqrt(np.clip(np.diag(inv), 0, None))


@dataclasses.dataclass(frozen=True)
class DynamicFit:
    """Result of :func:`fit_dynamic`: estimate, standard errors, Fisher matrix, convergence."""

    names: tuple
    p: np.ndarray
    se: np.ndarray
    fisher: np.ndarray
    rms_residual: float  # in units of noise_deg (about 1 for a good fit)
    converged: bool
    steps: int

    def as_dict(self) -> dict:
        return dict(names=list(self.names), estimate=self.p.tolist(), se=self.se.tolist(),
                    relative_se=(self.se / np.abs(self.p)).tolist(), rms_residual_over_noise=self.rms_residual,
                    converged=self.converged, steps=self.steps, log10_cond_fisher=float(np.log10(np.linalg.cond(self.fisher))))


def fit_dynamic(build, theta_meas, p0, *, duration_s: float, sample_hz: float, noise_deg: float,
                names=None, max_steps: int = 60, rtol: float = 1e-8, atol: float = 1e-8) -> DynamicFit:
    """Fit the positive parameters ``p`` of ``build(p)`` to the recording ``theta_meas`` [deg] by
    Levenberg-Marquardt on ``log p`` with forward-mode Jacobians; standard errors from the Fisher
    information at the estimate."""
    theta_meas = jnp.asarray(theta_meas, float)
    p0 = np.asarray(p0, dtype=np.float64)
    if np.any(p0 <= 0):
        raise ValueError(f"p0 must be positive (the fit works on log p), got {p0}")

    def resid(p):
        th, res = theta_response(build, p, duration_s, sample_hz)
        r = (th - theta_meas) / noise_deg
        # A failed simulation is an infinitely bad fit, never a silent NaN.
        return jnp.where(res == RESULT_OK, r, 1e10)

    x, sol = least_squares(resid, jnp.asarray(p0), LogTransform(), rtol=rtol, atol=atol, max_steps=max_steps,
                           jac="fwd")
    p = np.asarray(x)
    F = np.asarray(fisher_information(build, p, duration_s, sample_hz, noise_deg))
    r = np.asarray(resid(jnp.asarray(p)))
    return DynamicFit(tuple(names or [f"p{i}" for i in range(len(p))]), p, standard_errors_from_fisher(F), F,
                      float(np.sqrt(np.mean(r**2))), bool(sol.result == optx.RESULTS.successful),
                      int(sol.stats["num_steps"]))


def design_grid(build_exc: Callable, p_nominal, grid: np.ndarray, *, duration_s: float, sample_hz: float,
                noise_deg: float) -> dict:
    """D-optimal excitation over a grid: ``build_exc(p, e)`` builds the system for parameters ``p`` and
    excitation vector ``e`` (a row of ``grid``, e.g. amplitude [N*m] and frequency [Hz]). The Fisher
    information of every row is computed in one ``vmap`` at ``p_nominal``.

    Returns ``{"logdet": (n,), "se": (n, dim), "relative_se": (n, dim), "best": index}``.
    """
    p = jnp.asarray(p_nominal, float)
    grid = jnp.asarray(grid, float)

    def one(e):
        F = fisher_information(lambda q: build_exc(q, e), p, duration_s, sample_hz, noise_deg)
        return F

    Fs = np.asarray(jax.vmap(one)(grid))
    logdet = np.array([np.linalg.slogdet(F)[1] if np.all(np.isfinite(F)) else -np.inf for F in Fs])
    se = np.stack([standard_errors_from_fisher(F) for F in Fs])
    rel = se / np.abs(np.asarray(p))
    return dict(logdet=logdet, se=se, relative_se=rel, best=int(np.argmax(logdet)), fisher=Fs)


def with_dynamics(model, sigma0, sigma1, segment: int | None = None):
    """``model`` (LuGre or Segmented of LuGres) with ``sigma0`` [N*m/deg] and ``sigma1`` [N*m*s/deg]
    replaced (in segment ``segment``, 0-based, for a Segmented model; arrays allowed: traceable)."""
    import equinox as eqx

    from ..friction import Segmented

    if isinstance(model, Segmented):
        if segment is None:
            raise ValueError("a Segmented model needs segment=k (0-based) to say whose sigma0/sigma1 to replace")
        return eqx.tree_at(lambda m: (m.segments[segment].sigma0, m.segments[segment].sigma1), model,
                           (jnp.asarray(sigma0, float), jnp.asarray(sigma1, float)))
    return eqx.tree_at(lambda m: (m.sigma0, m.sigma1), model, (jnp.asarray(sigma0, float), jnp.asarray(sigma1, float)))


def torque_sine_system(friction, J: float, amplitude_nm, frequency_hz) -> System:
    """Open-loop torque ``amplitude_nm*sin(2*pi*frequency_hz*t)`` [N*m] on a joint at rest."""
    from ..control import OpenLoop, PositionSine
    from ..plant import Joint

    return System(friction=friction, joint=Joint(J=J), controller=OpenLoop(rate=jnp.asarray(amplitude_nm, float)),
                  reference=PositionSine(1.0, frequency_hz))
