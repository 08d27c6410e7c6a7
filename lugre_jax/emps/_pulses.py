"""How a run's ``pulses_N`` column enters the loop, estimated from the run itself.

The column is a force [N] applied to the drive, but the recording does not say where, with which
gain, sign or delay. Two places are tested, each by a linear regression on the column lagged by
``d`` samples, ``d`` over a grid (default 0..100 ms):

* **plant** (a force on the mass the logged ``vir`` does not contain): the inverse model of the
  benchmark's IDIM-LS (asymmetric Coulomb and viscous friction, at 1 kHz) with one more column,
  ``-pulses(t - d)``, so that ``gtau*vir = M*ddq + F(dq) - g*pulses(t - d)``: ``g`` is the force
  gain (1 = the column is the force on the load at its own sign). The force and pulses columns
  are filtered as the position is on its way to ``ddq`` (:func:`matched_force`).
* **command** (added to the controller's output before ``vir`` is logged): the logged ``vir`` minus
  the controller law applied to the logged ``qm``, ``qg`` (which reproduces ``vir`` closely on the
  estimation run: docs/emps.md), regressed on ``pulses(t - d)``; the gain in V/N times ``gtau`` is the
  same force gain ``g``.

At each location the delay is the one of least squared residual. The gain's standard error is
Newey-West (Bartlett kernel, bandwidth by Andrews' 1991 AR(1) plug-in): the residuals of both
regressions are autocorrelated, so the ordinary least-squares error would be too small. A
location is *established* when its gain differs from 0 by more than the two-sided Bonferroni
quantile for all the delays and both locations tried
(family-wise error 5 %); the reported interval is the 95 % interval at the chosen delay. The delay
interval is the set of delays whose profile likelihood ratio ``n_eff*log(SSE(d)/SSE_min)`` stays
below the chi-square(1) 95 % quantile, with ``n_eff = n * (OLS variance / Newey-West variance)`` of
the gain (fewer independent samples than rows). When neither location is established the pulses
are left out of the simulations and the reason is kept in :class:`PulseEntry`; they are never fed
in at an assumed unit gain.
"""

from __future__ import annotations

import dataclasses

import equinox as eqx
import numpy as np

from .._fit import covariance
from ..io import EmpsRun
from ._idim import N_BORDER, filtered_kinematics, sample_period

PLANT, COMMAND, NONE = "plant", "command", "none"
DEFAULT_MAX_DELAY_S = 0.1


def andrews_lags(u: np.ndarray) -> int:
    """Bartlett-kernel bandwidth of Andrews (1991) with the AR(1) plug-in, for the series ``u``."""
    u = np.asarray(u, np.float64) - np.mean(u)
    den = u[:-1] @ u[:-1]
    rho = float(np.clip((u[1:] @ u[:-1]) / den, -0.99, 0.99)) if den > 0 else 0.0
    alpha = 4 * rho**2 / ((1 - rho) ** 2 * (1 + rho) ** 2)
    return max(1, int(np.ceil(1.1447 * (alpha * u.shape[0]) ** (1.0 / 3.0))))


def newey_west_cov(X: np.ndarray, e: np.ndarray, lags: int | None = None) -> np.ndarray:
    """Heteroskedasticity-and-autocorrelation-consistent covariance of OLS coefficients
    (Newey & West 1987, Bartlett weights); ``lags`` defaults to Andrews' choice for the last
    column's score ``X[:, -1]*e`` (the coefficient of interest here)."""
    if lags is None:
        lags = andrews_lags(X[:, -1] * e)
    u = X * e[:, None]
    S = u.T @ u
    for l_ in range(1, lags + 1):
        G = u[l_:].T @ u[:-l_]
        S += (1 - l_ / (lags + 1)) * (G + G.T)
    B = np.linalg.inv(X.T @ X)
    return B @ S @ B


def lagged(x: np.ndarray, d: int) -> np.ndarray:
    """``x`` delayed by ``d >= 0`` samples (zeros before the start)."""
    if d == 0:
        return np.array(x, np.float64)
    return np.concatenate([np.zeros(d), x[:-d]])


