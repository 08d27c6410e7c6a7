"""Locate model-reality mismatch in the residual of the inverse joint model (Li et al., Electronics
2020, 9, 284, eq. 1-2 and 9), with a controlled family-wise false-alarm rate.

Tests (each gives one p-value per region):

* binned means of the residual over velocity bands x direction, position bins, time windows, time
  since the last reversal x new direction, and acceleration sign x direction; the standard error is
  CLUSTER-ROBUST over ~1 s time blocks (residuals are autocorrelated within a block, roughly
  independent between blocks) and the t statistic is referred to Student-t with (clusters - 1) dof;
* a periodogram of the residual against POSITION (least-squares/Lomb-Scargle projection on position
  binned finely; the statistic is the drop in residual sum of squares by one sinusoid, chi2(2) under
  white noise, scaled by the long-run variance factor kappa of the residual), maximised over the
  period grid with a Bonferroni correction for the number of independent frequencies;
* a periodogram against TIME, each ordinate divided by the local median of its neighbours (robust to
  coloured noise), maximised with a Bonferroni correction;
* cross-correlation of the residual with the inputs (v, a, jerk, sign(v), |a|·sign(v)) at lags up to +-0.5 s, with
  Bartlett's variance for two autocorrelated series, Bonferroni over lags;
* the friction curve's shape: means of the residual signed by the direction of motion in bands of
  log-speed, after removing what the baseline's static parameters could make, with a margin from
  the band's expected errors-in-variables mean;
* a friction trend: the slope of the residual on F*(t - t_mid) (F the model's friction torque),
  cluster-robust;
* Ljung-Box whiteness on 20 lags (reported; not a location).

All p-values form one family, corrected by Holm's step-down method: under the null (model correct,
noise independent of the inputs) the probability of reporting ANY mismatch is <= alpha (5 %).
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from ._config import DiagnoseConfig

BACKGROUND_DOF = 0.3  # degrees of freedom per neighbour of the time periodogram's median background
MIN_PERIODS = 10  # a time-periodic line needs this many periods in the recording


def holm(p: np.ndarray) -> np.ndarray:
    """Holm step-down adjusted p-values (family-wise error control)."""
    p = np.asarray(p, float)
    m = p.size
    order = np.argsort(p)
    adj = np.empty(m)
    running = 0.0
    for i, j in enumerate(order):
        running = max(running, min(1.0, (m - i) * p[j]))
        adj[j] = running
    return adj


def long_run_variance_factor(r: np.ndarray, blocks: np.ndarray) -> float:
    """kappa = (variance of block means * mean block size) / variance: 1 for white noise."""
    _, inv, cnt = np.unique(blocks, return_inverse=True, return_counts=True)
    means = np.bincount(inv, weights=r) / cnt
    k = float(np.sum(cnt * (means - r.mean()) ** 2) / (len(cnt) - 1) / r.var())
    return max(1.0, k)


def cluster_mean_test(r: np.ndarray, mask: np.ndarray, blocks: np.ndarray, min_clusters: int = 5,
                      margin: np.ndarray | None = None):
    """Mean of ``r[mask]`` with a cluster-robust (time-block) standard error; None if too few clusters.

    ``margin``: per-sample bound on a residual the conditioning may leave (smoothing bias); the test
    is then of ``|mean| > mean(margin)`` (an effect beyond what the conditioning can explain)."""
    rb, bb = r[mask], blocks[mask]
    if rb.size < 20:
        return None
    _, inv = np.unique(bb, return_inverse=True)
    G = int(inv.max()) + 1
    if G < min_clusters:
        return None
    mean = float(rb.mean())
    u = np.bincount(inv, weights=rb - mean)
    var = G / (G - 1) * float(np.sum(u ** 2)) / rb.size ** 2
    se = np.sqrt(max(var, 1e-300))
    m_bias = float(np.mean(margin[mask])) if margin is not None else 0.0
    tval = np.sign(mean) * max(abs(mean) - m_bias, 0.0) / se
    df = G - 1
    p = float(2 * stats.t.sf(abs(tval), df))
    q = stats.t.ppf(0.975, df)
    return {"mean_residual": mean, "se": float(se), "ci95": [mean - q * se, mean + q * se], "statistic": float(tval),
            "df": df, "n": int(rb.size), "p_value": p, "conditioning_margin": m_bias}


def trend_test(r: np.ndarray, x: np.ndarray, blocks: np.ndarray, keep: np.ndarray, min_clusters: int = 5,
               margin: float = 0.0):
    """Least-squares slope of ``r`` on ``x`` over the ``keep`` samples, with a cluster-robust
    (time-block) standard error and Student-t with (clusters - 1) dof; None if too few clusters.
    ``margin``: a slope below it is not claimed (the test is of |slope| > margin)."""
    rb, xb, bb = r[keep], x[keep], blocks[keep]
    _, inv = np.unique(bb, return_inverse=True)
    G = int(inv.max()) + 1 if inv.size else 0
    sxx = float(np.dot(xb, xb))
    if G < min_clusters or sxx <= 0:
        return None
    beta = float(np.dot(xb, rb)) / sxx
    u = np.bincount(inv, weights=xb * (rb - beta * xb))
    se = np.sqrt(max(G / (G - 1) * float(np.sum(u ** 2)) / sxx ** 2, 1e-300))
    tval = np.sign(beta) * max(abs(beta) - margin, 0.0) / se
    return {"slope": beta, "statistic": float(tval), "df": G - 1, "p_value": float(2 * stats.t.sf(abs(tval), G - 1))}


def _reversal_clock(t, v, v_dead):
    """Time since the last change of direction, and the current direction (+1/-1/0)."""
    s = np.where(v > v_dead, 1, np.where(v < -v_dead, -1, 0))
    since = np.full(t.shape, np.inf)
    last_dir, t_rev = 0, -np.inf
    for i in range(t.size):
        if s[i] != 0 and s[i] != last_dir:
            if last_dir != 0:
                t_rev = t[i]
            last_dir = s[i]
        since[i] = t[i] - t_rev
    return since, np.where(s == 0, last_dir, s)


def reversal_info(t, v, V):
    since, direction = _reversal_clock(np.asarray(t), np.asarray(v), 0.005 * V)
    n_rev = int(np.sum(since == 0))
    return since, direction, n_rev


def _extra_array(known, key: str, like: np.ndarray) -> np.ndarray:
    """``known[key]`` as a float array, zeros like ``like`` where there is none."""
    x = known.get(key)
    return np.zeros_like(like, dtype=float) if x is None else np.asarray(x, float)


def _shape_bands(rec, r, blocks, moving, u, noise, known, shape_resolution: float,
                 shape_bands: int = DiagnoseConfig.shape_bands) -> list[dict]:
    """The ``friction_shape`` tests (see ``binned_tests``): one per log-speed band, or none where
    the bands are too few to tell a shape from the baseline's own static shapes."""
    v = np.asarray(rec.velocity, float)
    sv = np.sign(v)
    eiv = _extra_array(known, "eiv_bias_nm", r)
    cb = _extra_array(known, "conditioning_bias_nm", r)
    G = known.get("static_basis")
    G = np.zeros((r.size, 0)) if G is None else np.asarray(G, float).reshape(r.size, -1)
    mv = moving & (r != 0)
    if mv.sum() <= 40:
        return []
    lv = np.log(np.abs(v[mv]))
    lo_, hi_ = np.quantile(lv, [0.01, 0.99])
    if hi_ - lo_ <= np.log(2.0):
        return []
    n_b = int(min(shape_bands, max(2, np.ceil((hi_ - lo_) / np.log(1.5)))))
    be = np.exp(np.linspace(lo_, hi_, n_b + 1))
    be[0], be[-1] = 0.0, np.inf
    rs = r * sv
    bands = []
    for lo, hi in zip(be[:-1], be[1:]):
        m = mv & (np.abs(v) >= lo) & (np.abs(v) < hi)
        if m.sum() < 20:
            continue
        res = cluster_mean_test(rs, m, blocks)
        if res is not None:
            bm = abs(float(np.mean(eiv[m] * sv[m]))) + float(np.mean(cb[m])) + shape_resolution * noise
            bands.append((lo, hi, m, res, bm))
    k = G.shape[1]
    if len(bands) < k + 2:  # too few bands to tell a shape from the baseline's own
        return []
    if k:
        Gb = np.array([G[b[2]].mean(axis=0) for b in bands])
        mb = np.array([b[3]["mean_residual"] for b in bands])
        sw = 1.0 / np.sqrt(np.array([b[3]["se"] ** 2 + b[4] ** 2 for b in bands]))
        beta = np.linalg.lstsq(Gb * sw[:, None], mb * sw, rcond=None)[0]
        rs = rs - G @ beta
    out = []
    for lo, hi, m, _, bm in bands:
        res = cluster_mean_test(rs, m, blocks, margin=np.full(r.shape, bm))
        if res is not None:
            out.append({"test": "friction_shape", "region": {
                "velocity_abs_from": float(lo), "velocity_abs_to": float(hi), "unit": u["velocity"],
                "signed_by": "direction of motion", "baseline_static_shapes_removed": k}, **res})
    return out


