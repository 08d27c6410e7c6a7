"""Output-error identification of EMPS models through the simulator, by nonlinear least squares.

Two protocols, two objectives:

* closed loop (:func:`fit_closed_loop`): the loop is driven by the recorded reference ``qg``
  through the known controller; the residual stacks the relative errors of motor force, position
  and velocity (each divided by the norm of its measured signal, so the objective is the sum of
  the squared relative errors the benchmark reports). The loop is stable: one shooting interval.
* benchmark protocol (:func:`fit_open_loop`): driven by ``vir`` alone, a free mass drifts, so the
  simulation error is truncated: ``n_segments`` windows of ``segment_len`` samples, each started
  from the filtered measured state (position, velocity; LuGre's bristles in steady sliding),
  vmapped; residual = simulated minus measured position. The protocol scores a long free run, so
  few long windows (default 4 tiling the data) fit it better than many short ones.

Parameters are mapped to their declared bounds by a logistic transform; the fit is scipy's
trust-region ``least_squares`` (``trf``, Jacobian-scaled steps) on the jitted residual and its
forward-mode Jacobian (a dozen parameters against ~10^4 residuals).
Standard errors from the Fisher information at the optimum, ``s^2 (J^T J)^-1`` in physical units
with ``s^2 = r^T r/(N - p)``: residuals of a simulation are autocorrelated, so these are lower
bounds on the true uncertainty.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np
from scipy.optimize import least_squares

from ..io import EmpsRun
from ._idim import N_BORDER, filtered_kinematics, sample_period
from ._models import AbstractEmpsModel
from ._pulses import IGNORED, PulseEntry
from ._simulate import AbstractStepping, closed_loop, fit_stepping, open_loop


#: Termination of the fits (scipy's ``least_squares``): ``rtol`` is its ``ftol``, converged when a
#: step lowers the sum of squares by less than 1e-5 of it, far below the sum's own sampling spread
#: (at least ~sqrt(2/N), 1e-2 for 10^4 residuals, more as they are autocorrelated); ``atol`` its
#: ``xtol`` and ``gtol``. Under the protocol the objective has flat valleys (docs/emps.md) where a
#: step test on the parameters never ends.
FIT_RTOL, FIT_ATOL = 1e-5, 1e-8
#: Residual evaluations allowed per fit (the default runs converge well inside it; docs/emps.md).
FIT_MAX_STEPS = 200


@dataclasses.dataclass(frozen=True)
class FitResult:
    """A fitted model, its standard errors (name -> value, physical units), the final objective
    (sum of squared residuals), residual evaluations (``n_steps``), wall time, whether the solver
    converged and why not:
    ``status`` is ``"converged"``, ``"step limit"`` (stopped at ``max_steps``) or ``"failed"``."""

    model: AbstractEmpsModel
    std: dict
    loss: float
    n_steps: int
    time_s: float
    success: bool
    protocol: str
    status: str = "converged"
    max_steps: int = FIT_MAX_STEPS

    @property
    def converged(self) -> bool:
        return self.status == "converged"

    def to_json(self) -> dict:
        units = type(self.model).units()
        jn = type(self.model).json_names
        return {"protocol": self.protocol, "params": self.model.to_dict(), "std": dict(self.std),
                "units": {jn.get(k, k): u for k, u in units.items()}, "loss": self.loss,
                "evaluations": self.n_steps, "max_evaluations": self.max_steps, "fit_time_s": self.time_s,
                "success": self.success, "status": self.status}


class RunArrays:
    """The arrays a fit or a score needs from one run, computed once (numpy, full rate)."""

    def __init__(self, run: EmpsRun):
        self.run = run
        self.T = sample_period(run)
        self.q_f, self.dq_f, _ = filtered_kinematics(run)
        self.force = run.force

    def closed_initial(self, model: AbstractEmpsModel, k: int):
        """State at sample ``k`` from the measurement and the 2-tap filter's history."""
        r, T = self.run, self.T
        v0 = float(self.dq_f[k])
        x0 = jnp.array([r.qm[k], v0, 0.0]).at[2].set(model.z_sliding(v0))
        if k >= 2:
            hist = (float(r.qm[k - 1]), float(r.qm[k - 2]))
        else:  # before the recording: extrapolated at the filtered velocity
            hist = (float(r.qm[k] - T * v0), float(r.qm[k] - 2 * T * v0))
        return x0, hist