@dataclasses.dataclass(frozen=True)
class LocationFit:
    """The regression at one location: force gain ``g`` (N per N of ``pulses_N``) at the delay of
    least residual, its Newey-West standard error and 95 % interval, the delay [samples] with its
    profile-likelihood 95 % set, ``|t|``, the Bonferroni quantile it must exceed, and the share of
    the residual variance the pulses column explains at that delay."""

    location: str
    gain: float
    gain_se: float
    gain_ci95: tuple[float, float]
    delay: int
    delay_ci95: tuple[int, int]
    t_abs: float
    t_needed: float
    explained: float
    n: int
    n_eff: float
    sse_by_delay: np.ndarray = dataclasses.field(repr=False)

    @property
    def established(self) -> bool:
        return bool(np.isfinite(self.t_abs) and self.t_abs > self.t_needed)

    def to_json(self) -> dict:
        return {"location": self.location, "gain": self.gain, "gain_se": self.gain_se,
                "gain_ci95": list(self.gain_ci95), "delay_samples": self.delay,
                "delay_ci95_samples": list(self.delay_ci95), "t_abs": self.t_abs,
                "t_needed_bonferroni": self.t_needed, "established": self.established,
                "explained_share": self.explained, "n_rows": self.n, "n_eff": self.n_eff}


class PulseEntry(eqx.Module):
    """How ``pulses_N`` enters: ``location`` (``"plant"``, ``"command"`` or ``"none"``), force gain
    ``gain`` (N/N, sign included) and ``delay`` [samples]. ``none`` (not established) feeds nothing.
    Built by :func:`estimate_pulse_entry` or by hand (synthetic runs)."""

    location: str = eqx.field(static=True, default=NONE)
    gain: float = eqx.field(static=True, default=0.0)
    delay: int = eqx.field(static=True, default=0)

    def __check_init__(self):
        if self.location not in (PLANT, COMMAND, NONE):
            raise ValueError(f"PulseEntry.location must be 'plant', 'command' or 'none', got {self.location!r}")
        if int(self.delay) < 0:
            raise ValueError(f"PulseEntry.delay must be >= 0 samples, got {self.delay}")

    def inputs(self, pulses_N: np.ndarray, gtau: float) -> tuple[np.ndarray, np.ndarray]:
        """``(plant force [N], command voltage [V])`` added in the closed loop, per sample."""
        p = lagged(np.asarray(pulses_N, np.float64), int(self.delay))
        zero = np.zeros_like(p)
        if self.location == PLANT:
            return self.gain * p, zero
        if self.location == COMMAND:
            return zero, self.gain * p / gtau
        return zero, zero

    def to_json(self) -> dict:
        return {"location": self.location, "gain": self.gain, "delay_samples": int(self.delay)}


UNIT_GAIN = PulseEntry(PLANT, 1.0, 0)  # the column taken at face value: a labelled variant only
IGNORED = PulseEntry()


@dataclasses.dataclass(frozen=True)
class PulseEstimate:
    """Both locations' fits, the entry chosen (or ``none``) and why."""

    entry: PulseEntry
    fits: dict  # location -> LocationFit
    reason: str
    delays: np.ndarray = dataclasses.field(repr=False)
    T: float = 1e-3

    @property
    def established(self) -> bool:
        return self.entry.location != NONE

    def to_json(self) -> dict:
        ch = self.fits.get(self.entry.location)
        return {"established": self.established, "entry": self.entry.to_json(),
                "gain_ci95": list(ch.gain_ci95) if ch else None,
                "delay_s": self.entry.delay * self.T,
                "delay_ci95_s": [ch.delay_ci95[0] * self.T, ch.delay_ci95[1] * self.T] if ch else None,
                "reason": self.reason, "delay_grid_samples": [int(self.delays[0]), int(self.delays[-1])],
                "locations": {k: v.to_json() for k, v in self.fits.items()}}