def binned_tests(rec, r, blocks, scales, known=None, resolution: float = DiagnoseConfig.resolution,
                 shape_resolution: float = DiagnoseConfig.shape_resolution,
                 shape_bands: int = DiagnoseConfig.shape_bands) -> list[dict]:
    """The binned-mean tests; ``resolution``, ``shape_resolution`` and ``shape_bands``:
    :class:`DiagnoseConfig`'s."""
    known = dict(rec.extra) if known is None else known
    t, th, v, a = (np.asarray(x) for x in (rec.time, rec.position, rec.velocity, rec.acceleration))
    V, A = scales["V"], scales["A"]
    u = rec.units
    out = []

    # a region's mean must also exceed a resolution margin, a fraction of the per-sample noise:
    # the inverse model's own errors in variables at the slowest speeds leave means of that order
    # even with the true parameters, which is not missing physics
    noise = float(scales.get("noise", 0.0))
    floor = noise * resolution
    margin = _extra_array(known, "conditioning_bias_nm", r) + floor

    def add(kind, region, mask):
        res = cluster_mean_test(r, mask, blocks, margin=margin)
        if res is not None:
            out.append({"test": kind, "region": region, **res})

    # velocity bands x direction
    moving = np.abs(v) > 0.005 * V
    add("velocity_band", {"direction": "rest", "velocity_abs_max": 0.005 * V, "unit": u["velocity"]}, ~moving)
    edges = np.unique(np.quantile(np.abs(v[moving]), np.linspace(0, 1, 7))) if moving.any() else []
    for sgn, name in ((1, "+"), (-1, "-")):
        for lo, hi in zip(edges[:-1], edges[1:]):
            m = moving & (np.sign(v) == sgn) & (np.abs(v) >= lo) & (np.abs(v) <= hi)
            add("velocity_band", {"direction": name, "velocity_abs_from": float(lo),
                                  "velocity_abs_to": float(hi), "unit": u["velocity"]}, m)
    # the friction curve's shape: the residual signed by the direction of motion, in bands of
    # log-speed (a Stribeck fall or a viscous law the baseline's shape cannot follow is odd in v and
    # changes sign along the speed axis, so the direction bands above, quantile-wide and per
    # direction, average it away). What the baseline's own static parameters could make (the
    # band means of extra['static_basis'], weighted least squares) is taken out first: a fit pulled
    # by noisy transients leaves a shape of that kind on the precise plateaus, and it is not missing
    # physics. Each band's margin is its own expected errors-in-variables mean (from the perturbed
    # kinematics, see diagnose), the conditioning bias, and ``shape_resolution`` of the noise
    out += _shape_bands(rec, r, blocks, moving, u, noise, known, shape_resolution, shape_bands)
    # position bins
    pe = np.unique(np.quantile(th, np.linspace(0, 1, 13)))
    for lo, hi in zip(pe[:-1], pe[1:]):
        add("position_bin", {"position_from": float(lo), "position_to": float(hi), "unit": u["position"]},
            (th >= lo) & (th <= hi))
    # time windows
    te = np.linspace(t[0], t[-1], 11)
    for lo, hi in zip(te[:-1], te[1:]):
        add("time_window", {"time_from": float(lo), "time_to": float(hi), "unit": u["time"]},
            (t >= lo) & (t <= hi))
    # after reversals
    since, direction, _ = reversal_info(t, v, V)
    for lo, hi in ((0.0, 0.1), (0.1, 0.3), (0.3, 1.0)):
        for sgn, name in ((1, "+"), (-1, "-")):
            add("after_reversal", {"seconds_since_reversal_from": lo, "to": hi, "new_direction": name},
                (since >= lo) & (since < hi) & (direction == sgn))
    # acceleration sign x direction (transients)
    big = np.abs(a) > 0.2 * A
    for sv, nv in ((1, "+"), (-1, "-")):
        for sa, na in ((1, "+"), (-1, "-")):
            add("acceleration", {"direction": nv, "acceleration_sign": na,
                                 "acceleration_abs_above": 0.2 * A, "unit": u["acceleration"]},
                big & (np.sign(v) == sv) & (np.sign(a) == sa))
    return out