def _to_params(theta, lo, hi):
    return lo + (hi - lo) * jax.nn.sigmoid(theta)


def _to_theta(p, lo, hi):
    u = np.clip((np.asarray(p) - lo) / (hi - lo), 1e-6, 1 - 1e-6)
    return np.log(u) - np.log1p(-u)


def closed_loop_window(model, data: RunArrays, start: int, stop: int, *, pulses: PulseEntry = IGNORED,
                       stepping: AbstractStepping | None = None):
    """Closed-loop simulation of samples ``start:stop`` from the measured state at ``start``:
    ``(q, v, force, ok)`` with force = gtau*vir_sim. ``pulses`` says how the run's ``pulses_N``
    enters (default: not at all)."""
    r = data.run
    x0, hist = data.closed_initial(model, start)
    f, u = (a[start:stop] for a in pulses.inputs(r.pulses_N, r.gtau))
    q, v, vir, ok = closed_loop(model, r.qg[start:stop], f, x0, hist, gtau=r.gtau, kp=r.kp, kv=r.kv,
                                T=data.T, stepping=stepping, u_cmd=u)
    return q, v, r.gtau * vir, ok


def _lm(residual, model0: AbstractEmpsModel, max_steps: int, rtol: float, atol: float,
        progress: Callable[[int], None] | None, fixed: tuple[str, ...] = ()):
    cls = type(model0)
    names_all = cls.names()
    unknown = [n for n in fixed if n not in names_all]
    if unknown:
        raise ValueError(f"fixed: {unknown} are not parameters of {cls.__name__} ({list(names_all)})")
    free = np.array([n not in fixed for n in names_all])
    lo, hi = (jnp.asarray(b) for b in cls.bounds())
    full0 = _to_theta(np.asarray(model0.vector()), np.asarray(lo), np.asarray(hi))
    theta0 = full0[free]
    free_idx = jnp.asarray(np.flatnonzero(free))

    def full(theta):
        return jnp.asarray(full0).at[free_idx].set(theta)

    def raw(theta):
        r = residual(cls.from_vector(_to_params(full(theta), lo, hi)))
        return jnp.where(jnp.isfinite(r), r, 1e3)  # a failed simulation: a large, not NaN, residual

    f, jac = jax.jit(raw), jax.jit(jax.jacfwd(raw))

    def fun(th):
        if progress is not None:
            progress(1)
        return np.asarray(f(jnp.asarray(th)))

    t0 = time.perf_counter()
    sol = least_squares(fun, theta0, jac=lambda th: np.asarray(jac(jnp.asarray(th))), method="trf",
                        x_scale="jac", ftol=rtol, xtol=atol, gtol=atol, max_nfev=max_steps)
    theta = full(jnp.asarray(sol.x))
    elapsed = time.perf_counter() - t0
    p = _to_params(theta, lo, hi)
    model = cls.from_vector(p)
    # Fisher information in the free physical parameters, at the optimum (fixed ones: SE 0).
    J = jax.jacfwd(lambda pp: residual(cls.from_vector(pp)))(p)[:, free_idx]
    r = residual(model)
    n, k = J.shape
    s2 = float(r @ r) / max(n - k, 1)
    se = np.zeros(len(names_all))
    try:
        cov = s2 * np.linalg.inv(np.asarray(J.T @ J))
        se[free] = np.sqrt(np.clip(np.diag(cov), 0, None))
    except np.linalg.LinAlgError:
        se[free] = np.inf
    names = [cls.json_names.get(nm, nm) for nm in names_all]
    finite = bool(np.all(np.isfinite(np.asarray(r))))
    ok = sol.status > 0 and finite
    n_steps = int(sol.nfev)
    status = "converged" if ok else "step limit" if (sol.status == 0 and finite) else "failed"
    return (model, dict(zip(names, map(float, se))), float(r @ r), n_steps, elapsed, ok, status, max_steps)


