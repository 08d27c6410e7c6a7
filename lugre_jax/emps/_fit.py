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

The fit is the package's bounded least squares (:func:`lugre_jax._fit.fit`): Levenberg-Marquardt
(optimistix) on the jitted residual with a forward-mode Jacobian (a dozen parameters against ~10^4
residuals), parameters mapped to their declared bounds by a logistic transform. Standard errors
from the Gauss-Newton covariance at the optimum, ``s^2 (J^T J)^-1`` in physical units with
``s^2 = r^T r/(N - p)`` (:func:`lugre_jax._fit.covariance`: ``inf`` for a parameter on its bound
or along a direction the data do not inform): residuals of a simulation are autocorrelated, so
these are lower bounds on the true uncertainty.
"""

from __future__ import annotations

import dataclasses
import time

import jax
import jax.numpy as jnp
import numpy as np

from .. import _fit
from .._results import RESULTS, result_name
from ..io import EmpsRun
from ._idim import N_BORDER, filtered_kinematics, sample_period
from ._models import AbstractEmpsModel
from ._pulses import IGNORED, PulseEntry
from ._simulate import AbstractSubstepping, closed_loop, fit_stepping, open_loop


#: Termination of the fits: converged when an accepted step lowers the sum of squares by less than
#: ``FIT_RTOL`` of it (:class:`lugre_jax._fit.LossStop`), far below the sum's own sampling spread (at
#: least ~sqrt(2/N), 1e-2 for 10^4 residuals, more as they are autocorrelated), or when it changes
#: every unconstrained parameter and every residual by less than ``FIT_ATOL + FIT_RTOL`` times its
#: size (optimistix's Cauchy test). Under the protocol the objective has flat valleys (docs/emps.md)
#: where a test on the parameters' steps alone never ends.
FIT_RTOL, FIT_ATOL = 1e-5, 1e-8
#: Levenberg-Marquardt steps allowed per fit (the default runs converge well inside it; docs/emps.md).
FIT_MAX_STEPS = 200


@dataclasses.dataclass(frozen=True)
class FitResult:
    """A fitted model, its standard errors (name -> value, physical units; 0 for a parameter held
    fixed), the final objective ``loss`` (sum of squared residuals), the solver's steps
    (``n_steps``), wall time and the solver's ``result`` (a :class:`lugre_jax._results.RESULTS` item).
    ``status`` names it: ``"converged"``, ``"step limit"`` (stopped at ``max_steps``) or
    ``"failed"`` (any other result, or a simulation that is not finite at the estimate)."""

    model: AbstractEmpsModel
    std: dict
    loss: float
    n_steps: int
    time_s: float
    result: RESULTS
    protocol: str
    max_steps: int = FIT_MAX_STEPS
    finite: bool = True

    @property
    def status(self) -> str:
        if self.finite and self.result == RESULTS.successful:
            return "converged"
        if self.finite and self.result == RESULTS.nonlinear_max_steps_reached:
            return "step limit"
        return "failed"

    @property
    def success(self) -> bool:
        return self.status == "converged"

    @property
    def converged(self) -> bool:
        return self.success

    def to_json(self) -> dict:
        units = type(self.model).units()
        jn = type(self.model).json_names
        return {"protocol": self.protocol, "params": self.model.to_dict(), "std": dict(self.std),
                "units": {jn.get(k, k): u for k, u in units.items()}, "loss": self.loss,
                "steps": self.n_steps, "max_steps": self.max_steps, "fit_time_s": self.time_s,
                "result": result_name(self.result), "status": self.status}


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


def closed_loop_window(model, data: RunArrays, start: int, stop: int, *, pulses: PulseEntry = IGNORED,
                       stepping: AbstractSubstepping | None = None):
    """Closed-loop simulation of samples ``start:stop`` from the measured state at ``start``:
    ``(q, v, force, ok)`` with force = gtau*vir_sim. ``pulses`` says how the run's ``pulses_N``
    enters (default: not at all)."""
    r = data.run
    x0, hist = data.closed_initial(model, start)
    f, u = (a[start:stop] for a in pulses.inputs(r.pulses_N, r.gtau))
    q, v, vir, ok = closed_loop(model, r.qg[start:stop], f, x0, hist, gtau=r.gtau, kp=r.kp, kv=r.kv,
                                T=data.T, stepping=stepping, u_cmd=u)
    return q, v, r.gtau * vir, ok


def _least_squares(residual, model0: AbstractEmpsModel, max_steps: int, rtol: float, atol: float,
                   protocol: str, fixed: tuple[str, ...] = ()) -> FitResult:
    """:func:`lugre_jax._fit.fit` of ``residual(model)`` over the parameters not named in ``fixed``
    (they keep ``model0``'s values), within the declared bounds."""
    cls = type(model0)
    names_all = cls.names()
    unknown = [n for n in fixed if n not in names_all]
    if unknown:
        raise ValueError(f"fixed: {unknown} are not parameters of {cls.__name__} ({list(names_all)})")
    free = np.array([n not in fixed for n in names_all])
    free_idx = jnp.asarray(np.flatnonzero(free))
    lo, hi = cls.bounds()
    p0 = model0.vector()

    def model_of(x):
        return cls.from_vector(p0.at[free_idx].set(x))

    def raw(x):
        r = residual(model_of(x))
        return jnp.where(jnp.isfinite(r), r, 1e3)  # a failed simulation: a large, not NaN, residual

    t0 = time.perf_counter()
    fit = _fit.fit(raw, p0[free_idx], np.asarray(lo)[free], np.asarray(hi)[free], rtol=rtol, atol=atol,
                   max_steps=max_steps, jac="fwd", ftol=rtol, jac_scale=True)
    elapsed = time.perf_counter() - t0
    model = model_of(jnp.asarray(fit.params))
    r = np.asarray(residual(model))
    se = np.zeros(len(names_all))
    se[free] = fit.standard_errors
    names = [cls.json_names.get(nm, nm) for nm in names_all]
    return FitResult(model, dict(zip(names, map(float, se))), float(r @ r), fit.n_steps, elapsed, fit.result,
                     protocol, max_steps, bool(np.all(np.isfinite(r))))


def fit_closed_loop(model0: AbstractEmpsModel, data: RunArrays, start: int, stop: int, *,
                    stepping: AbstractSubstepping | None = None, max_steps: int = FIT_MAX_STEPS,
                    rtol: float = FIT_RTOL, atol: float = FIT_ATOL) -> FitResult:
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

    return _least_squares(residual, model0, max_steps, rtol, atol, "closed_loop")


def segment_starts(start: int, stop: int, n_segments: int, segment_len: int) -> np.ndarray:
    """``n_segments`` window starts spread evenly so the last window ends at ``stop``."""
    last = stop - segment_len
    if last < start:
        raise ValueError(f"segment_len {segment_len} longer than the fit window {stop - start}")
    return np.unique(np.round(np.linspace(start, last, n_segments)).astype(int))


def open_loop_segments(model, data: RunArrays, starts, segment_len: int, *, pulses: PulseEntry = IGNORED,
                       stepping: AbstractSubstepping | None = None):
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
                  stepping: AbstractSubstepping | None = None,
                  max_steps: int = FIT_MAX_STEPS, rtol: float = FIT_RTOL, atol: float = FIT_ATOL,
                  fixed: tuple[str, ...] = ()) -> FitResult:
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

    return _least_squares(residual, model0, max_steps, rtol, atol,
                          f"benchmark_truncated_{len(starts)}x{segment_len}", fixed)