def _position_lines(theta, R, nbins: int = 2048, oversample: int = 4):
    """Least-squares sinusoid fits vs position of every row of ``R`` on finely binned data: the
    frequency grid, each fit's drop of the sum of squares and its (cos, sin) coefficients."""
    theta = np.asarray(theta)
    R = np.atleast_2d(np.asarray(R, float))
    span = float(np.ptp(theta))
    width = span / nbins
    idx = np.minimum(((theta - theta.min()) / width).astype(int), nbins - 1)
    cnt = np.bincount(idx, minlength=nbins).astype(float)
    keep = cnt > 0
    ssum = np.zeros((R.shape[0], nbins))
    for i in range(R.shape[0]):
        ssum[i] = np.bincount(idx, weights=R[i], minlength=nbins)
    x = theta.min() + (np.arange(nbins)[keep] + 0.5) * width
    n, S = cnt[keep], ssum[:, keep]
    S = S - np.outer(S.sum(1) / n.sum(), n)  # remove the weighted mean
    fmin, fmax = 0.5 / span, 1.0 / (4 * width)
    freqs = np.arange(fmin, fmax, 1.0 / (oversample * span))
    drop = np.empty((R.shape[0], freqs.size))
    coef = np.empty((R.shape[0], freqs.size, 2))
    for i0 in range(0, freqs.size, 256):
        f = freqs[i0:i0 + 256, None]
        c, sn = np.cos(2 * np.pi * f * x), np.sin(2 * np.pi * f * x)
        cc, ss_, cs = (n * c * c).sum(1), (n * sn * sn).sum(1), (n * c * sn).sum(1)
        bc, bs = S @ c.T, S @ sn.T
        det = cc * ss_ - cs ** 2
        ac = (ss_ * bc - cs * bs) / det
        as_ = (cc * bs - cs * bc) / det
        drop[:, i0:i0 + 256] = ac * bc + as_ * bs
        coef[:, i0:i0 + 256] = np.stack([ac, as_], axis=-1)
    return freqs, drop, coef, span, fmin, fmax