def fit_closed_loop(model0: AbstractEmpsModel, data: RunArrays, start: int, stop: int, *,
                    stepping: AbstractStepping | None = None, max_steps: int = FIT_MAX_STEPS,
                    rtol: float = FIT_RTOL, atol: float = FIT_ATOL,
                    progress: Callable[[int], None] | None = None) -> FitResult:
    """Fit ``model0``'s parameters to samples ``start:stop`` in closed loop (module docstring)."""
    stepping = fit_stepping(model0) if stepping is None else stepping
    s = slice(max(start, N_BORDER) - start, None)
    F = jnp.asarray(data.force[start:stop][s])
    Q = jnp.asarray(data.q_f[start:stop][s])
    V = jnp.asarray(data.dq_f[start:stop][s])
    nF, nQ, nV = (float(jnp.linalg.norm(a)) for a in (F, Q, V))

    def residual(model):
        q, v, f, _ = closed_loop_window(model, data, start, stop, stepping=stepping)
        return jnp.concatenate([(f[s] - F) / nF, (q[s] - Q) / nQ, (v[s] - V) / nV])

    model, se, loss, n, el, ok, status, ms = _lm(residual, model0, max_steps, rtol, atol, progress)
    return FitResult(model, se, loss, n, el, ok, "closed_loop", status, ms)


def segment_starts(start: int, stop: int, n_segments: int, segment_len: int) -> np.ndarray:
    """``n_segments`` window starts spread evenly so the last window ends at ``stop``."""
    last = stop - segment_len
    if last < start:
        raise ValueError(f"segment_len {segment_len} longer than the fit window {stop - start}")
    return np.unique(np.round(np.linspace(start, last, n_segments)).astype(int))


def open_loop_segments(model, data: RunArrays, starts, segment_len: int, *, pulses: PulseEntry = IGNORED,
                       stepping: AbstractStepping | None = None):
    """Open-loop (vir-driven) simulations of ``segment_len`` samples from each start, vmapped:
    ``(q, ok)`` of shape (n_segments, segment_len). Pulses entering at the plant are added as a
    force; at the command they are already in the logged ``vir``."""
    r = data.run
    idx = np.asarray(starts)[:, None] + np.arange(segment_len)[None, :]
    vir = jnp.asarray(r.vir[idx])
    f = jnp.asarray(pulses.inputs(r.pulses_N, r.gtau)[0][idx])
    v0 = jnp.asarray(data.dq_f[starts])
    x0 = jnp.stack([jnp.asarray(r.qm[starts]), v0, model.z_sliding(v0)], -1)

    def one(x0_, vir_, f_):
        q, _, ok = open_loop(model, vir_, f_, x0_, gtau=r.gtau, T=data.T, stepping=stepping)
        return q, ok

    return jax.vmap(one)(x0, vir, f)


def fit_open_loop(model0: AbstractEmpsModel, data: RunArrays, start: int, stop: int, *,
                  n_segments: int = 4, segment_len: int | None = None,
                  stepping: AbstractStepping | None = None,
                  max_steps: int = FIT_MAX_STEPS, rtol: float = FIT_RTOL, atol: float = FIT_ATOL,
                  progress: Callable[[int], None] | None = None, fixed: tuple[str, ...] = ()) -> FitResult:
    """Truncated-simulation-error fit for the benchmark protocol (module docstring); residual in mm.
    ``segment_len`` defaults to tiling ``start:stop`` with the ``n_segments`` windows; parameters
    named in ``fixed`` keep ``model0``'s values."""
    if segment_len is None:
        segment_len = (stop - start) // n_segments
    stepping = fit_stepping(model0) if stepping is None else stepping
    starts = segment_starts(start, stop, n_segments, segment_len)
    idx = starts[:, None] + np.arange(segment_len)[None, :]
    Y = jnp.asarray(data.run.qm[idx])

    def residual(model):
        q, _ = open_loop_segments(model, data, starts, segment_len, stepping=stepping)
        return 1e3 * (q - Y).ravel()

    model, se, loss, n, el, ok, status, ms = _lm(residual, model0, max_steps, rtol, atol, progress, fixed)
    return FitResult(model, se, loss, n, el, ok, f"benchmark_truncated_{len(starts)}x{segment_len}", status, ms)