def _profile(y: np.ndarray, base: np.ndarray, cols: list[np.ndarray], delays: np.ndarray, location: str,
             t_needed: float) -> LocationFit:
    from scipy import stats

    n = y.shape[0]
    sse = np.empty(len(delays))
    for i, c in enumerate(cols):
        X = np.column_stack([base, c]) if base.size else c[:, None]
        beta, *_ = np.linalg.lstsq(X, y, rcond=None)
        r = y - X @ beta
        sse[i] = r @ r
    i = int(np.argmin(sse))
    X = np.column_stack([base, cols[i]]) if base.size else cols[i][:, None]
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    e = y - X @ beta
    cov_nw = newey_west_cov(X, e)
    cov_ols = covariance(X, e).covariance
    g, se = float(beta[-1]), float(np.sqrt(max(cov_nw[-1, -1], 0.0)))
    n_eff = float(n * min(1.0, cov_ols[-1, -1] / max(cov_nw[-1, -1], 1e-300)))
    z = float(stats.norm.ppf(0.975))
    inside = delays[n_eff * np.log(sse / sse[i]) <= stats.chi2.ppf(0.95, 1)]
    # residual variance without the pulses column: what share the column explains
    if base.size:
        b0, *_ = np.linalg.lstsq(base, y, rcond=None)
        r0 = y - base @ b0
    else:
        r0 = y
    explained = float(1 - sse[i] / (r0 @ r0)) if r0 @ r0 > 0 else 0.0
    t_abs = abs(g) / se if se > 0 else float("inf")
    return LocationFit(location, g, se, (g - z * se, g + z * se), int(delays[i]),
                       (int(inside.min()), int(inside.max())), float(t_abs), t_needed, explained, n, n_eff, sse)


def matched_force(f: np.ndarray, T: float = 1e-3) -> np.ndarray:
    """A force held over each sample, filtered as :func:`filtered_kinematics` filters the position
    into ``ddq``: the same zero-phase Butterworth, then the kernel ``[1, 3, 3, 1]/8`` over samples
    ``k-2..k+1`` -- the two central differences of a position driven by a zero-order-held force
    average it with exactly these weights. Without it the pulses' edges, which ``ddq`` smooths and
    the raw column does not, bias the gain."""
    from scipy import signal

    from ._idim import filtfilt_matlab

    b, a = signal.butter(4, 100.0 / (0.5 / T))
    x = filtfilt_matlab(b, a, np.asarray(f, np.float64))
    y = x.copy()
    y[2:-1] = (x[:-3] + 3 * x[1:-2] + 3 * x[2:-1] + x[3:]) / 8
    return y


def controller_law(run: EmpsRun, vir_max: float = 10.0) -> np.ndarray:
    """The drive's law applied to the logged ``qm``, ``qg`` (see ``_simulate``): ``vir`` [V]."""
    T = sample_period(run)
    q = run.qm
    q2 = np.concatenate([[q[0], q[0]], q[:-2]])
    return np.clip(run.kp * run.kv * (run.qg - q) - run.kv * (q - q2) / (2 * T), -vir_max, vir_max)