def _peaks(freqs, z, coef, k: int = 5) -> list[dict]:
    """Local maxima of z, strongest first, as ripple guesses."""
    lm = np.flatnonzero((z[1:-1] > z[:-2]) & (z[1:-1] >= z[2:])) + 1
    lm = lm[np.argsort(-z[lm])][:k]
    return [{"period": float(1 / freqs[j]), "amplitude": float(np.hypot(*coef[j])),
             "phase": float(np.arctan2(*coef[j])), "z": float(z[j])} for j in lm]


def position_peaks_many(theta, R) -> list[list[dict]]:
    """The position periodogram's peaks of every row of ``R`` (the scale of z does not change them)."""
    freqs, drop, coef, *_ = _position_lines(theta, R)
    return [_peaks(freqs, drop[i], coef[i]) for i in range(drop.shape[0])]


def position_periodogram(theta, r, kappa, nbins: int = 2048, oversample: int = 4):
    """Least-squares sinusoid fit vs position on finely binned data; returns grid, power, peaks, test."""
    freqs, drop, coef, span, fmin, fmax = _position_lines(theta, r, nbins, oversample)
    drop, coef = drop[0], coef[0]
    sigma2 = float(np.var(r)) * kappa
    z = drop / (2 * sigma2)  # chi2(2)/2 under H0 -> Exp(1)
    m_eff = max(1.0, span * (fmax - fmin))
    i = int(np.argmax(z))
    p_single = float(np.exp(-z[i]))
    p = float(-np.expm1(m_eff * np.log1p(-min(p_single, 1 - 1e-16)))) if p_single > 0 else 0.0
    return {"freqs": freqs, "z": z, "peaks": _peaks(freqs, z, coef), "p_value": p, "m_eff": m_eff,
            "statistic": float(z[i]), "period": float(1 / freqs[i])}


def _local_background(I, half_window: int, share: float = 1.0 / 3.0, min_half: int = 10):
    """Median of each ordinate's neighbours, over +-h_k = max(min_half, min(half_window, share*k))
    bins at bin k: a window proportional to the frequency at the low end, where the residual of an
    inverse model is red (errors in variables along a repeated excitation leave a hump there, not
    a line), and ``half_window`` bins above. Returns (background, neighbours used per bin); ``I``
    may hold several periodograms, one per row."""
    from scipy.ndimage import median_filter

    I2 = np.atleast_2d(I)
    bg = median_filter(I2, size=(1, 2 * half_window + 1), mode="reflect")
    m = I2.shape[1]
    used = np.full(m, 2 * half_window + 1, float)
    k_full = int(np.ceil(half_window / share))
    for k in range(min(k_full, m)):
        h = max(min_half, int(share * (k + 1)))
        lo, hi = max(0, k - h), min(m, k + h + 1)
        nb = np.concatenate([I2[:, lo:k], I2[:, k + 1:hi]], axis=1)
        bg[:, k], used[k] = np.median(nb, axis=1), nb.shape[1]
    return (bg[0] if np.ndim(I) == 1 else bg), used


def _power(t, R, oversample: int = 1):
    """Schuster periodogram of every row of ``R`` without its zero frequency: (frequencies, power);
    ``oversample`` > 1 evaluates it on a grid that many times finer (zero padding)."""
    R = np.atleast_2d(np.asarray(R, float))
    n = R.shape[1]
    m = oversample * n
    X = np.fft.rfft(R - R.mean(axis=1, keepdims=True), n=m, axis=1)
    return np.fft.rfftfreq(m, float(np.median(np.diff(t))))[1:], (np.abs(X) ** 2 / n)[:, 1:]


def line_logp(I, bg, used):
    """Each periodogram ordinate ``I`` over its median background ``bg`` (from ``used`` neighbours):
    (ratio to the background's mean, log single-ordinate p-value ``-nu*log1p(ratio/nu)``, nu =
    BACKGROUND_DOF times the neighbours used; :func:`time_periodogram`)."""
    ratio = I / np.maximum(bg / np.log(2), 1e-300)
    nu = BACKGROUND_DOF * used
    return ratio, -nu * np.log1p(ratio / nu)


def _time_lines(t, R, half_window: int = 200):
    f, I = _power(t, R)
    ratio, logp = line_logp(I, *_local_background(I, half_window))
    # a line is a periodicity: at least MIN_PERIODS periods in the recording (slower structure is
    # the time windows' and the drift candidate's; at the lowest ordinates a red hump and a line
    # cannot be told apart by their neighbours)
    logp[:, : MIN_PERIODS - 1] = 0.0
    return f, I, ratio, logp


