"""Signal conditioning and noise estimates from the recording itself (no constant tuned to one
generator): which velocity to use (the measured column or the position's derivative), how much to
smooth it (Savitzky-Golay, window set by the estimated noise), and the torque noise floor that a
correct baseline should reach.

Noise estimates use the high-frequency part of each signal: the third difference of a smooth signal
is negligible at the sampling rate while that of white noise has variance 20*sigma^2; its median
absolute deviation makes the estimate robust to the few samples at sharp transients. The torque's
noise may be coloured (an averaged or filtered current): :func:`torque_noise_std` then follows the
estimate to longer lags, where it reaches the noise's full std.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.signal import freqz, savgol_coeffs, savgol_filter

from ._config import DiagnoseConfig


def _mad_std(d) -> float:
    return float(1.4826 * np.median(np.abs(d - np.median(d))))


def hf_noise_std(x) -> float:
    """Per-sample white-noise std of ``x`` from its third difference (robust MAD estimate)."""
    d = np.diff(np.asarray(x, float), 3)
    if d.size < 10:
        return 0.0
    return _mad_std(d) / float(np.sqrt(20.0))


def _third_difference(x, k: int) -> np.ndarray:
    return x[:-3 * k] - 3 * x[k:-2 * k] + 3 * x[2 * k:-k] - x[3 * k:]


def _kept_differences(n: int, k: int, jumps=None, signal_d=None, limit: float = 0.0) -> np.ndarray | None:
    """Which of the ``n`` lag-k third differences the noise profile keeps, or None when fewer than
    a quarter (and 10) are left, and all are kept. ``signal_d``: a prediction's own lag-k third
    differences."""
    ok = np.ones(n, bool)
    if jumps is not None:
        # leave out the differences whose span holds a jump of the signal (a step between
        # set-points): at long lags they would be a large share, past what the MAD ignores
        c = np.concatenate([[0], np.cumsum(jumps)])
        ok &= (c[3 * k + 1:] - c[:-3 * k - 1]) == 0
    if signal_d is not None:
        # and those the signal (a model's prediction of it) reaches past ``limit``: at the long lags
        # that show a colour, the signal's own rise where the motion changes fast is not the smooth
        # k^6 law the fit allows for, and it reads as colour
        ok &= np.abs(signal_d) <= limit
    return ok if ok.sum() >= max(10, n // 4) else None


def _third_difference_std(x, k: int, jumps=None, signal=None, limit: float = 0.0,
                          outlier_std: float = DiagnoseConfig.outlier_std) -> float:
    d = _third_difference(x, k)
    ok = _kept_differences(d.size, k, jumps, None if signal is None else _third_difference(signal, k), limit)
    if ok is not None:
        d = d[ok]
    # and those far out at this lag: a fast but resolved change of the signal (the friction torque
    # through a reversal, ~2*Fc within the pre-sliding distance) is no jump at lag 1 but spans a
    # share of the long lags that grows with k, as a colour's rise does: left in, it makes white
    # noise look coloured and the floor too high
    for _ in range(3):
        s = _mad_std(d)
        ok = np.abs(d - np.median(d)) <= outlier_std * s
        if s <= 0 or ok.all() or ok.sum() < max(10, d.size // 2):
            break
        d = d[ok]
    return _mad_std(d) / np.sqrt(20.0)


def _jumps(x: np.ndarray, jump_std: float | None) -> np.ndarray:
    """Where the signal steps: lag-1 third differences beyond ``jump_std`` robust std (the white
    part's); None leaves none out."""
    d1 = np.diff(x, 3)
    s1 = _mad_std(d1)
    jumps = np.zeros(x.size, bool)
    if s1 > 0 and jump_std is not None:
        jumps[np.flatnonzero(np.abs(d1 - np.median(d1)) > jump_std * s1)] = True
    return jumps


def noise_profile(x, max_lag: int = 128, segments: int = 8, jump_std: float | None = 6.0, signal=None,
                  limit: float = 0.0, outlier_std: float = DiagnoseConfig.outlier_std):
    """(lags, std, se): the third-difference noise estimate at lags of k samples
    (``x[i] - 3x[i+k] + 3x[i+2k] - x[i+3k]``, robust MAD; lags 1, 2, 3, 4, 6, 8, ... up to
    ``max_lag`` and a twelfth of a segment) and its standard error (spread over
    ``segments`` contiguous parts). White noise gives the same std at every lag; noise correlated
    over m samples (an averaged or low-passed sensor) is partly cancelled by the difference at lags
    below m, so the estimate rises to the noise's full std there; a smooth signal adds a part
    growing as k^3. ``signal``: a prediction of the signal in ``x``; the differences it reaches past
    ``limit`` are left out (:func:`refined_torque_noise`). ``outlier_std``: a difference further than
    this many robust stds from the median at its lag is left out as signal
    (:attr:`DiagnoseConfig.outlier_std`)."""
    x = np.asarray(x, float)
    sig = None if signal is None else np.asarray(signal, float)
    seg = x.size // segments
    jumps = _jumps(x, jump_std)
    lags, sd, se = [], [], []
    for k in (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128):
        if k > max_lag or 3 * k > seg // 4:
            break
        lags.append(k)
        sd.append(_third_difference_std(x, k, jumps, sig, limit, outlier_std))
        parts = [_third_difference_std(x[i * seg:(i + 1) * seg], k, jumps[i * seg:(i + 1) * seg],
                                       None if sig is None else sig[i * seg:(i + 1) * seg], limit, outlier_std)
                 for i in range(segments)]
        se.append(float(np.std(parts, ddof=1)) / np.sqrt(segments))
    return np.array(lags, int), np.array(sd, float), np.array(se, float)


def signal_profile(x, signal, lags, limit: float, jump_std: float | None = 6.0) -> np.ndarray:
    """Variance of the lag-k third differences of ``signal`` (a model's prediction of the signal in
    ``x``) over the differences :func:`noise_profile` keeps at each of ``lags`` (those within
    ``limit`` and clear of ``x``'s jumps): the signal's own share of that profile, in its shape."""
    sig = np.asarray(signal, float)
    jumps = _jumps(np.asarray(x, float), jump_std)
    out = []
    for k in lags:
        d = _third_difference(sig, k)
        ok = _kept_differences(d.size, k, jumps, d, limit)
        out.append(float(np.var(d if ok is None else d[ok])))
    return np.array(out, float)


def _gain_from_acf(r_k, r_2k, r_3k):
    """var of the lag-k third difference of a unit-variance noise over 20, from its autocorrelation
    at lags k, 2k and 3k (``x[i] - 3x[i+k] + 3x[i+2k] - x[i+3k]``: 20 - 30 r_k + 12 r_2k - 2 r_3k)."""
    return 1.0 - (30.0 * r_k - 12.0 * r_2k + 2.0 * r_3k) / 20.0


def _third_difference_gain(k, phi):
    """:func:`_gain_from_acf` of an AR(1) noise (coefficient phi: autocorrelation phi^k)."""
    return _gain_from_acf(phi ** k, phi ** (2 * k), phi ** (3 * k))


# Autocorrelation weights of the moving-average parts the broader colour family allows: none, a zero
# at the Nyquist frequency (1 + z^-1) and a double one ((1 + z^-1)^2, a second-order Butterworth's
# or any bilinear-transformed second-order low-pass's), at lags 0, 1, 2.
_MA_WEIGHTS = ((1.0,), (2.0, 1.0), (6.0, 4.0, 1.0))
_MA_POLY = ((1.0,), (1.0, 1.0), (1.0, 2.0, 1.0))


def _arma_acf(a1: float, a2: float, ma: int, hmax: int) -> np.ndarray:
    """Autocorrelation at lags 0..hmax of ``(1 + z^-1)^ma`` over the AR(2) ``1 - a1 z^-1 - a2 z^-2``
    (a stationary pair), from the AR(2)'s Yule-Walker recursion and the MA part's weights."""
    w = _MA_WEIGHTS[ma]
    H = hmax + len(w)
    r = np.empty(H + 1)
    r[0], r[1] = 1.0, a1 / (1.0 - a2)
    for h in range(2, H + 1):
        r[h] = a1 * r[h - 1] + a2 * r[h - 2]
    if len(w) == 1:
        return r[:hmax + 1]
    full = np.concatenate([r[:0:-1], r])  # lags -H..H
    h = np.arange(hmax + 1) + H
    g = w[0] * full[h]
    for m in range(1, len(w)):
        g = g + w[m] * (full[h - m] + full[h + m])
    return g / g[0]


def _arma_grid() -> list[tuple[float, float]]:
    """AR(2) pairs of the broader colour family: complex poles (radius 0.001-0.999 on a log scale of
    1 - radius, angle up to pi/2: a resonant low-pass) and real pole pairs (one pole 0.001-0.999,
    the other -0.9..0.9)."""
    out = []
    for rad in 1.0 - np.logspace(-3.0, 0.0, 31)[:-1]:
        out += [(2.0 * rad * np.cos(th), -rad ** 2) for th in np.linspace(0.0, np.pi / 2.0, 16)[1:]]
    for p1 in 1.0 - np.logspace(-3.0, 0.0, 31)[:-1]:
        out += [(p1 + p2, -p1 * p2) for p2 in np.linspace(-0.9, 0.9, 13)]
    return out


_ARMA_GAINS: dict = {}


def _arma_gains(lags: np.ndarray) -> tuple[list, np.ndarray, np.ndarray]:
    """For every member of the broader family (AR(2) pair x MA part): its lag-k third-difference
    gain at ``lags`` (rows of the second array) and at half the largest lag (the third), cached per
    lag set."""
    key = tuple(int(k) for k in lags)
    if key not in _ARMA_GAINS:
        kk = np.asarray(key, int)
        half = int(kk[-1] // 2)
        members, gains, at_half = [], [], []
        for a1, a2 in _arma_grid():
            for ma in range(len(_MA_WEIGHTS)):
                r = _arma_acf(a1, a2, ma, 3 * max(kk[-1], half))
                members.append((float(a1), float(a2), ma))
                gains.append(_gain_from_acf(r[kk], r[2 * kk], r[3 * kk]))
                at_half.append(_gain_from_acf(r[half], r[2 * half], r[3 * half]))
        _ARMA_GAINS[key] = (members, np.array(gains), np.array(at_half))
    return _ARMA_GAINS[key]


def _pole_radius(a1: float, a2: float) -> float:
    """The largest pole radius of the AR(2) ``1 - a1 z^-1 - a2 z^-2`` (its memory: ~1/(1 - radius))."""
    return float(np.max(np.abs(np.roots([1.0, -a1, -a2]))))


def arma_unit_std(a1: float, a2: float, ma: int) -> float:
    """Std of ``(1 + z^-1)^ma / (1 - a1 z^-1 - a2 z^-2)`` driven by unit white noise."""
    from scipy.signal import lfilter

    n = int(min(200_000, max(1_000, 30.0 / max(1.0 - _pole_radius(a1, a2), 1e-6))))
    imp = np.zeros(n)
    imp[0] = 1.0
    return float(np.sqrt(np.sum(lfilter(_MA_POLY[ma], [1.0, -a1, -a2], imp) ** 2)))


def broader_colour_noise(rng: np.random.Generator, shape: tuple[int, int], arma: tuple) -> np.ndarray:
    """Unit-variance draws (rows) of the broader colour ``arma = (white share, a1, a2, ma)`` of
    :func:`torque_noise_std`: the white share plus the unit-variance ARMA part, started a settling
    time early so that it is stationary."""
    from scipy.signal import lfilter

    share, a1, a2, ma = arma
    burn = int(min(50_000, 10.0 / max(1.0 - _pole_radius(a1, a2), 1e-4)))
    w = rng.standard_normal((shape[0], shape[1] + burn))
    c = lfilter(_MA_POLY[ma], [1.0, -a1, -a2], w, axis=1)[:, burn:] / arma_unit_std(a1, a2, ma)
    e = rng.standard_normal(shape)
    return np.sqrt(share) * e + np.sqrt(1.0 - share) * c


@dataclasses.dataclass(frozen=True)
class TorqueNoise:
    """The torque channel's noise as estimated from its third differences: ``std`` per sample;
    ``phi`` its lag-1 autocorrelation (the AR(1) coefficient; 0 for white noise); ``arma`` the
    broader colour ``(white share, a1, a2, ma)`` where claimed, else ``()``; ``open`` where the
    profile still rises at its longest lag (:func:`noise_estimate_open`: ``std`` may be a lower
    bound)."""

    std: float
    phi: float = 0.0
    arma: tuple = ()
    open: bool = False


def torque_noise_std(x, jump_std: float | None = 6.0, profile=None,
                     colour_chi2: float = DiagnoseConfig.colour_chi2, signal_var=None) -> TorqueNoise:
    """The per-sample noise std of ``x`` seen through its colour, and the AR(1) coefficient of that
    colour (0: white, the estimate is then :func:`hf_noise_std`), as a :class:`TorqueNoise`.

    The :func:`noise_profile` variances are fitted (weighted by their standard errors) by
    ``sigma^2*g(k, phi) + c*k^6``: a first-order low-passed (AR(1)) noise, whose lag-k third
    difference has variance ``20*sigma^2*g`` (g rises from 1 - 0.9*phi to 1 as k passes the
    correlation length), plus a smooth signal's part. Colour is claimed only when the best phi
    beats phi = 0 by ``colour_chi2`` (:attr:`DiagnoseConfig.colour_chi2`); a drive's averaged torque
    (TRO2021) is such a noise. A broader family is then tried: a white part plus an ARMA part whose
    AR(2) poles are complex (a resonant or second-order low-pass) or real, with no MA zero or one or two
    at the Nyquist frequency (a bilinear-transformed filter's); claimed only when it beats the model
    chosen so far by ``colour_chi2`` again (three more parameters; an AR(1) or white noise keeps its
    estimate), only where its plateau shows (as for AR(1)), and only where the profile rises over its
    first four lags by ``sqrt(colour_chi2)`` standard errors (colour, not a signal's departure from k^6
    at long lags). A second-order low-passed noise, which
    AR(1) reads at half its std, is then read within a few per cent (``tests/test_noise_colour.py``).
    Where the broader model is claimed, ``arma`` holds it and ``phi`` is its lag-1 autocorrelation.
    ``profile``: the :func:`noise_profile` of ``x`` if already computed (with ``jump_std``).
    ``signal_var``: a prediction's :func:`signal_profile` at the profile's lags, a further signal
    column (its shape, where the motion's third differences grow more slowly than k^6), with its
    coefficient in [0, 1]: the prediction's differences hold the signal's plus what the kinematics'
    errors bring through the model, independent of it, so they bound the signal's variance from
    above; the model's own misfit is left to the k^6 column. Unbounded, a prediction whose
    profile saturates as a noise's does (steps, a sweep's fast end) takes the noise's share."""
    from scipy.optimize import lsq_linear, nnls

    white = hf_noise_std(x)
    lags, sd, se = noise_profile(x, jump_std=jump_std) if profile is None else profile
    if lags.size < 3 or white <= 0:
        return TorqueNoise(float(white))
    v = sd ** 2
    sv = np.maximum(2.0 * sd * se, 1e-3 * v)  # std error of each variance
    k = lags.astype(float)

    def fit(phi):
        cols = [_third_difference_gain(k, phi), (k / k[-1]) ** 6]
        if signal_var is None or not np.any(signal_var > 0):
            coef, rnorm = nnls(np.column_stack(cols) / sv[:, None], v / sv)
            return rnorm ** 2, coef[0]
        A = np.column_stack(cols + [np.asarray(signal_var, float) / 20.0]) / sv[:, None]
        sol = lsq_linear(A, v / sv, bounds=([0.0, 0.0, 0.0], [np.inf, np.inf, 1.0]), method="bvls")
        return 2.0 * sol.cost, sol.x[0]

    chi0, _ = fit(0.0)
    # only colours whose plateau the profile shows (g >= 0.9 from half the largest lag on): a longer
    # correlation would be an extrapolation, so the estimate stays a lower bound there
    phis = [phi for phi in 1.0 - np.logspace(-3.0, 0.0, 61)[:-1]
            if _third_difference_gain(k[-1] / 2.0, phi) >= 0.9]
    chosen = (chi0, white ** 2, 0.0, ())
    if phis:
        best = min((fit(phi) + (phi,) for phi in phis), key=lambda r: r[0])
        if chi0 - best[0] >= colour_chi2 and best[1] > white ** 2:
            chosen = (best[0], best[1], best[2], ())
    # the broader family only where the profile rises over its first lags (1 to 4 samples, where a
    # smooth signal's third difference is negligible) by sqrt(colour_chi2) standard errors: a colour
    # shows there, and its extra shapes do not take up a signal's departure from k^6 at long lags
    j = min(3, lags.size - 1)
    rise = (v[j] - v[0]) / float(np.hypot(sv[0], sv[j]))
    broad = _broader_colour(lags, v, sv, k, signal_var) if rise >= np.sqrt(colour_chi2) else None
    if broad is not None and chosen[0] - broad[0] >= colour_chi2 and broad[1] > white ** 2:
        chosen = broad
    return TorqueNoise(float(np.sqrt(chosen[1])), float(chosen[2]), tuple(chosen[3]))


def _broader_colour(lags, v, sv, k, signal_var):
    """The best member of :func:`torque_noise_std`'s broader family on the profile variances ``v``
    (standard errors ``sv``): ``(chi2, variance, lag-1 autocorrelation, (white share, a1, a2, ma))``,
    or None when no member's plateau shows. The white and ARMA variances and the k^6 part are
    non-negative least squares per member (the signal column, where given, bounded by 1)."""
    from scipy.optimize import lsq_linear, nnls

    members, gains, at_half = _arma_gains(lags)
    cols = [np.ones_like(k), None, (k / k[-1]) ** 6]
    with_signal = signal_var is not None and np.any(signal_var > 0)
    if with_signal:
        cols.append(np.asarray(signal_var, float) / 20.0)
    best = None
    for (a1, a2, ma), g, gh in zip(members, gains, at_half):
        cols[1] = g
        A = np.column_stack(cols) / sv[:, None]
        if with_signal:
            sol = lsq_linear(A, v / sv, bounds=([0.0] * 4, [np.inf, np.inf, np.inf, 1.0]), method="bvls")
            coef, chi = sol.x, 2.0 * sol.cost
        else:
            coef, rn = nnls(A, v / sv)
            chi = rn ** 2
        var = coef[0] + coef[1]
        if var <= 0 or (coef[0] + coef[1] * gh) / var < 0.9:
            continue
        if best is None or chi < best[0]:
            share = coef[0] / var
            rho1 = (1.0 - share) * _arma_acf(a1, a2, ma, 1)[1]
            best = (chi, var, rho1, (float(share), a1, a2, ma))
    return best


def noise_estimate_open(x, std: float, profile=None) -> bool:
    """True when the :func:`noise_profile` of ``x`` (or the one given) still lies above ``std`` by
    more than 10 % (and three standard errors) at its longest lag: a colour longer than the profile
    reaches, or the signal there; either way ``std`` may be only a lower bound of the noise."""
    _, prof, se = noise_profile(x) if profile is None else profile
    return bool(prof.size >= 3 and prof[-1] - 3.0 * se[-1] > 1.1 * std)


def torque_noise_model(torque, profile=None, *, colour_chi2: float = DiagnoseConfig.colour_chi2,
                       outlier_std: float = DiagnoseConfig.outlier_std, signal_var=None) -> TorqueNoise:
    """The torque channel's :class:`TorqueNoise` from its :func:`noise_profile` (computed when not
    given): :func:`torque_noise_std`, with ``open`` (:func:`noise_estimate_open`) only where colour was claimed
    (a white estimate is read at lag 1, where the signal is absent, and the longest lags of a white
    recording hold the signal, so the flag would fire on white noise too). ``signal_var``: a
    prediction's signal column (:func:`torque_noise_std`); it only takes signal out of the profile,
    so it may lower the estimate, never raise it: where the fit with it reads higher, it has moved
    the colour's shape instead (a noise whose profile is not AR(1)'s, as a drive's averaged current),
    and the estimate without it stays."""
    profile = noise_profile(torque, outlier_std=outlier_std) if profile is None else profile
    est = torque_noise_std(torque, profile=profile, colour_chi2=colour_chi2)
    if signal_var is not None:
        est = min(est, torque_noise_std(torque, profile=profile, colour_chi2=colour_chi2, signal_var=signal_var),
                  key=lambda m: m.std)
    return dataclasses.replace(est, open=bool(est.phi > 0 and noise_estimate_open(torque, est.std, profile)))


def refined_torque_noise(torque, prediction, std: float, share: float = DiagnoseConfig.resolved_share, *,
                         colour_chi2: float = DiagnoseConfig.colour_chi2,
                         outlier_std: float = DiagnoseConfig.outlier_std) -> TorqueNoise:
    """:func:`torque_noise_model` again, with the lag-k third differences left out where the fitted
    model's ``prediction`` of the torque has its own lag-k third difference above
    ``share`` of the noise's (``std``, the first estimate): there the signal, not the
    noise, sets the difference. The profile's long lags, which tell a colour, otherwise hold the
    motion's fast changes too (a coloured noise at a low rate, where few lags span the correlation,
    reads high by that). What the prediction's kept differences vary by enters the fit as a further
    signal column (:func:`signal_profile`): at long lags few differences are free of the motion, and
    its part there grows more slowly than the k^6 the fit otherwise allows, so its excess would read
    as noise."""
    limit = share * float(np.sqrt(20.0)) * std
    profile = noise_profile(torque, signal=prediction, limit=limit, outlier_std=outlier_std)
    signal_var = signal_profile(torque, prediction, profile[0], limit)
    return torque_noise_model(torque, profile, colour_chi2=colour_chi2, signal_var=signal_var)


def quantisation_step(x) -> float:
    """The encoder step of a quantised signal (the most common smallest non-zero increment), or 0."""
    d = np.abs(np.diff(np.asarray(x, float)))
    d = d[d > 0]
    if d.size < 10:
        return 0.0
    q = float(np.min(d))
    # quantised: (almost) every increment is a whole multiple of the smallest one
    k = d / q
    return q if np.mean(np.abs(k - np.round(k)) < 1e-3) > 0.99 else 0.0


@dataclasses.dataclass(frozen=True)
class Conditioning:
    """How the kinematics were conditioned, and the noise estimated from the data.

    ``torque_noise`` [torque unit] (its colour ``torque_noise_colour``: the AR(1) coefficient
    fitted by :func:`torque_noise_std`, 0 for white noise, or the lag-1 autocorrelation of the
    broader model ``torque_noise_arma`` (white share, a1, a2, MA zeros; empty unless claimed);
    ``torque_noise_open``: the noise is
    coloured and its profile still rises past the estimate at its longest lag, so the estimate may
    be a lower bound), ``velocity_noise`` of the velocity column (0 when there is none) and
    ``position_noise`` (including quantisation, ``q/sqrt(12)``) per sample; ``source``:
    ``recording`` (used as loaded: already smooth enough), ``velocity`` (the column, Savitzky-Golay
    smoothed) or ``position`` (Savitzky-Golay derivatives of the position); ``window`` in samples
    (polynomial ``order``, 3 or 5); ``accel_noise`` and ``velocity_noise_after``: per-sample noise std of the
    conditioned acceleration and velocity; ``accel_noise_torque``: what ``accel_noise`` means in
    torque for the inertia used to choose the window; ``unresolved_fraction``: share of samples
    where the kinematics are not resolved at this smoothing (left out of fit, validation and tests);
    ``blend``: the acceleration is ``a_W + blend*(a_W - a_2W-1)``, the smoothing bias extrapolated
    from the change between the windows W and 2W-1 (:func:`smoothing_blend`; 0: ``a_W`` alone);
    ``bias_nm``: the per-sample bound on the torque the smoothing can leave (:func:`condition`;
    None for kinematics used as loaded), not part of :meth:`to_json`.
    """

    torque_noise: float
    velocity_noise: float
    position_noise: float
    quantisation: float
    source: str
    window: int
    accel_noise_torque: float
    velocity_noise_after: float
    accel_noise: float = 0.0
    unresolved_fraction: float = 0.0
    torque_noise_colour: float = 0.0
    torque_noise_open: bool = False
    torque_noise_arma: tuple = ()
    velocity_measured: bool = True
    position_measured: bool = True
    order: int = 3
    blend: float = 0.0
    bias_nm: np.ndarray | None = dataclasses.field(default=None, repr=False, compare=False)

    def to_json(self) -> dict:
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v
                for f in dataclasses.fields(self) if f.name != "bias_nm"}


def _gain(W, deriv, dt, order=3):
    """Noise gain ||h|| of the Savitzky-Golay derivative filter (white input of unit std)."""
    return float(np.linalg.norm(savgol_coeffs(W, order, deriv=deriv, delta=dt)))


def _accel_filter(cond: "Conditioning", dt: float) -> tuple[np.ndarray, int]:
    """``(h, dv)``: the filter the conditioned acceleration is, applied to the measured velocity
    (``dv`` 0) or position (``dv`` 1): the window W's Savitzky-Golay derivative, blended
    (``a_W + blend*(a_W - a_2W-1)``) when ``cond.blend`` is set."""
    W, dv = cond.window, 0 if cond.source == "velocity" else 1
    h = savgol_coeffs(W, cond.order, deriv=dv + 1, delta=dt)
    if cond.blend:
        h = (1.0 + cond.blend) * np.pad(h, (W - 1) // 2) \
            - cond.blend * savgol_coeffs(2 * W - 1, cond.order, deriv=dv + 1, delta=dt)
    return h, dv


def blended(cond: "Conditioning", blend: float, dt: float) -> "Conditioning":
    """``cond`` with its acceleration blended (``a_W + blend*(a_W - a_2W-1)``): the acceleration's
    noise is then that of the blended filter, ``(1 + blend)*h_W - blend*h_2W-1`` (with ``blend``
    near -1 the wider window's, a third of ``h_W``'s at the same noise), not the window W's; what
    reads it (the inertia's attenuation by errors in variables) needs the noise of the acceleration
    the fit was given."""
    cond = dataclasses.replace(cond, blend=blend)
    if not blend or cond.source == "recording":
        return cond
    h, _ = _accel_filter(cond, dt)
    sig = cond.velocity_noise if cond.source == "velocity" else cond.position_noise
    noise = sig * float(np.linalg.norm(h))
    scale = noise / cond.accel_noise if cond.accel_noise > 0 else 1.0
    return dataclasses.replace(cond, accel_noise=noise, accel_noise_torque=cond.accel_noise_torque * scale)


def _gain_over_derivative(h, dv: int, dt: float, f) -> np.ndarray:
    """The filter ``h``'s gain at frequencies ``f`` [Hz] over the exact derivative of order
    ``dv + 1`` (``h`` applied to a velocity, ``dv`` 0, or a position, ``dv`` 1)."""
    return np.abs(freqz(h, worN=f, fs=1.0 / dt)[1]) / (2 * np.pi * f) ** (dv + 1)


def accel_bandwidth(cond: "Conditioning", dt: float) -> float:
    """Bandwidth [Hz] of the conditioned acceleration: the lowest frequency at which the filter
    it is (:func:`_accel_filter`, blend included) passes less than 1/sqrt(2) of the true
    acceleration's amplitude (its gain over the ideal derivative's). Computed from the filter's
    own coefficients, so it holds for any window, order and blend. A recorded acceleration's sensor
    filter is not known: a quarter of the sampling rate."""
    if cond.source == "recording":
        return 0.25 / dt
    h, dv = _accel_filter(cond, dt)
    f = np.linspace(0.0, 0.5 / dt, 8193)[1:]
    gain = _gain_over_derivative(h, dv, dt, f)
    below = np.flatnonzero(gain < 1.0 / np.sqrt(2.0))
    return float(f[below[0]]) if below.size else 0.5 / dt


def accel_error(cond: "Conditioning", dt: float, f) -> np.ndarray:
    """Relative error ``|1/G(f) - 1|`` of the conditioned acceleration at frequencies ``f`` [Hz]:
    ``G`` the Savitzky-Golay window's gain over the exact derivative's, so a sine of estimated
    amplitude A there is truly ``A/G``. Blended, the larger of the windows W and 2W-1 (the blend's
    coefficient is itself estimated, between or beyond them); unblended, W's. A recorded
    acceleration's sensor filter is not known: 0 (no systematic error claimed)."""
    f = np.atleast_1d(np.asarray(f, float))
    if cond.source == "recording":
        return np.zeros_like(f)
    dv = 0 if cond.source == "velocity" else 1
    out = np.zeros_like(f)
    for W in ((cond.window, 2 * cond.window - 1) if cond.blend else (cond.window,)):
        G = _gain_over_derivative(savgol_coeffs(W, cond.order, deriv=dv + 1, delta=dt), dv, dt, f)
        out = np.maximum(out, np.abs(1.0 / np.maximum(G, 1e-12) - 1.0))
    return out


def memory(cond: "Conditioning") -> int:
    """Samples the conditioned acceleration at one sample draws on: the window, or the wider window
    ``2W-1`` when blended with it."""
    return 2 * cond.window - 1 if cond.blend else cond.window


# Savitzky-Golay polynomial orders the window choice considers: order 5 has less bias at the same
# noise near the excitation's top frequency (an order-3 window attenuates a multisine's top line and
# leaves the rest of it in the residual)
ORDERS = (3, 5)
# ...but its derivative passes a band of noise just below its cut-off, which the time periodogram
# sees as a line; an order-5 window is considered only where the acceleration noise it brings
# (J0 times its noise) is below this share of the torque noise
ORDER5_NOISE_SHARE = 0.5


def condition(rec, J0: float, s2_0: float, max_window_s: float = 0.3, choices=None, error_only: bool = False,
              cfg: DiagnoseConfig | None = None):
    """Choose and condition the kinematics of ``rec``; returns (conditioned recording,
    Conditioning, unresolved mask); with ``error_only``, the chosen window's estimated squared
    torque error (below) only. ``choices``: (source, W, order) triples to choose from (default: every
    measured source and window).

    For each measured source (the velocity column; the position: ``rec.meta``'s
    ``velocity_measured`` / ``position_measured``) each Savitzky-Golay window W and polynomial order (``ORDERS``), the
    torque error that the kinematics bring is estimated as ``J0^2*(4*bias_W^2 + noise_W^2) +
    s2_0^2*noise_v^2``: ``noise_W`` from the estimated per-sample noise through the filter's exact
    gain, ``bias_W^2`` from the change from W to 2W-1 less that change's own noise. The (source, W)
    with the smaller estimate is used; its velocity, acceleration and smoothed position replace the
    recording's. If that is the velocity column at the lightest window, the recording's own
    derivatives are kept as loaded. Where the acceleration came with the data
    (``meta['acceleration_supplied']``, e.g. EMPS: the benchmark's filtered differences at 1 kHz),
    no window change measures its bias, so the data decide between it and the chosen window: the
    one with more resolved samples per unit of the linear inverse model's mean squared residual
    (on the samples both resolve) is used.

    ``cfg``: the diagnosis's settings (the torque-noise estimate's ``colour_chi2`` and
    ``outlier_std``, ``resolved_share``; default :class:`DiagnoseConfig`).

    Unresolved samples: where the per-sample smoothing-bias bound, or the acceleration's
    significant change from a narrower window (:func:`_sharper_than_window`), exceeds
    ``cfg.resolved_share`` of the torque noise (widened by the window), and, with a velocity column,
    sharp transients the sampling cannot resolve (:func:`unresolved_transients`).
    """
    from ..io import Recording

    t = np.asarray(rec.time, float)
    dt = float(np.median(np.diff(t)))
    vel_meas = bool(rec.meta.get("velocity_measured", True))
    pos_meas = bool(rec.meta.get("position_measured", True))
    cfg = DiagnoseConfig() if cfg is None else cfg
    noise = torque_noise_model(rec.torque, colour_chi2=cfg.colour_chi2, outlier_std=cfg.outlier_std)
    st = noise.std
    sv, q, sp, sources = _sources(rec)
    windows = _windows(rec, dt, max_window_s)
    # sharp transients the sampling cannot resolve leave the fit whatever the window (below), so
    # the smoothing bias that chooses the window is measured on the other samples only
    from scipy.ndimage import maximum_filter1d

    sharp = unresolved_transients(rec.velocity, sv) if vel_meas else np.zeros(rec.n, bool)
    best = None
    options = [(source, W, order) for source, *_ in sources for order in ORDERS for W in windows if W > order + 1]
    pool = options if choices is None else choices
    for source, sig, dv, x in sources:
        for W, order in [(W, o) for s_, W, o in pool if s_ == source]:
            W2 = 2 * W - 1
            if W2 > rec.n // 2:
                continue
            hW = savgol_coeffs(W, order, deriv=dv + 1, delta=dt)
            noise2 = sig ** 2 * float(np.sum(hW ** 2))
            if order > 3 and choices is None and J0 * np.sqrt(noise2) > ORDER5_NOISE_SHARE * st:
                continue
            aW = savgol_filter(x, W, order, deriv=dv + 1, delta=dt)
            a2 = savgol_filter(x, W2, order, deriv=dv + 1, delta=dt)
            hd = window_change(W, order, dv + 1, dt)
            # smoothing bias grows with the window (as W^(order+1) for a smooth signal, slower at
            # sharp steps and near the filter's cut-off): the bias at W is taken as a third of the
            # change from W to 2W-1, that change less its own noise (for either order: near the
            # cut-off, where the choice is made, the change is a few times the bias, far below the
            # asymptotic 15 or 63 times)
            smooth = ~(maximum_filter1d(sharp.astype(np.int8), W2) > 0) if sharp.any() else slice(None)
            diff2 = max(float(np.mean((aW - a2)[smooth] ** 2)) - sig ** 2 * float(np.sum(hd ** 2)), 0.0)
            bias2 = diff2 / 9.0
            sig_v = sig * _gain(W, dv, dt, order)
            # bias counts four times: unlike noise it is structured, and the residual tests see it
            # (a located mean after reversals, for one)
            mse = J0 ** 2 * (4 * bias2 + noise2) + s2_0 ** 2 * sig_v ** 2
            if best is None or mse < best[0]:
                best = (mse, source, W, order, sig_v, np.sqrt(noise2), a2, sig * float(np.linalg.norm(hd)))
    if best is None:
        raise ValueError(f"no window among {choices} can condition this recording")
    if error_only:
        return best[0]
    _, source, W, order, sig_v, sig_a, a2, sig_d = best
    common = dict(torque_noise=st, torque_noise_colour=noise.phi, torque_noise_open=noise.open,
                  torque_noise_arma=noise.arma, velocity_noise=sv,
                  position_noise=float(sp), quantisation=q, accel_noise=float(sig_a), velocity_measured=vel_meas,
                  position_measured=pos_meas)
    v, a, th = conditioned_kinematics(t, rec.position, rec.velocity, source, W, order)
    _, sig_src, dv_src, x_src = next(s_ for s_ in sources if s_[0] == source)
    # per-sample bound on the torque the smoothing bias can leave in the residual (for the tests'
    # margins): J0 times a third of the change of the acceleration from W to 2W-1
    bias_nm = np.abs(J0 * (a - a2)) / 3.0
    # only where the change from W to 2W-1 is above its own noise: with noisy kinematics the
    # difference is mostly noise, which the floor's errors-in-variables part already counts
    significant = np.abs(a - a2) > 3.0 * sig_d
    bad = ((bias_nm > cfg.resolved_share * st) & significant) | _sharper_than_window(
        t, x_src, a, dv_src, sig_src, W, order, J0, cfg.resolved_share * st, cfg.alpha)
    bad = maximum_filter1d(bad.astype(np.int8), W) > 0
    if vel_meas:
        bad |= sharp
    if source == "position" and q > 0:
        # a quantised position resolves speeds above one step per window only: below that even the
        # direction of motion is not known from the samples, so neither is the friction
        bad |= maximum_filter1d((np.abs(v) < q / (W * dt)).astype(np.int8), W) > 0
    # the recording's own derivatives: kept as loaded where the lightest velocity window wins
    # a noise-free recording (a simulation's output, DiagnoseConfig.noise_free_share) is used as
    # loaded: no smoothing is needed, and every bias would count
    from ._model import data_scales

    noise_free = st <= cfg.noise_free_share * data_scales(rec)["T"]
    use_recording = vel_meas and q == 0 and (noise_free or (source == "velocity" and W == windows[0]
                                                             and order == 3))
    if vel_meas and q == 0 and not use_recording and rec.meta.get("acceleration_supplied", False):
        # an acceleration that came with the data (e.g. EMPS: computed upstream at ten times the
        # rate) has no window whose change measures its bias; the data decide between it and the
        # chosen window by the information each leaves: its resolved samples over the inverse
        # model's mean squared residual on them (docs/diagnosis.md)
        both = ~sharp & ~bad
        ms_rec = _inverse_residual_ms(rec.velocity, rec.acceleration, rec.torque, both)
        ms_win = _inverse_residual_ms(v, a, rec.torque, both)
        use_recording = (~sharp).mean() / ms_rec > (~bad).mean() / ms_win
    if use_recording:
        sig_a = hf_noise_std(rec.acceleration)
        common["accel_noise"] = float(sig_a)
        info = Conditioning(source="recording", window=1, accel_noise_torque=float(J0 * sig_a),
                            velocity_noise_after=float(sv), unresolved_fraction=float(sharp.mean()), **common)
        return rec, info, sharp
    out = Recording(t, th, v, a, np.asarray(rec.torque, float), rec.units, rec.source, dict(rec.extra), rec.meta)
    info = Conditioning(source=source, window=int(W), order=int(order), accel_noise_torque=float(J0 * sig_a),
                        velocity_noise_after=float(sig_v), unresolved_fraction=float(bad.mean()), bias_nm=bias_nm,
                        **common)
    return out, info, bad


def _sources(rec) -> tuple:
    """The measured kinematic sources of ``rec``: (velocity noise, quantisation step, position noise,
    ``[(source, its noise, derivative order of the velocity, signal)]``)."""
    vel_meas = bool(rec.meta.get("velocity_measured", True))
    pos_meas = bool(rec.meta.get("position_measured", True))
    sv = hf_noise_std(rec.velocity) if vel_meas else 0.0
    q = quantisation_step(rec.position) if pos_meas else 0.0
    sp = max(hf_noise_std(rec.position), q / np.sqrt(12.0)) if pos_meas else 0.0
    sources = ([("velocity", sv, 0, rec.velocity)] if vel_meas else []) + \
              ([("position", sp, 1, rec.position)] if pos_meas else [])
    return sv, q, float(sp), sources


def _windows(rec, dt: float, max_window_s: float) -> list:
    wmax = max(5, int(max_window_s / dt) | 1)
    return [w for w in range(5, wmax + 1, 2) if w <= max(5, rec.n // 4)] or [5]


def window_options(rec, cond: "Conditioning", J0: float, max_window_s: float = 0.3) -> list:
    """The (source, W, order) choices :func:`condition` weighs other than ``cond``'s own (order 5
    where its acceleration noise through the inertia ``J0`` is below ``ORDER5_NOISE_SHARE`` of the
    torque noise)."""
    dt = float(np.median(np.diff(np.asarray(rec.time, float))))
    out = []
    for source, sig, dv, _ in _sources(rec)[3]:
        for order in ORDERS:
            for W in _windows(rec, dt, max_window_s):
                if W <= order + 1 or 2 * W - 1 > rec.n // 2 or (source, W, order) == (cond.source, cond.window,
                                                                                         cond.order):
                    continue
                h = savgol_coeffs(W, order, deriv=dv + 1, delta=dt)
                if order == 3 or J0 * sig * float(np.linalg.norm(h)) <= ORDER5_NOISE_SHARE * cond.torque_noise:
                    out.append((source, W, order))
    return out


def _inverse_residual_ms(v, a, torque, keep) -> float:
    """Mean squared residual of the linear inverse model ``J*a + Fc*sign(v) + sigma2*v + offset``
    plus a Stribeck term (its speed searched on a grid) on the ``keep`` samples: what one set of
    kinematics leaves unexplained, for comparing two sets on the same samples."""
    from ._model import stribeck_ls_grid

    v, a, y = (np.asarray(x, float)[keep] for x in (v, a, torque))
    if y.size < 10:
        return float("inf")
    V = float(np.percentile(np.abs(v), 99)) or 1.0
    return min(sse for _, _, sse in stribeck_ls_grid([a, np.sign(v), v, np.ones_like(v)], v, y, V)) / y.size


def conditioned_kinematics(t, position, velocity, source: str, W: int, order: int = 3, blend: float = 0.0):
    """(velocity, acceleration, bristle path) conditioned from ``source`` (``velocity`` or
    ``position``) with a Savitzky-Golay window ``W`` of polynomial order ``order``; with ``blend``
    the acceleration is ``a_W + blend*(a_W - a_2W-1)`` (:class:`Conditioning`).

    The bristles follow the position path. A coarse encoder jerks z by sigma0*q at every step (see
    docs/diagnosis.md), and smoothing the quantised position makes the path wiggle; so the path is
    complementary: the integral of the conditioned velocity, pulled to the measured position over
    ~4 s. (The measured position, and a measured velocity's own integral, are the other paths the
    baseline fit may choose.)"""
    t = np.asarray(t, float)
    dt = float(np.median(np.diff(t)))
    if source == "velocity":
        v = savgol_filter(velocity, W, order)
        a = savgol_filter(velocity, W, order, deriv=1, delta=dt)
    else:
        v = savgol_filter(position, W, order, deriv=1, delta=dt)
        a = savgol_filter(position, W, order, deriv=2, delta=dt)
    if blend:
        a = a + blend * (a - wider_acceleration(t, position, velocity, source, W, order))
    return v, a, velocity_path(t, position, v)


def velocity_path(t, position, velocity) -> np.ndarray:
    """The bristle path from a velocity: its integral, pulled to ``position`` over ~4 s.

    Given the measured velocity itself (not smoothed) it keeps the path's sharp turns, which a
    smoothing window blurs at steps and reversals; its noise integrates to a random walk that only
    matters where the bristles hold still (dwells, which are left out, :func:`at_rest`): while the
    joint slides, z forgets the path within a few pre-sliding lengths."""
    from scipy.integrate import cumulative_trapezoid
    from scipy.ndimage import uniform_filter1d

    t = np.asarray(t, float)
    pos = np.asarray(position, float)
    iv = np.concatenate([[0.0], cumulative_trapezoid(np.asarray(velocity, float), t)])
    n_lp = max(1, int(4.0 / float(np.median(np.diff(t))))) | 1
    return iv + uniform_filter1d(pos - iv, min(n_lp, (pos.size // 2) | 1), mode="nearest")


def _sharper_than_window(t, x, a, dv: int, sig: float, W: int, order: int, J0: float, share_nm: float,
                         alpha: float) -> np.ndarray:
    """Samples whose acceleration the window ``W`` smooths by more than ``share_nm`` of torque
    (through ``J0``), seen against narrower windows (``W`` halved down to 5 samples): where the
    change from a narrower window exceeds its own noise at a family-wise ``alpha`` over the
    recording's samples and those windows (Bonferroni over ``n/w`` independent stretches per window
    ``w``, two-sided). The change from W to 2W-1 misses a motion sharper than either window (a step
    the loop makes in a few samples: both windows smear it nearly alike, while the truth differs
    from both by many times the noise); a narrower window resolves it at more noise, so only a
    change beyond that noise counts. ``x``: the source signal, ``a`` its acceleration at ``W`` (no
    blend), ``dv`` its derivative order below the velocity, ``sig`` its per-sample noise (white)."""
    from scipy.stats import norm

    dt = float(np.median(np.diff(t)))
    ws = []
    w = W
    while (w := (w // 2) | 1) >= max(5, order + 2):
        ws.append(w)
    out = np.zeros(np.shape(x), bool)
    if not ws:
        return out
    z = float(norm.isf(alpha / 2.0 / sum(len(x) / w for w in ws)))
    for w in ws:
        change = a - savgol_filter(x, w, order, deriv=dv + 1, delta=dt)
        noise = sig * float(np.linalg.norm(window_change(W, order, dv + 1, dt, w)))
        out |= (J0 * np.abs(change) > share_nm) & (np.abs(change) > z * noise)
    return out


def window_change(W: int, order: int, deriv: int, dt: float, other: int | None = None) -> np.ndarray:
    """Coefficients of the change of a Savitzky-Golay derivative (order ``deriv``) between the window
    ``W`` and ``other`` (default ``2W-1``; wider or narrower, the shorter padded): white noise of
    std ``sig`` on the input moves that change by ``sig * ||h||``."""
    other = 2 * W - 1 if other is None else other
    n = max(W, other)
    h = [np.pad(savgol_coeffs(w, order, deriv=deriv, delta=dt), (n - w) // 2) for w in (W, other)]
    return h[0] - h[1]


def wider_acceleration(t, position, velocity, source: str, W: int, order: int = 3) -> np.ndarray:
    """The acceleration :func:`conditioned_kinematics` gives at the window ``2W-1`` (no blend, no
    bristle path): the reference the smoothing bias at ``W`` is measured against."""
    x, dv = (velocity, 0) if source == "velocity" else (position, 1)
    return savgol_filter(x, 2 * W - 1, order, deriv=dv + 1, delta=float(np.median(np.diff(np.asarray(t, float)))))


def friction_smoothing_error(t, friction, cond: "Conditioning") -> np.ndarray:
    """What the inertial torque's smoothing leaves in an inverse model's residual where the friction
    changes fast: ``J*(a - a_cond)`` for an acceleration ``a = (u - friction)/J`` whose motor torque
    ``u`` is smooth (a controller's output), so that the acceleration carries the friction's own
    sharp changes (a reversal's switch, a breakaway) and the conditioned one ``a_cond`` blurs them.
    The conditioning itself (:func:`conditioned_kinematics`, ``cond``'s source, window, order and
    blend) is applied to the friction's integral as a velocity and its double integral as a position:
    the result is its blur of ``friction`` less ``friction``."""
    from scipy.integrate import cumulative_trapezoid

    t = np.asarray(t, float)
    f = np.asarray(friction, float)
    # on the uniform grid the conditioning's filters assume (its median step): a gap in the time
    # stamps (chained runs) would otherwise integrate the friction over the gap into a jump
    tu = t[0] + float(np.median(np.diff(t))) * np.arange(t.size)
    v = np.concatenate([[0.0], cumulative_trapezoid(f, tu)])
    theta = np.concatenate([[0.0], cumulative_trapezoid(v, tu)])
    return conditioned_kinematics(t, theta, v, cond.source, cond.window, cond.order, cond.blend)[1] - f


def model_bias_unresolved(rec_in, cond: "Conditioning", kin, predict,
                          share: float = DiagnoseConfig.resolved_share) -> np.ndarray:
    """Samples where the whole model's torque changes by more than the resolved share when its
    velocity and acceleration come from the window ``2W-1`` instead: the smoothing-bias rule of
    :func:`condition` (a third of the change from W to 2W-1 above ``share`` of the
    torque noise, where the change is above three times its own noise; widened by the window),
    with the model's torque in place of ``J0*a``. Near a slow reversal a smoothed velocity moves
    the friction through its Stribeck slope and bristles by many times the noise, where ``J0*a``
    barely changes. Not applied to the recording's own derivatives or to those of a quantised
    position. ``predict``: the fitted model's torque along kinematics like ``kin``."""
    import equinox as eqx
    import jax.numpy as jnp
    from scipy.ndimage import maximum_filter1d

    # derivatives of a quantised position: the change from W to 2W-1 is then the steps' structured
    # error as much as the window's bias (not white, so its noise bound does not hold), and the
    # speeds an encoder does not resolve are already left out (:func:`condition`)
    if cond.source == "recording" or (cond.source == "position" and cond.quantisation > 0):
        return np.zeros(np.shape(kin.v), bool)
    t = np.asarray(rec_in.time, float)
    dt = float(np.median(np.diff(t)))
    W, order = cond.window, cond.order
    x, dv, sig = ((rec_in.velocity, 0, cond.velocity_noise) if cond.source == "velocity"
                  else (rec_in.position, 1, cond.position_noise))
    v2 = savgol_filter(x, 2 * W - 1, order, deriv=dv, delta=dt)
    a2 = wider_acceleration(t, rec_in.position, rec_in.velocity, cond.source, W, order)
    kin2 = eqx.tree_at(lambda k: (k.v, k.a), kin, (jnp.asarray(v2), jnp.asarray(a2)))
    bias_nm = np.abs(np.asarray(predict(kin)) - np.asarray(predict(kin2))) / 3.0

    def change_noise(deriv):
        return sig * float(np.linalg.norm(window_change(W, order, deriv, dt)))

    significant = (np.abs(np.asarray(kin.v) - v2) > 3.0 * change_noise(dv)) | \
                  (np.abs(np.asarray(kin.a) - a2) > 3.0 * change_noise(dv + 1))
    bad = (bias_nm > share * cond.torque_noise) & significant
    return maximum_filter1d(bad.astype(np.int8), W) > 0


def perturbed_kinematics(rec_in, cond: "Conditioning", path: str, seed: int = 0):
    """One draw of the errors in variables: ``(synthetic, reference)``, each ``(v, a, bristle
    path)``, built from the measured signals exactly as the fit's kinematics are (``cond``'s source
    and window; ``path``: ``measured``, ``complementary`` or ``velocity``), the synthetic one from measurements
    carrying fresh errors of the kind and size estimated from the data. The model's prediction on
    the synthetic minus that on the reference is one draw of what the kinematics' errors bring into
    the residual.

    Each error is imitated in kind, since the bristles respond to its shape, not only its size:
    white noise on a velocity column (and its integral where it is the only sensor: the path is
    then a random walk); on a quantised position, the smooth path re-quantised on a randomly
    shifted grid (a staircase with steps where the joint crosses them, against that smooth path as
    reference: a white dither of one step would drive the bristles as a real dither does); white
    noise on an unquantised position."""
    from scipy.integrate import cumulative_trapezoid

    from ..io import derive_kinematics

    rng = np.random.default_rng(seed)
    t = np.asarray(rec_in.time, float)
    pos = np.asarray(rec_in.position, float)
    vel = np.asarray(rec_in.velocity, float)
    pos_ref, vel_ref = pos, vel
    vel_syn = vel + rng.standard_normal(vel.size) * cond.velocity_noise if cond.velocity_measured else vel
    if cond.position_measured and cond.quantisation > 0:
        q = cond.quantisation
        # the smooth path: the complementary one (velocity where measured, else the position's
        # derivative at the chosen window) pulled to the encoder over seconds
        src = "velocity" if cond.velocity_measured else "position"
        pos_ref = conditioned_kinematics(t, pos, vel, src, max(cond.window, 5))[2]
        u = rng.uniform(0.0, q)
        pos_syn = q * np.round((pos_ref + u) / q) - u
    elif cond.position_measured:
        pos_syn = pos + rng.standard_normal(pos.size) * cond.position_noise
    else:
        pos_syn = pos + np.concatenate([[0.0], cumulative_trapezoid(vel_syn - vel, t)])
    if not cond.velocity_measured:
        vel_ref, vel_syn = np.gradient(pos_ref, t), np.gradient(pos_syn, t)

    def build(p, v_in):
        if cond.source == "recording":
            return v_in, derive_kinematics(t, v_in), p
        v, a, th = conditioned_kinematics(t, p, v_in, cond.source, cond.window, cond.order, cond.blend)
        if path == "velocity":
            th = velocity_path(t, p, v_in)
        return v, a, (p if path == "measured" else th)

    return build(pos_syn, vel_syn), build(pos_ref, vel_ref)


def at_rest(velocity, velocity_noise: float, alpha: float, min_run: int = 1) -> np.ndarray:
    """Samples of the dwells: runs of at least ``min_run`` samples whose conditioned velocity is not
    told from rest at level ``alpha`` (two-sided, against its noise std ``velocity_noise``). In a
    dwell LuGre's bristle state is set by presliding displacements too small to measure and by the
    history before the stop, so it cannot be computed from the kinematics: a correct inverse model
    misses the friction there by up to the breakaway level, a structured error no candidate may
    claim. A shorter run is a passage through zero, whose path the kinematics do resolve, and a run
    whose mean velocity is told from zero a creep, whose sliding state they resolve too."""
    from scipy import ndimage, stats

    v = np.asarray(velocity, float)
    z, sv = stats.norm.isf(alpha / 2.0), max(float(velocity_noise), 0.0)
    still = np.abs(v) < z * sv
    if min_run > 1 and still.any():
        # a dwell's own noise lifts alpha of its samples over the bound, in excursions of up to a
        # window: gaps shorter than min_run between still samples are closed first
        gaps, _ = ndimage.label(~still)
        size = np.bincount(gaps)
        inner = (gaps > 0) & (gaps != gaps[0]) & (gaps != gaps[-1])
        still = still | (inner & (size[gaps] < min_run))
        runs, _ = ndimage.label(still)
        size = np.bincount(runs)
        # a slow creep whose velocity each window cannot tell from zero still travels: a run is a
        # dwell when its mean velocity is not told from zero either, against the mean's noise (the
        # smoothed velocity's errors are correlated over about a window, so ~size/min_run of them
        # are independent)
        mean = np.bincount(runs, weights=v) / np.maximum(size, 1)
        se = sv * np.sqrt(min_run / np.maximum(size, 1))
        dwell = (size >= min_run) & (np.abs(mean) < z * se)
        still = (runs > 0) & dwell[runs]
    return still


def forget_after(mask, position, length: float) -> np.ndarray:
    """``mask`` widened forward: after each masked run, until the joint has travelled ``length``
    along its path (the bristles' memory: LuGre's z forgets its past over a few relaxation lengths
    Fs/sigma0 of travel)."""
    mask = np.asarray(mask, bool)
    s = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(np.asarray(position, float))))])
    last = np.maximum.accumulate(np.where(mask, np.arange(mask.size), -1))
    return mask | ((last >= 0) & (s - s[np.maximum(last, 0)] < length))


def unresolved_transients(velocity, sv: float, pad: int = 4) -> np.ndarray:
    """Samples where the velocity is not smooth at the sampling rate (a sharp step the loop follows
    within a sample or two): there no estimate of the acceleration from samples exists, and the
    inverse model's J*a is wrong by the unresolved impulse. Flagged where the velocity departs from
    its 5-sample cubic fit by more than 4 noise std (and 0.3 % of its range), widened by ``pad``
    samples."""
    from scipy.ndimage import maximum_filter1d

    v = np.asarray(velocity, float)
    if v.size < 10:
        return np.zeros(v.shape, bool)
    V = float(np.percentile(np.abs(v), 99)) or 1.0
    dev = np.abs(v - savgol_filter(v, 5, 3))
    bad = dev > max(4.0 * sv, 3e-3 * V)
    return maximum_filter1d(bad.astype(np.int8), 2 * pad + 1) > 0


def smoothing_blend(rec_in, crec, cond: Conditioning, J: float, residual, train, val) -> float:
    """The share of ``a_W - a_2W-1`` to add to the conditioned acceleration, from the torque.

    A Savitzky-Golay derivative's bias grows with its window, so the true acceleration is about
    ``a_W + beta*(a_W - a_2W-1)``; the baseline's residual then holds ``J*beta*(a_W - a_2W-1)``.
    ``beta`` is that column's least-squares coefficient on the ``train`` samples of ``residual``
    (torque less the baseline fitted to ``a_W``), used only where it lowers the residual's mean
    square on the held-out ``val`` samples; 0 otherwise, or when the data are used as loaded."""
    if cond.source == "recording" or 2 * cond.window - 1 >= rec_in.n // 2:
        return 0.0
    a2 = wider_acceleration(rec_in.time, rec_in.position, rec_in.velocity, cond.source, cond.window, cond.order)
    col = float(J) * (np.asarray(crec.acceleration, float) - a2)
    r = np.asarray(residual, float)
    den = float(np.sum(col[train] ** 2))
    if not (den > 0 and np.any(val)):
        return 0.0
    beta = float(np.sum(r[train] * col[train])) / den
    return beta if np.mean((r - beta * col)[val] ** 2) < np.mean(r[val] ** 2) else 0.0