def estimate_pulse_entry(run: EmpsRun, *, max_delay_s: float = DEFAULT_MAX_DELAY_S) -> PulseEstimate:
    """Estimate where, with which gain and delay ``run.pulses_N`` enters (module docstring)."""
    from scipy import stats

    T = sample_period(run)
    delays = np.arange(0, int(round(max_delay_s / T)) + 1)
    p = np.asarray(run.pulses_N, np.float64)
    if not run.has_pulses or not np.any(p != 0):
        return PulseEstimate(IGNORED, {}, "the run has no pulses_N column (or it is all zeros)", delays, T)
    # two-sided Bonferroni over every delay and both locations: family-wise 5 %
    t_needed = float(stats.norm.ppf(1 - 0.05 / (2 * 2 * len(delays))))

    # plant: the inverse model (asymmetric friction, offset) plus -pulses(t - d), at 1 kHz, every
    # force column filtered as the kinematic path filters the position (matched_force)
    _, dq, ddq = filtered_kinematics(run)
    s = slice(N_BORDER, -N_BORDER)
    dq, ddq = dq[s], ddq[s]
    sg = np.sign(dq)
    op, om = 0.5 * (1 + sg), 0.5 * (1 - sg)
    base = np.column_stack([ddq, dq * op, op, dq * om, -om])
    y = matched_force(run.force)[s]
    pm = matched_force(p)
    cols = [-lagged(pm, int(d))[s] for d in delays]
    plant = _profile(y, base, cols, delays, PLANT, t_needed)

    # command: logged vir minus the controller law, in newtons (gtau*V), at full rate
    e = run.gtau * (run.vir - controller_law(run))
    cmd = _profile(e[2:], np.empty((0,)), [lagged(p, int(d))[2:] for d in delays], delays, COMMAND, t_needed)

    fits = {PLANT: plant, COMMAND: cmd}
    est = [f for f in fits.values() if f.established]
    if not est:
        reason = ("not established: at neither location does the gain differ from 0 beyond the "
                  f"Bonferroni quantile {t_needed:.2f} (plant |t| {plant.t_abs:.2f}, command |t| "
                  f"{cmd.t_abs:.2f}); the pulses are left out of the simulations")
        return PulseEstimate(IGNORED, fits, reason, delays, T)
    best = max(est, key=lambda f: f.t_abs)
    other = [f for f in est if f is not best]
    reason = (f"established at the {best.location}: gain {best.gain:.3f} (95 % {best.gain_ci95[0]:.3f}.."
              f"{best.gain_ci95[1]:.3f}), delay {best.delay} samples ({best.delay_ci95[0]}..{best.delay_ci95[1]}), "
              f"|t| {best.t_abs:.1f} > {t_needed:.2f}")
    if other:
        reason += f"; the {other[0].location} is also significant (|t| {other[0].t_abs:.1f}), the larger |t| is used"
    return PulseEstimate(PulseEntry(best.location, best.gain, best.delay), fits, reason, delays, T)


def pulse_train(n: int, T: float, *, amplitude: float = 30.0, width_s: float = 0.1, period_s: float = 1.5,
                start_s: float = 0.5) -> np.ndarray:
    """Rectangular force pulses [N] of alternating sign: ``width_s`` long every ``period_s``."""
    t = np.arange(n) * T
    k = np.floor((t - start_s) / period_s)
    on = (t >= start_s) & ((t - start_s - k * period_s) < width_s)
    return np.where(on, amplitude * np.where(k % 2 == 0, 1.0, -1.0), 0.0)


def make_pulse_run(run: EmpsRun, model, pulses_N: np.ndarray, entry: PulseEntry, *, seed: int = 0,
                   quantum: float = 5e-8, vir_noise: float = 0.0037) -> EmpsRun:
    """A synthetic run: ``run``'s reference ``qg`` and loop gains, ``model`` simulated in closed
    loop with ``pulses_N`` entering as ``entry`` says; the logged ``qm`` is quantised to the
    encoder step ``quantum`` [m] (50 nm on EMPS) and the logged ``vir`` carries white noise of
    ``vir_noise`` V RMS (the law's mismatch on the estimation run). The returned run holds the
    nominal ``pulses_N`` column (what a user would be given)."""
    import jax.numpy as jnp

    from ._simulate import closed_loop

    T = sample_period(run)
    f, u = entry.inputs(pulses_N, run.gtau)
    x0 = jnp.array([run.qm[0], 0.0, 0.0])
    q, _, vir, ok = closed_loop(model, run.qg, f, x0, (run.qm[0], run.qm[0]), gtau=run.gtau, kp=run.kp,
                                kv=run.kv, T=T, u_cmd=u)
    if not bool(ok):
        raise ValueError("make_pulse_run: the closed-loop simulation failed (non-finite state)")
    rng = np.random.default_rng(seed)
    qm = np.round(np.asarray(q) / quantum) * quantum
    vir = np.asarray(vir) + vir_noise * rng.standard_normal(run.n)
    return EmpsRun(run.t, qm, np.asarray(run.qg), vir, np.asarray(pulses_N, np.float64), run.gtau, run.kp,
                   run.kv, True, f"synthetic({entry.location}, gain {entry.gain}, delay {entry.delay})")