def _strided_ratio(t, R, half_window: int = 200, stride: int = 16):
    """Each ordinate of every row's time periodogram over its neighbours' median, the median taken
    every ``stride`` ordinates and interpolated between (a running median over hundreds of draws is
    otherwise the cost of the whole test); the first ``MIN_PERIODS - 1`` ordinates are 0."""
    from numpy.lib.stride_tricks import sliding_window_view

    f, I = _power(t, R)
    m = I.shape[1]
    h = min(half_window, max(1, (m - 1) // 2))
    padded = np.pad(I, ((0, 0), (h, h)), mode="reflect")
    at = np.unique(np.r_[np.arange(0, m, stride), m - 1])
    windows = sliding_window_view(padded, 2 * h + 1, axis=1)
    bg_at = np.empty((I.shape[0], at.size))
    for r0 in range(0, I.shape[0], 8):  # a few rows' windows at a time: bounded memory
        w = windows[r0:r0 + 8, at]  # a copy, partitioned in place: its middle element is the median
        w.partition(h, axis=-1)  # (the window 2h + 1 is odd)
        bg_at[r0:r0 + 8] = w[..., h]
    bg = np.stack([np.interp(np.arange(m), at, b) for b in bg_at])
    ratio = I / np.maximum(bg / np.log(2), 1e-300)
    ratio[:, : MIN_PERIODS - 1] = 0.0
    return f, ratio


def time_peaks_many(t, R, half_window: int = 200, stride: int = 16) -> np.ndarray:
    """The time periodogram's strongest line [Hz] of every row of ``R``, for starting points: as
    :func:`time_periodogram`, with the background of :func:`_strided_ratio`."""
    f, ratio = _strided_ratio(t, R, half_window, stride)
    return f[np.argmax(ratio, axis=1)]


def time_periodogram(t, r, half_window: int = 200):
    """Schuster periodogram of the residual vs time, each ordinate over the median of its
    neighbours (:func:`_local_background`), so that coloured noise is not mistaken for a line.

    The background is itself estimated, so the ratio of an ordinate to it is F-like: the
    single-ordinate p-value is (1 + R/nu)^-nu rather than exp(-R), with nu = BACKGROUND_DOF times
    the neighbours used (the median of N exponential ordinates is worth fewer degrees of freedom
    than their mean; tests/test_locate_background.py checks the level on white noise)."""
    f, I, R, logp = _time_lines(t, r, half_window)
    I, R, logp = I[0], R[0], logp[0]
    i = int(np.argmin(logp))
    p_single = float(np.exp(logp[i]))
    m = max(1, R.size - (MIN_PERIODS - 1))
    p = float(-np.expm1(m * np.log1p(-min(p_single, 1 - 1e-16)))) if p_single > 0 else 0.0
    return {"freqs": f, "power": I, "ratio": R, "p_value": p, "statistic": float(R[i]),
            "frequency": float(f[i])}


def _row_spectra(R, m: int, L: int):
    """Each row's std, transform (length ``m``, centred) and autocorrelation to lag ``L``."""
    from scipy import fft

    rc = R - R.mean(axis=1, keepdims=True)
    Fr = fft.rfft(rc, m, axis=1, workers=-1)
    ar = fft.irfft(Fr * np.conj(Fr), m, axis=1, workers=-1)[:, : L + 1]
    return rc.std(axis=1), Fr, ar / np.where(ar[:, :1] != 0, ar[:, :1], 1.0)


def _xcorr_input(x, max_lag: int, L: int, min_lag: int, m: int):
    """An input's conjugate transform, autocorrelation, tested lags and std; None if it is constant
    or no lag is left."""
    lags = np.arange(-max_lag, max_lag + 1)
    lags = lags[np.abs(lags) >= min_lag]
    sx, Fx, ax = (y[0] for y in _row_spectra(x[None, :], m, L))
    if sx == 0 or lags.size == 0:
        return None
    return np.conj(Fx), ax, lags, sx


def _xcorr_z(sr, Fr, ar, inp, n: int, L: int, margin_nm: float):
    """Correlations at the input's lags (rows x lags), their Bartlett standard error (rows) and the
    standardised excess over the margin (rows x lags); a constant row gives 0."""
    from scipy import fft

    Fx, ax, lags, sx = inp
    cc = fft.irfft(Fr * Fx[None, :], 2 * (Fr.shape[1] - 1), axis=1, workers=-1)
    # corr(r_t, x_{t+k}) = cc[-k] with this FFT convention (k > 0 wraps to the end)
    rho = cc[:, -lags] / (n * np.where(sr > 0, sr, 1.0)[:, None] * sx)
    w = 1 - np.arange(L + 1) / (L + 1)
    se = np.sqrt(np.maximum((1 + 2 * np.sum(w[1:] * ar[:, 1:] * ax[1:], axis=1)) / n, 1.0 / n))
    z = np.maximum(np.abs(rho) - margin_nm / np.where(sr > 0, sr, np.inf)[:, None], 0.0) / se[:, None]
    return rho, se, z


def xcorr_test(r, x, max_lag: int, L: int, min_lag: int = 0, margin_nm: float = 0.0):
    """max_k |corr(r_t, x_{t+k})| over ``min_lag <= |k| <= max_lag``, Bartlett variance, Bonferroni
    over lags. ``min_lag`` > 0 skips the lags at which the input and the residual share measurement
    noise through the conditioning filter (errors in variables: an acceleration smoothed over W
    samples and the residual it leaves are correlated at |k| < W under the null).
    ``margin_nm``: the residual's part along the standardised input (``corr * std(r)``, N*m per
    input std) that is not claimed; the statistic counts only the correlation beyond it."""
    n = r.size
    inp = _xcorr_input(np.asarray(x, float), max_lag, L, min_lag, 2 * n)
    if inp is None:
        return None
    rho, se, z = _xcorr_z(*_row_spectra(np.asarray(r, float)[None, :], 2 * n, L), inp, n, L, margin_nm)
    rho, se, zz = rho[0], float(se[0]), z[0]
    j = int(np.argmax(zz))
    p = float(min(1.0, inp[2].size * 2 * stats.norm.sf(zz[j])))
    return {"lag_samples": int(inp[2][j]), "correlation": float(rho[j]), "statistic": float(zz[j]),
            "p_value": p, "rho": rho, "lags": inp[2], "se": se}


def xcorr_statistics(R, inputs, max_lag: int, L: int) -> np.ndarray:
    """:func:`xcorr_test`'s statistic for every row of ``R`` (draws x n) against each input of
    ``inputs`` (``(x, min_lag, margin_nm)`` triples): draws x inputs. Each row's transform and
    autocorrelation are computed once for all inputs, each input's once for all rows."""
    R = np.atleast_2d(np.asarray(R, float))
    B, n = R.shape
    prepared = [(_xcorr_input(np.asarray(x, float), max_lag, L, ml, 2 * n), mg) for x, ml, mg in inputs]
    out = np.zeros((B, len(inputs)))
    for b0 in range(0, B, 16):  # bounded memory: 16 rows' transforms at a time
        spectra = _row_spectra(R[b0:b0 + 16], 2 * n, L)
        for k, (inp, mg) in enumerate(prepared):
            if inp is not None:
                out[b0:b0 + 16, k] = np.max(_xcorr_z(*spectra, inp, n, L, mg)[2], axis=1)
    return out


def _time_line_statistic(t, R, half_window: int = 200, stride: int = 16) -> np.ndarray:
    """Largest ordinate-over-background ratio of the time periodogram of every row of ``R`` past
    the first ``MIN_PERIODS - 1`` ordinates (:func:`_strided_ratio`)."""
    return np.max(_strided_ratio(t, R, half_window, stride)[1], axis=1)


def gumbel_sf(x: float, draws: np.ndarray) -> float:
    """Upper-tail probability of ``x`` under a Gumbel law fitted to ``draws`` by its moments: the
    largest of many nearly independent ordinates (a periodogram's peak) is Gumbel whatever the
    ordinates' common law, and the fit extends the null draws' tail past their own resolution."""
    d = np.asarray(draws, float)
    sd = float(np.std(d, ddof=1)) if d.size > 1 else 0.0
    if not sd > 0:
        return 1.0 if x <= float(np.max(d, initial=0.0)) else 0.0
    beta = sd * np.sqrt(6.0) / np.pi
    mu = float(np.mean(d)) - np.euler_gamma * beta
    return float(-np.expm1(-np.exp(-(x - mu) / beta)))


def ljung_box_many(R, m: int = 20, min_lag: int = 1, margin: float = 0.0) -> np.ndarray:
    """:func:`ljung_box`'s statistic for every row of ``R`` (16 rows' transforms at a time)."""
    R = np.atleast_2d(np.asarray(R, float))
    n = R.shape[1]
    k = np.arange(min_lag, min_lag + m)
    out = np.empty(R.shape[0])
    for b0 in range(0, R.shape[0], 16):
        ac = _row_spectra(R[b0:b0 + 16], 2 * n, int(k[-1]))[2][:, k]
        out[b0:b0 + 16] = n * (n + 2) * np.sum(np.maximum(ac ** 2 - margin / m, 0.0) / (n - k), axis=1)
    return out


def scaled_chi2_sf(x: float, draws: np.ndarray) -> float:
    """Upper-tail probability of ``x`` under ``c*chi2(nu)`` matched to the mean and variance of
    ``draws`` (Satterthwaite): the law of a sum of squared correlations of coloured noise."""
    d = np.asarray(draws, float)
    m, v = float(np.mean(d)), float(np.var(d, ddof=1)) if d.size > 1 else 0.0
    if not (m > 0 and v > 0):
        return 1.0 if x <= float(np.max(d, initial=0.0)) else 0.0
    return float(stats.chi2.sf(x * 2.0 * m / v, 2.0 * m * m / v))


def ljung_box(r, m: int = 20, min_lag: int = 1, margin: float = 0.0):
    """Ljung-Box on the ``m`` lags from ``min_lag`` (past the conditioning filter's memory, where the
    smoothed measurement noise the residual carries is uncorrelated).

    ``margin``: the share of the residual variance that past lags may predict before it counts
    (autocorrelations below ``sqrt(margin/m)`` per lag are discounted): a baseline at its noise floor
    on a long recording leaves weak colour from the conditioning (a quantised encoder's, for one),
    significant at that length but not missing physics."""
    Q = float(ljung_box_many(r, m, min_lag, margin)[0])
    return {"statistic": Q, "df": m, "p_value": float(stats.chi2.sf(Q, m))}


def locate(rec, r, blocks, scales, alpha: float = 0.05, filter_lags: int = 0, keep=None,
           friction=None, known: dict | None = None, null=None, resolution: float = DiagnoseConfig.resolution,
           shape_resolution: float = DiagnoseConfig.shape_resolution,
           shape_bands: int = DiagnoseConfig.shape_bands) -> dict:
    """Run every test on residual ``r`` and Holm-correct them jointly; see the module docstring.

    ``filter_lags``: the memory (in samples) of the filter that conditioned the kinematics; the
    cross-correlation with acceleration and jerk and the whiteness test skip shorter lags.
    ``keep``: the resolved samples (``r`` is 0 elsewhere); the inputs are correlated on those only,
    since near an unresolved transient the residual keeps a smoothing bias below the resolution
    threshold that lines up with the transient's large acceleration a window away.
    ``friction``: the model's friction torque per sample, the shape a drift of the whole friction
    takes in the residual (the friction-trend test's regressor); without it, sign(v).
    ``known``: what a correct model's residual keeps in expectation, not claimed as structure:
    ``eiv_bias_nm`` and ``conditioning_bias_nm`` (per sample), ``static_basis`` (the baseline's
    static-curve derivatives), ``eiv_inertial_nm``; default: the recording's ``extra`` columns.
    ``null``: simulated residuals of a complete model (draws x n, :mod:`._calibrate`'s measurement
    chain); the two periodograms' peaks, the cross-correlations and the whiteness test then also
    refer their statistic to its law on the draws (Ljung-Box: a scaled chi-square matched to them),
    the tail extended by a fitted Gumbel law (:func:`gumbel_sf`), and keep the larger of that
    p-value and the analytic one: the analytic law holds for noise of the assumed kind, the
    simulated one for the measurement chain the data show (a quantised encoder's derivatives,
    coloured noise), and neither test may fire on what the other explains."""
    known = dict(rec.extra) if known is None else {k: v for k, v in known.items() if v is not None}
    r = np.asarray(r, float)
    keep = np.ones(r.shape, bool) if keep is None else np.asarray(keep, bool)
    kappa = long_run_variance_factor(r, blocks)
    tests = binned_tests(rec, r, blocks, scales, known, resolution, shape_resolution, shape_bands)
    pp = position_periodogram(rec.position, r, kappa)
    tests.append({"test": "position_periodic", "region": {"period": pp["period"], "unit": rec.units["position"]},
                  "statistic": pp["statistic"], "p_value": pp["p_value"], "m_eff": pp["m_eff"]})
    tp = time_periodogram(rec.time, r)
    tests.append({"test": "time_periodic", "region": {"frequency_hz": tp["frequency"]},
                  "statistic": tp["statistic"], "p_value": tp["p_value"]})
    Rn = None
    if null is not None and len(null) > 1:
        Rn = np.asarray(null, float) * keep[None, :]
        _, drop_n, *_ = _position_lines(rec.position, Rn)
        # the observed peak's drop over the residual's variance, from the periodogram above
        # (its statistic is that drop over 2*kappa*var)
        tests[-2]["p_analytic"] = tests[-2]["p_value"]
        tests[-2]["p_value"] = max(tests[-2]["p_value"],
                                   gumbel_sf(2.0 * kappa * pp["statistic"], drop_n.max(axis=1) / np.var(Rn, axis=1)))
        tl = _time_line_statistic(rec.time, np.vstack([r[None, :], Rn]))
        tests[-1]["p_analytic"] = tests[-1]["p_value"]
        tests[-1]["p_value"] = max(tests[-1]["p_value"], gumbel_sf(float(tl[0]), tl[1:]))
    fs = scales["fs"]
    max_lag = max(1, int(round(0.5 * fs)))
    L = min(r.size // 4, int(5 * fs))
    xcs = {}
    jerk = np.gradient(np.asarray(rec.acceleration, float), np.asarray(rec.time, float))
    # what errors in variables leave correlated with the acceleration beyond the filter's memory
    # (the attenuated share of J*a_true, see diagnose); expected under the null, so taken out here
    eiv = known.get("eiv_inertial_nm")
    r_acc = r if eiv is None else r - np.where(keep, np.asarray(eiv, float), 0.0)
    acc = np.asarray(rec.acceleration, float)
    # |a|*sign(v): the shape of a friction that grows with the transmitted (inertial) torque; it is
    # even in the acceleration, so the cross-correlations with a and jerk cancel it between
    # speeding up and slowing down (docs/diagnosis.md, load-dependent friction)
    # the shapes a correct model's residual keeps in expectation (known["nuisance"]: the kinematics'
    # systematic error through the model, the smoothing's bias) are projected out of the residual and
    # of the null draws before the cross-correlations, as the candidates' test does
    nuis = known.get("nuisance")
    Q = None
    if nuis is not None and keep.any():
        from ._calibrate import _orth

        Q = _orth(np.asarray(nuis, float).reshape(r.size, -1)[keep])

    def deflate(y):
        if Q is None or Q.shape[1] == 0:
            return y
        y = np.array(y, float)
        y[..., keep] -= (y[..., keep] @ Q) @ Q.T
        return y

    r_x, r_acc = deflate(r), deflate(r_acc)
    Rn_x = deflate(Rn) if null is not None and len(null) > 1 else None
    xc_inputs = []
    for name, x in (("velocity", rec.velocity), ("acceleration", acc), ("jerk", jerk),
                    ("sign_velocity", np.sign(rec.velocity)),
                    ("transmitted_torque", np.abs(acc) * np.sign(rec.velocity))):
        # inputs made from the smoothed acceleration share the smoothing's error with the residual
        # within the filter's memory: its noise, and its bias at every change of the acceleration,
        # whose law needs the true acceleration (no null from the data exists), so those lags are
        # skipped (with derivatives of a quantised position filter_lags exceeds max_lag: not run)
        ml = filter_lags if name in ("acceleration", "jerk", "transmitted_torque") else 0
        x = np.asarray(x, float)
        x = np.where(keep, x, np.mean(x[keep]) if keep.any() else 0.0)
        # the velocity and its sign carry the baseline's static curve (viscous and Coulomb parts):
        # what it leaves along them below the binned means' margin is not claimed either (a
        # baseline at its floor leaves small correlations there that a long recording makes
        # significant)
        mg = resolution * float(scales.get("noise", 0.0)) if name in ("velocity", "sign_velocity") else 0.0
        xc = xcorr_test(r_acc if name in ("acceleration", "jerk", "transmitted_torque") else r_x, x, max_lag, L, ml, mg)
        if xc is not None:
            xcs[name] = xc
            xc_inputs.append((x, ml, mg))
            tests.append({"test": "cross_correlation", "region": {"input": name, "lag_s": xc["lag_samples"] / fs},
                          "statistic": xc["statistic"], "p_value": xc["p_value"]})
    if Rn_x is not None and xc_inputs:
        # the largest standardised correlation over the lags on every null draw: its law for the
        # measurement chain at hand (the Bartlett variance assumes noise independent of the input,
        # which smoothed kinematics are not within the filter's memory)
        Z = xcorr_statistics(Rn_x, xc_inputs, max_lag, L)
        for test, zn in zip(tests[-len(xc_inputs):], Z.T):
            test["p_analytic"] = test["p_value"]
            test["p_value"] = max(test["p_value"], gumbel_sf(float(test["statistic"]), zn))
    # friction drifting in time: the residual grows along F*(t - t_mid), F the model's friction
    # torque (sign(v) without one). A square wave with the excitation's direction changes, its mean
    # over any time window is ~0, so neither the time windows nor the velocity bands (which average
    # over time) see it. F rather than sign(v): the drift scales the whole friction, so the fast
    # samples, whose viscous part is large, carry most of it, and only F weighs them so
    # margin: as for the binned means, a change of the direction-signed mean residual from the
    # first half of the recording to the second (slope * mean|F| * duration / 2) below ``resolution``
    # of the per-sample noise is not claimed
    tt = np.asarray(rec.time, float)
    dur = max(float(tt[-1] - tt[0]), 1e-300)
    shape = np.sign(np.asarray(rec.velocity, float)) if friction is None else np.asarray(friction, float)
    size = float(np.mean(np.abs(shape[keep]))) if keep.any() else 0.0
    tr = trend_test(r, shape * (tt - 0.5 * (tt[0] + tt[-1])), blocks, keep,
                    margin=resolution * float(scales.get("noise", 0.0)) / (0.5 * dur * max(size, 1e-300)))
    if tr is not None:
        region = {"input": "sign(v)*(t - t_mid)" if friction is None else "F*(t - t_mid)", "slope": tr["slope"]}
        if friction is not None:
            region["relative_change_over_recording"] = tr["slope"] * dur
        tests.append({"test": "friction_trend", "region": region, "statistic": tr["statistic"],
                      "p_value": tr["p_value"]})
    lb_margin = resolution ** 2 if scales.get("noise") else 0.0
    lb = ljung_box(r, min_lag=max(1, filter_lags), margin=lb_margin)
    test = {"test": "whiteness_ljung_box", "region": {"whole_recording": True, "lags": lb["df"],
                                                      "from_lag": max(1, filter_lags)},
            "statistic": lb["statistic"], "p_value": lb["p_value"]}
    if Rn is not None:
        # Q on every null draw (the kinematics' errors through the model are coloured), its law a
        # scaled chi-square matched to the draws' mean and variance (a sum of squares, not a maximum)
        qn = ljung_box_many(Rn, min_lag=max(1, filter_lags), margin=lb_margin)
        test["p_analytic"] = test["p_value"]
        test["p_value"] = max(test["p_value"], scaled_chi2_sf(lb["statistic"], qn))
    tests.append(test)
    p_adj = holm(np.array([x["p_value"] for x in tests]))
    for x, q in zip(tests, p_adj):
        x["p_holm"] = float(q)
        x["significant"] = bool(q < alpha)
    located = sorted([x for x in tests if x["significant"]], key=lambda x: x["p_holm"])
    structural = [x for x in located if x["test"] != "whiteness_ljung_box"]
    return {"tests": tests, "located": located, "structural": structural, "kappa": kappa,
            "alpha": alpha, "n_tests": len(tests), "position_periodogram": pp,
            "time_periodogram": tp, "xcorr": xcs}
