"""Smoothing of averaged Stribeck data, Li et al., Electronics 2020, 9, 284, section 4.2.2:
a cubic spline through the averaged torques (Fig. 4), and the 4-term "Sum of Sin" curve of
eq. (12), ``MT(v) = sum_i a_i sin(b_i v + c_i)``, fitted to the spline on each segment (the paper
used Matlab's cftool).

Choices, and why:

* The spline is scipy's penalised cubic smoothing spline (``make_smoothing_spline``) with the
  penalty chosen by generalised cross-validation and weights ``1/se**2``: averaged data still carry
  noise, and an interpolating spline would follow it. For locating the minimum over the whole range
  it is fitted in ``log(v)`` (one smoothing level cannot suit both the steep Stribeck drop and the
  gentle viscous rise in linear ``v``); per segment it is fitted in ``v`` (``log v`` for segment 1)
  with the neighbouring segment's boundary value pinned, for continuity (the paper fits each segment
  "based on the end parameters of the upper segment").
* The decelerating branch of the low-velocity segment must be tangent to the accelerating one at the
  minimum-torque velocity (equal value and slope). We fit it as the accelerating spline plus a
  polynomial in ``(v_min - v)`` starting at power 2, which meets both conditions exactly.
* Sum-of-sines is linear in ``(a cos c, a sin c)`` once the frequencies ``b`` are fixed, so we
  optimise only over ``b`` (variable projection) from many starting frequency sets; this is far
  more reliable than a 12-parameter nonlinear fit.

Units: velocity deg/s, torque N*m.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import interpolate, optimize


@dataclasses.dataclass(frozen=True)
class SmoothingSpline:
    """A smoothing spline ``torque(v)`` [N*m] of velocity [deg/s] on ``[v_lo, v_hi]``; with
    ``log_x`` the spline lives in ``log(v)`` (see :func:`fit_smoothing_spline`)."""

    spline: interpolate.BSpline
    v_lo: float
    v_hi: float
    lam: float
    log_x: bool = False

    def _x(self, v):
        v = np.asarray(v, dtype=np.float64)
        return np.log(np.maximum(v, 1e-300)) if self.log_x else v

    def __call__(self, v):
        return self.spline(self._x(v))

    def derivative(self, v, nu: int = 1):
        if nu != 1 and self.log_x:
            raise ValueError("only the first derivative is available for a log-velocity spline")
        d = self.spline.derivative(nu)(self._x(v))
        return d / np.asarray(v, dtype=np.float64) if self.log_x else d


def fit_smoothing_spline(velocity, torque, se=None, lam: float | None = None, *, log_x: bool = False,
                         pins=()) -> SmoothingSpline:
    """Penalised cubic smoothing spline of averaged torques [N*m] against velocity [deg/s].

    ``se`` (standard errors) become weights ``1/se**2`` (normalised); ``lam=None`` chooses the
    smoothing by generalised cross-validation. ``log_x=True`` fits in ``log(v)`` (v > 0): the
    Stribeck drop at low velocity is then no steeper than the rest, so one smoothing level suits the
    whole range. ``pins`` = ``[(v, torque), ...]`` are extra points with 1e4 times the largest weight
    (continuity with a neighbouring segment). Needs at least 5 distinct velocities.
    """
    v = np.asarray(velocity, dtype=np.float64)
    t = np.asarray(torque, dtype=np.float64)
    if se is not None:
        s = np.asarray(se, dtype=np.float64)
        w = 1.0 / s**2 if (np.all(np.isfinite(s)) and np.all(s > 0)) else np.ones_like(v)
    else:
        w = np.ones_like(v)
    w = w / w.mean()
    for vp, tp in pins:
        keep = np.abs(v - vp) > 1e-12 * max(1.0, abs(vp))
        v, t, w = np.append(v[keep], vp), np.append(t[keep], tp), np.append(w[keep], 1e4 * w.max())
    order = np.argsort(v)
    v, t, w = v[order], t[order], w[order]
    if np.unique(v).size != v.size:
        raise ValueError("fit_smoothing_spline: velocities must be distinct (average repeated set-points first)")
    if v.size < 5:
        raise ValueError(f"fit_smoothing_spline needs at least 5 set-points, got {v.size}")
    if log_x and v[0] <= 0:
        raise ValueError("fit_smoothing_spline(log_x=True) needs positive velocities")
    x = np.log(v) if log_x else v
    spl = interpolate.make_smoothing_spline(x, t, w=w, lam=lam)
    return SmoothingSpline(spl, float(v[0]), float(v[-1]), float("nan") if lam is None else float(lam), log_x)


@dataclasses.dataclass(frozen=True)
class TangentBranch:
    """Decelerating branch: ``base(v) + sum_j c_j (v_t - v)**j`` for j = 2..deg (tangent at ``v_t``)."""

    base: SmoothingSpline
    v_t: float
    coef: np.ndarray

    def __call__(self, v):
        v = np.asarray(v, dtype=np.float64)
        d = np.clip(self.v_t - v, 0.0, None)
        powers = np.arange(2, 2 + self.coef.size)
        return self.base(v) + (d[..., None] ** powers) @ self.coef

    def derivative(self, v):
        v = np.asarray(v, dtype=np.float64)
        d = np.clip(self.v_t - v, 0.0, None)
        powers = np.arange(2, 2 + self.coef.size)
        return self.base.derivative(v) - (powers * d[..., None] ** (powers - 1)) @ self.coef


def fit_tangent_branch(base: SmoothingSpline, velocity, torque, v_t: float, se=None, degree: int = 5) -> TangentBranch:
    """Fit the decelerating branch tangent to ``base`` at ``v_t`` [deg/s] (weighted least squares)."""
    v = np.asarray(velocity, dtype=np.float64)
    t = np.asarray(torque, dtype=np.float64)
    n_terms = min(degree - 1, max(v.size - 1, 1))
    d = np.clip(v_t - v, 0.0, None)
    A = d[:, None] ** np.arange(2, 2 + n_terms)
    y = t - base(v)
    w = np.ones_like(v) if se is None or not np.all(np.isfinite(se)) else 1.0 / np.asarray(se)
    coef, *_ = np.linalg.lstsq(A * w[:, None], y * w, rcond=None)
    return TangentBranch(base, float(v_t), coef)


@dataclasses.dataclass(frozen=True)
class SumOfSines:
    """Eq. (12): ``MT(v) = sum_i a_i sin(b_i v + c_i)``; v in deg/s, MT in N*m, b in rad/(deg/s)."""

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    v_lo: float
    v_hi: float
    rms: float  # N*m, against the curve it was fitted to

    def __call__(self, v):
        v = np.asarray(v, dtype=np.float64)
        return np.sin(v[..., None] * self.b + self.c) @ self.a

    def to_json(self) -> dict:
        return dict(a=self.a.tolist(), b=self.b.tolist(), c=self.c.tolist(), v_range=[self.v_lo, self.v_hi], rms=self.rms)


def _sines_linear(x, y, b, ridge=1e-10):
    """Best (p, q) with y ~ sum p sin(b x) + q cos(b x) for fixed b; returns coefficients, residual."""
    A = np.concatenate([np.sin(np.outer(x, b)), np.cos(np.outer(x, b))], axis=1)
    # A tiny ridge keeps near-duplicate frequencies from producing huge cancelling amplitudes.
    lhs = A.T @ A + ridge * np.trace(A.T @ A) / A.shape[1] * np.eye(A.shape[1])
    pq = np.linalg.solve(lhs, A.T @ y)
    return pq, A @ pq - y


def fit_sum_of_sines(curve, v_lo: float, v_hi: float, n_terms: int = 4, n_grid: int = 200, n_starts: int = 24, seed: int = 0) -> SumOfSines:
    """Fit eq. (12) with ``n_terms`` sines to ``curve(v)`` sampled on ``n_grid`` points of
    ``[v_lo, v_hi]`` [deg/s] by variable projection over the frequencies (see module docstring)."""
    if not v_hi > v_lo:
        raise ValueError(f"fit_sum_of_sines: need v_hi > v_lo, got [{v_lo}, {v_hi}]")
    v = np.linspace(v_lo, v_hi, n_grid)
    y = np.asarray(curve(v), dtype=np.float64)
    L = v_hi - v_lo
    # Work on x in [0, 1]: frequencies then live on a scale-free range.
    x = (v - v_lo) / L
    rng = np.random.default_rng(seed)

    def res(beta):
        return _sines_linear(x, y, beta)[1]

    best = None
    starts = [np.pi * np.arange(1, n_terms + 1) * s for s in (0.25, 0.5, 1.0)]
    starts += [np.sort(rng.uniform(0.05, 4.0 * np.pi, n_terms)) for _ in range(n_starts)]
    for beta0 in starts:
        try:
            r = optimize.least_squares(res, beta0, bounds=(1e-3, 8 * np.pi), method="trf", max_nfev=400)
        except (ValueError, np.linalg.LinAlgError):
            continue
        if best is None or r.cost < best.cost:
            best = r
    beta = best.x
    pq, e = _sines_linear(x, y, beta)
    p, q = pq[:n_terms], pq[n_terms:]
    a = np.hypot(p, q)
    phase = np.arctan2(q, p)  # p sin(bx) + q cos(bx) = a sin(bx + phase)
    # Back to velocity: b x + phase = (b/L) v + (phase - b v_lo / L).
    b = beta / L
    c = phase - b * v_lo
    return SumOfSines(a, b, c, float(v_lo), float(v_hi), float(np.sqrt(np.mean(e**2))))
