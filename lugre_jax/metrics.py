"""Low-velocity performance metrics for the experiments of Li et al., Electronics 2020, 9, 284,
sections 5-6 (Figs. 8-10, 12-15): dead zone, creep, the +-0.001 deg/s error band of section 6.3, and
position-tracking error.

All functions take sampled trajectories as NumPy-compatible arrays whose *last* axis is time (so a
batch of lanes, shape ``(n_lanes, n_samples)``, gives one value per lane). Units: time in s, angle in
deg, velocity in deg/s.

Definitions (stated once, used everywhere):

* **Dead zone** :func:`dead_zone_lag`: the horizontal distance between the ideal ramp
  ``v_cmd*(t - t_cmd)`` and the joint's position curve, ``D(t) = (theta_ref(t) - theta(t))/v_cmd``,
  averaged over the last part of the record. A joint that stands still for ``D`` seconds and then
  follows the ramp exactly (the paper's picture of a "2 s dead zone", Fig. 9c) gives exactly ``D``;
  so does a joint whose controller holds a constant position lag (a PI velocity loop must build the
  uncompensated friction torque in its integrator: lag = residual friction / ki).
* **Onset** :func:`dead_zone_onset`: from the command until the joint's velocity, averaged over a
  window of ``hold_s``, first reaches ``frac`` (default 50%) of the command.
* **Creep amplitude** :func:`creep_amplitude`: peak-to-peak of the linearly detrended position error
  over a window (stick-slip "steps" on top of the ramp) [deg].
* **Band fraction** :func:`band_fraction`: fraction of samples with ``|omega - v_cmd| <= band`` (the
  paper's specification: 0.005 deg/s held within +-0.001 deg/s).
* **Cone fraction** :func:`cone_fraction`: the same band drawn on the position plot as in the
  paper's Fig. 13 (boundary lines ``(v_cmd +- band)*t``): fraction of samples inside the cone.
* **Tracking error** :func:`tracking_errors`: RMS and maximum absolute ``theta_ref - theta`` [deg].
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "band_fraction",
    "cone_fraction",
    "creep_amplitude",
    "dead_zone_lag",
    "dead_zone_onset",
    "tracking_errors",
    "velocity_ripple",
    "window_mask",
]


def window_mask(t, t_from: float | None = None, t_to: float | None = None) -> np.ndarray:
    """Boolean mask of samples with ``t_from <= t <= t_to`` (either bound may be None) [s]."""
    t = np.asarray(t, dtype=np.float64)
    m = np.ones(t.shape, dtype=bool)
    if t_from is not None:
        m &= t >= t_from - 1e-12
    if t_to is not None:
        m &= t <= t_to + 1e-12
    if not m.any():
        raise ValueError(f"window [{t_from}, {t_to}] s holds no samples of a record spanning "
                         f"[{t.min() if t.size else 'empty'}, {t.max() if t.size else 'empty'}] s")
    return m


def _check_v(v_cmd: float) -> float:
    v_cmd = float(v_cmd)
    if not (np.isfinite(v_cmd) and v_cmd != 0.0):
        raise ValueError(f"v_cmd must be a non-zero commanded velocity in deg/s, got {v_cmd!r}")
    return v_cmd


def dead_zone_lag(t, theta, v_cmd: float, *, t_cmd: float = 0.0, last_frac: float = 0.25,
                  t_from: float | None = None) -> np.ndarray:
    """Dead zone [s]: mean horizontal lag ``(v_cmd*(t - t_cmd) - theta)/v_cmd`` of the position curve
    behind the ideal ramp, averaged over ``t >= t_from`` (default: the last ``last_frac`` of the record).

    ``t`` [s] shape ``(n,)``; ``theta`` [deg] shape ``(..., n)`` (relative to the position at the
    command); ``v_cmd`` [deg/s]. Returns shape ``(...)``. Negative values mean the joint is ahead.
    """
    v_cmd = _check_v(v_cmd)
    t = np.asarray(t, dtype=np.float64)
    theta = np.asarray(theta, dtype=np.float64)
    if t_from is None:
        t_from = t[-1] - last_frac * (t[-1] - t_cmd)
    m = window_mask(t, max(t_from, t_cmd), None)
    lag = (v_cmd * (t - t_cmd) - theta) / v_cmd
    return lag[..., m].mean(axis=-1)


def dead_zone_onset(t, theta, v_cmd: float, *, t_cmd: float = 0.0, frac: float = 0.5,
                    hold_s: float = 0.5) -> np.ndarray:
    """Onset [s]: first time after ``t_cmd`` at which the joint's mean velocity over the next
    ``hold_s`` seconds reaches ``frac*v_cmd``, minus ``t_cmd``; ``inf`` if it never does.

    ``t`` [s] shape ``(n,)`` evenly sampled; ``theta`` [deg] shape ``(..., n)``; ``v_cmd`` [deg/s].
    The window average (position difference / hold_s) is what an encoder reading gives and ignores
    sub-window jitter.
    """
    v_cmd = _check_v(v_cmd)
    if not 0 < frac <= 1:
        raise ValueError(f"frac must be in (0, 1], got {frac}")
    t = np.asarray(t, dtype=np.float64)
    theta = np.asarray(theta, dtype=np.float64)
    dt = float(np.median(np.diff(t)))
    k = max(1, int(round(hold_s / dt)))
    if k >= t.size:
        raise ValueError(f"hold_s={hold_s} s is longer than the record ({t[-1] - t[0]} s)")
    vbar = (theta[..., k:] - theta[..., :-k]) / (t[k:] - t[:-k])
    ok = (vbar * np.sign(v_cmd) >= frac * abs(v_cmd)) & (t[:-k] >= t_cmd - 1e-12)
    first = np.argmax(ok, axis=-1)
    found = ok.any(axis=-1)
    return np.where(found, t[:-k][first] - t_cmd, np.inf)


def creep_amplitude(t, theta, theta_ref, *, t_from: float | None = None, t_to: float | None = None) -> np.ndarray:
    """Creep amplitude [deg]: peak-to-peak of the position error ``theta - theta_ref`` after removing
    its least-squares straight line over the window ``[t_from, t_to]`` [s].

    Detrending removes a constant lag and a slow drift so only the stick-slip steps remain. Shapes:
    ``t`` ``(n,)``, ``theta`` and ``theta_ref`` ``(..., n)`` [deg]; returns ``(...)``.
    """
    t = np.asarray(t, dtype=np.float64)
    m = window_mask(t, t_from, t_to)
    e = (np.asarray(theta, dtype=np.float64) - np.asarray(theta_ref, dtype=np.float64))[..., m]
    tw = t[m]
    A = np.stack([np.ones_like(tw), tw - tw.mean()], axis=1)
    coef, *_ = np.linalg.lstsq(A, np.moveaxis(e.reshape(-1, tw.size), -1, 0), rcond=None)
    resid = e.reshape(-1, tw.size) - (A @ coef).T
    return np.ptp(resid, axis=-1).reshape(e.shape[:-1])


def velocity_ripple(t, omega, v_cmd: float, *, t_from: float | None = None, t_to: float | None = None) -> np.ndarray:
    """RMS of ``omega - v_cmd`` over the window, relative to ``|v_cmd|`` (dimensionless)."""
    v_cmd = _check_v(v_cmd)
    m = window_mask(t, t_from, t_to)
    d = np.asarray(omega, dtype=np.float64)[..., m] - v_cmd
    return np.sqrt(np.mean(d**2, axis=-1)) / abs(v_cmd)


def band_fraction(t, omega, v_cmd: float, band: float = 0.001, *, t_from: float | None = None,
                  t_to: float | None = None) -> np.ndarray:
    """Fraction (0..1) of samples in ``[t_from, t_to]`` [s] with ``|omega - v_cmd| <= band``.

    ``omega`` [deg/s] shape ``(..., n)``; ``v_cmd`` and ``band`` [deg/s]. The paper's specification
    (section 6.3) is ``v_cmd = 0.005``, ``band = 0.001``.
    """
    if not band > 0:
        raise ValueError(f"band must be a positive velocity in deg/s, got {band!r}")
    v_cmd = _check_v(v_cmd)
    m = window_mask(t, t_from, t_to)
    d = np.abs(np.asarray(omega, dtype=np.float64)[..., m] - v_cmd)
    return np.mean(d <= band, axis=-1)


def cone_fraction(t, theta, v_cmd: float, band: float = 0.001, *, t_cmd: float = 0.0,
                  t_from: float | None = None, t_to: float | None = None) -> np.ndarray:
    """Fraction (0..1) of samples in ``[t_from, t_to]`` [s] whose position [deg] lies between the
    paper's error boundary curves ``(v_cmd - band)*(t - t_cmd)`` and ``(v_cmd + band)*(t - t_cmd)``
    (Fig. 13, lines 3 and 4). ``v_cmd``, ``band`` in deg/s; samples before the command are skipped.
    A joint with a dead zone ``D`` enters the cone at ``t = v_cmd*D/band``."""
    if not band > 0:
        raise ValueError(f"band must be a positive velocity in deg/s, got {band!r}")
    v_cmd = _check_v(v_cmd)
    t = np.asarray(t, dtype=np.float64)
    m = window_mask(t, t_cmd if t_from is None else max(t_from, t_cmd), t_to) & (t > t_cmd)
    tau = t[m] - t_cmd
    th = np.asarray(theta, dtype=np.float64)[..., m]
    lo, hi = np.sort(np.stack([(v_cmd - band) * tau, (v_cmd + band) * tau]), axis=0)
    return np.mean((th >= lo - 1e-15) & (th <= hi + 1e-15), axis=-1)


def tracking_errors(t, theta, theta_ref, *, t_from: float | None = None, t_to: float | None = None) -> dict:
    """Position-tracking error over ``[t_from, t_to]`` [s]: ``{"rms_deg", "max_abs_deg"}`` of
    ``theta_ref - theta`` [deg], each of shape ``(...)``."""
    m = window_mask(t, t_from, t_to)
    e = (np.asarray(theta_ref, dtype=np.float64) - np.asarray(theta, dtype=np.float64))[..., m]
    return {"rms_deg": np.sqrt(np.mean(e**2, axis=-1)), "max_abs_deg": np.max(np.abs(e), axis=-1)}
