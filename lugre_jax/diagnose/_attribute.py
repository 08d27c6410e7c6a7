"""Attribute a residual no candidate explains to the recorded signals: which ones it follows, in
what form, and how much of the held-out misfit that term removes.

A stated library of term groups, each a dependence with a standard physical reading (below).
Groups are added greedily, as the candidates are: each step tests every group's first-order gain
``||P_{G|B} r||^2`` (B: the current model's Jacobian columns and the groups already in) against the
same simulated null as the candidates (:mod:`._calibrate`; the time line's frequency search
repeated on every draw), family-wise by min-P at the attribution's share of alpha, and keeps the
most significant group only if its least-squares term lowers the held-out RMSE significantly:
cross-validated over the block phases a candidate's held-out test crosses (:func:`cv_gains`), every
group's held-out gain against the same gain on every null draw, family-wise by min-P over the
groups at the same share of alpha. The group is chosen on the training blocks, which the
cross-validation reuses; the min-P over all groups holds the test's level whichever group the
choice took (each draw's largest gain is inside its minimum). What smoothing the true motion leaves through
the model is held by the nuisance columns (the acceleration's blur where the friction changes fast:
:func:`._condition.friction_smoothing_error`), so the calibrated tests alone decide; the held-out
share ``sqrt(before^2 - after^2)`` is reported. The terms are linear in
their coefficients, so the first-order gain is the exact least-squares gain.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import _calibrate as C
from . import _model as M


@dataclasses.dataclass(frozen=True)
class TermGroup:
    """One dependence: ``name``, the columns' ``labels`` and ``units``, the ``reading``; for a
    one-column group whose physics depends on the sign, ``reading_negative`` where its coefficient is
    negative (:meth:`read`)."""

    name: str
    labels: tuple
    units: tuple
    reading: str
    reading_negative: str = ""

    def read(self, coef) -> str:
        """The reading that the fitted coefficients' sign supports."""
        if self.reading_negative and len(coef) == 1 and float(coef[0]) < 0:
            return self.reading_negative
        return self.reading


def _smooth_derivative(x, t, window: int):
    from scipy.signal import savgol_filter

    dt = float(np.median(np.diff(t)))
    w = max(5, int(window) | 1)
    return savgol_filter(np.asarray(x, float), w, 3, deriv=1, delta=dt) if x.size > w else np.gradient(x, t)


def library(ctx, kin, model_torque, window: int) -> list[tuple[TermGroup, np.ndarray]]:
    """The term library along the kinematics ``kin`` (each group's columns, full length), except
    the time line, whose frequency is searched on the residual (:func:`_time_line`)."""
    rec = ctx.rec
    u = rec.units
    t = np.asarray(rec.time, float)
    v = np.asarray(kin.v, float)
    a = np.asarray(kin.a, float)
    th = np.asarray(kin.theta, float)
    T, tu, pu = u["torque"], u["time"], u["position"]
    V = ctx.scales["V"]
    tau_rate = _smooth_derivative(model_torque, t, window)
    jerk = _smooth_derivative(a, t, window)
    out = [
        (TermGroup("torque_rate", ("d(tau_model)/dt",), (f"{tu}",),
                   "follows the torque's rate: actuator dynamics (a current loop's lag) or a delay"), tau_rate[:, None]),
        (TermGroup("velocity_squared", ("v*|v|",), (f"{T}*{tu}^2/{pu}^2",),
                   "grows with v|v|: fluid or windage drag",
                   "falls with v|v|: friction growing slower than linearly with speed (a viscous part that "
                   "saturates)"), (v * np.abs(v))[:, None]),
        (TermGroup("transmitted_torque", ("|tau_model|*sign(v)",), ("1",),
                   "grows with the transmitted torque: load-dependent (mesh, screw) friction",
                   "falls with the transmitted torque: friction that lessens under load"),
         (np.abs(model_torque) * np.tanh(v / (0.01 * V)))[:, None]),
        # the measured torque leading the joint's by d adds d*(J*jerk + dF/dt): a lag or delay reads
        # here as well as in the torque's rate, and on a heavy joint the smooth jerk fits it better
        # than the differentiated, noisy torque; a compliant transmission adds the fourth
        # derivative instead (J_load^2/k), not the jerk
        (TermGroup("jerk", ("jerk",), (f"{T}*{tu}^3/{pu}",),
                   "follows the jerk: the torque reaches the joint late (actuator dynamics or a delay, "
                   "lag about coefficient / J) or the kinematics are recorded late against the torque",
                   "falls with the jerk: the torque is recorded late against the kinematics (a torque "
                   "sensor's or filter's delay, about -coefficient / J)"), jerk[:, None]),
        (TermGroup("time", ("t - t_mid",), (f"{T}/{tu}",),
                   "drifts with time: a slowly changing offset (temperature, a sensor's drift)"),
         (t - 0.5 * (t[0] + t[-1]))[:, None]),
        (TermGroup("position", ("theta - mean",), (f"{T}/{pu}",),
                   "follows the position: a spring, a cable or an unmodelled load"), (th - th.mean())[:, None]),
    ]
    return out


TIME_LINE = TermGroup("time_periodic", ("sin(2*pi*f*t)", "cos(2*pi*f*t)"), ("1", "1"),
                      "periodic in time, not tied to the motion: an external disturbance")


def _time_line_freqs(t, R, rows, min_periods: float = 3.0, oversample: int = 4, iters: int = 16):
    """Frequency of the strongest line of each residual's periodogram between ``min_periods``
    periods in the recording and a quarter of the sample rate (rows: residuals, full length): the
    strongest ordinate on a grid ``oversample`` times finer than the Fourier frequencies, then the
    periodogram's maximum within one grid step either side (golden section, ``iters`` steps). A
    frequency off by a fraction ``e`` of a Fourier bin leaves a sine whose phase drifts by
    ``+-pi*e`` over the recording, and the remainder is structure a later term takes up."""
    from ._locate import _power

    R = np.atleast_2d(np.asarray(R, float))
    dt, n = float(np.median(np.diff(t))), R.shape[1]
    f, P = _power(t, R, oversample)
    band = (f >= min_periods / float(t[-1] - t[0])) & (f <= 0.25 / dt)
    if not band.any():
        return np.zeros(R.shape[0])
    f0 = f[band][np.argmax(P[:, band], axis=1)]
    tt = np.arange(n) * dt  # the periodogram's own clock (uniform samples)
    # demodulated at each row's grid frequency and summed over short blocks: within one grid step
    # the phase turns by at most pi/2 over the recording, so by at most pi/(4*blocks) in a block
    z = (R - R.mean(axis=1, keepdims=True)) * np.exp(-2j * np.pi * f0[:, None] * tt[None, :])
    starts = np.linspace(0, n, min(n, 2048), endpoint=False).astype(int)
    Z = np.add.reduceat(z, starts, axis=1)
    tb = 0.5 * (tt[starts] + tt[np.append(starts[1:], n) - 1])

    def power(fr):
        return np.abs(np.sum(Z * np.exp(-2j * np.pi * (fr - f0)[:, None] * tb[None, :]), axis=1)) ** 2

    step = 1.0 / (oversample * n * dt)
    g = (np.sqrt(5.0) - 1.0) / 2.0
    a, b = f0 - step, f0 + step
    c, d = b - g * (b - a), a + g * (b - a)
    pc, pd = power(c), power(d)
    for _ in range(iters):
        left = pc > pd  # the maximum lies in [a, d]
        a, b = np.where(left, a, c), np.where(left, d, b)
        x = np.where(left, b - g * (b - a), a + g * (b - a))
        px = power(x)
        c, d, pc, pd = (np.where(left, x, d), np.where(left, c, x), np.where(left, px, pd),
                        np.where(left, pc, px))
    fr = 0.5 * (a + b)
    return np.where(power(fr) >= power(f0), fr, f0)


def _sincos(t, f):
    return np.column_stack([np.sin(2 * np.pi * f * t), np.cos(2 * np.pi * f * t)])


def motion_lines(t, v, alpha: float, max_lines: int = 64) -> np.ndarray:
    """Frequencies of the motion's spectral lines: ordinates of the velocity's Hann-tapered periodogram
    beyond its local median background at family-wise ``alpha`` (Bonferroni over the ordinates, the
    median's own spread allowed for as in :func:`._locate._time_lines`), taken strongest first, each
    placed at its transform's peak within a Fourier bin and fitted out with the lines before it (so
    neither its side lobes nor its neighbours' leakage count; the taper keeps a line's leakage below
    the noise a few bins away, where the median looks). A linear error of the measured kinematics
    (smoothing, a delay, a sensor's dynamics) puts a sinusoid at every motion line into the
    residual, so a disturbance periodic in time is not identifiable there."""
    from ._locate import _local_background, line_logp

    t = np.asarray(t, float)
    x = np.asarray(v, float) - float(np.mean(v))
    if x.size < 16 or not np.all(np.isfinite(x)):
        return np.zeros(0)
    w = np.hanning(x.size)
    sw = np.sqrt(w)
    f = np.fft.rfftfreq(x.size, float(np.median(np.diff(t))))[1:]
    bound = np.log(alpha / f.size)
    lines: list[float] = []
    # the lines are fitted by least squares weighted by the taper (unweighted, the lines not yet
    # found leak into the fitted ones' amplitudes and leave remainders that read as lines), kept as
    # an orthonormal basis Q of the weighted columns so each line costs one projection
    y = sw * x
    Q = np.zeros((x.size, 0))
    bg = None
    while len(lines) < max_lines:
        P = np.abs(np.fft.rfft(sw * y))[1:] ** 2 / np.sum(w ** 2)  # the residual's tapered periodogram
        if bg is None:
            # the background of what is left: lines crowded within a median's window (a
            # multisine's low end) raise it until the lines among them are fitted out
            bg, used = _local_background(P, 200)
            n_before = len(lines)
        logp = line_logp(P, bg, used)[1]
        k = int(np.argmin(logp))
        if logp[k] > bound:
            if len(lines) == n_before:
                break
            bg = None
            continue
        lines.append(_peak(t, sw * y, f[k], f[0]))
        c = sw[:, None] * _sincos(t, lines[-1])
        for _ in range(2):
            c = c - Q @ (Q.T @ c)
        q = C._orth(c)
        Q = np.column_stack([Q, q])
        y = y - q @ (q.T @ y)
    return np.asarray(lines)


def _peak(t, y, f0: float, df: float) -> float:
    """The frequency within a Fourier bin ``df`` of ``f0`` where ``y``'s transform peaks, to a
    millionth of a bin: a strong line fitted out at a frequency off by a fraction of a bin leaves
    a remainder at its side that is itself a line above the background."""
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(lambda fl: -abs(np.sum(np.exp(-2j * np.pi * fl * t) * y)),
                          bounds=(f0 - df, f0 + df), method="bounded", options={"xatol": 1e-6 * df})
    return float(res.x)


def _off_lines(X, M, rows):
    """The columns ``X`` (every sample) less their least-squares fit on the training ``rows`` by the
    motion lines' columns ``M``: what of them a linear kinematic error cannot make."""
    X = np.atleast_2d(np.asarray(X, float).T).T
    if M is None or M.shape[1] == 0:
        return X
    c, *_ = np.linalg.lstsq(M[rows], X[rows], rcond=None)
    return X - M @ c


def _time_line(t, f, lines, rows):
    """The time line's columns at frequency ``f``, off the motion's ``lines`` (fitted on ``rows``)."""
    return _off_lines(_sincos(t, f), lines, rows)


def _line_columns(t, lines) -> np.ndarray | None:
    return np.column_stack([_sincos(t, fl) for fl in lines]) if len(lines) else None


def kinematic_lines(model, kin, t, r, rows, freqs, cond) -> np.ndarray | None:
    """The columns (sin, cos) of the motion's lines ``freqs`` (:func:`motion_lines`) at which the
    residual ``r`` is no larger than the error the conditioned acceleration's filter makes there
    (the model's inertial torque's amplitude at the line times :func:`._condition.accel_error`;
    amplitudes fitted jointly on the training ``rows``). A disturbance in a closed loop puts a line
    into the motion too, but one the loop rejects: its residual there is the disturbance, larger
    than any error of the motion's small acceleration at that line."""
    from ._condition import accel_error

    if cond is None or freqs is None:
        return None
    lines = _line_columns(t, freqs)
    if lines is None:
        return None
    inertial = np.asarray(M._parts(model, kin)[0], float)
    c, *_ = np.linalg.lstsq(lines[rows], np.column_stack([inertial, r])[rows], rcond=None)
    amp = np.hypot(c[0::2], c[1::2])  # lines x (inertial torque, residual)
    err = accel_error(cond, float(np.median(np.diff(t))), freqs)
    keep = np.repeat(err * amp[:, 0] >= amp[:, 1], 2)
    return lines[:, keep] if keep.any() else None


def fold_masks(keep, blocks, folds) -> list:
    """The samples of each cross-validated phase of ``folds`` among ``keep`` (one mask per phase)."""
    phase = M.block_phase(blocks)
    return [keep & (phase == j) for j in folds]


def cv_gains(base, Xs, e, keep, folds_m) -> np.ndarray:
    """Each term's cross-validated held-out gain on the residual ``e``: over the phases ``folds_m``
    (masks within ``keep``), ``sum(r0^2 - r1^2)`` on each phase, ``r0`` its residual after
    ``base``'s columns fitted on the other kept samples, ``r1`` the same with the term's columns
    (one ``X`` of ``Xs``) added. Computed from each phase's cross-products, so that one pass over
    the samples serves every term and phase; ``e`` may hold several residuals (n x m: gains
    len(Xs) x m). The columns are put on unit norm and directions below 1e-6 of the largest
    singular value dropped."""
    A = np.column_stack([base] + list(Xs))
    e = np.asarray(e, float)
    E = e.reshape(e.shape[0], -1)
    Ak = A[keep]
    norm = np.sqrt(np.einsum("ij,ij->j", Ak, Ak))
    norm[norm == 0] = 1.0
    A, Ak = A / norm, Ak / norm
    S, s = Ak.T @ Ak, Ak.T @ E[keep]
    kb = base.shape[1]
    ends = kb + np.cumsum([X.shape[1] for X in Xs])
    idx = [np.arange(kb)] + [np.r_[np.arange(kb), np.arange(e1 - X.shape[1], e1)] for X, e1 in zip(Xs, ends)]
    out = np.zeros((len(Xs), E.shape[1]))
    for m in folds_m:
        Am, Em = A[m], E[m]
        Sm, sm, qm = Am.T @ Am, Am.T @ Em, np.einsum("ij,ij->j", Em, Em)
        sse = [_fold_sse(S - Sm, s - sm, Sm, sm, qm, i) for i in idx]
        out += sse[0] - np.asarray(sse[1:])
    return out if e.ndim > 1 else out[:, 0]


def _fold_sse(Sf, sf, Sm, sm, qm, i) -> np.ndarray:
    """Held-out sums of squares of one phase (cross-products ``Sm``, ``sm``, ``qm``; one per
    residual) after the columns ``i`` fitted on the rest (``Sf``, ``sf``): a pseudo-inverse of
    their Gram matrix."""
    w, V = np.linalg.eigh(Sf[np.ix_(i, i)])
    ok = w > max(float(w[-1]), 1e-300) * 1e-12
    beta = V[:, ok] @ ((V[:, ok].T @ sf[i]) / w[ok][:, None])
    return qm - 2.0 * np.sum(beta * sm[i], axis=0) + np.sum(beta * (Sm[np.ix_(i, i)] @ beta), axis=0)


def cv_residual(D, r, keep, folds_m) -> np.ndarray:
    """``r`` less ``D``'s columns fitted, for each phase of ``folds_m``, on the other kept
    samples, on that phase (0 elsewhere): the residual :func:`cv_gains` scores. ``D`` may be a
    function of the fit's samples (columns that are themselves chosen on them)."""
    out = np.zeros_like(r)
    for m in folds_m:
        fit = keep & ~m
        Dm = D(fit) if callable(D) else D
        out[m] = (r - Dm @ _lstsq(Dm, r, fit))[m]
    return out


def _lstsq(A, r, rows) -> np.ndarray:
    """Least squares of ``r`` on ``A``'s columns over ``rows``, as :func:`cv_gains` fits: the columns
    on unit norm over those rows and directions below 1e-6 of the largest singular value dropped (a
    column nearly empty on the fit's samples would otherwise take a coefficient that the held-out
    samples, where it is not empty, turn into an error of any size)."""
    Ar = A[rows]
    norm = np.sqrt(np.einsum("ij,ij->j", Ar, Ar))
    norm[norm == 0] = 1.0
    beta, *_ = np.linalg.lstsq(Ar / norm, r[rows], rcond=1e-6)
    return beta / norm


def _held_out(X, base, r, rows, val):
    """The term ``X`` fitted on the training ``rows`` with the ``base`` columns (the model's
    linearised refit and the terms already in): (its RMSE on the fixed held-out phase ``val``, the
    prediction, the coefficients)."""
    Xall = np.column_stack([base, X])
    beta = _lstsq(Xall, r, rows)
    pred = Xall @ beta
    return float(np.sqrt(np.mean((r - pred)[val] ** 2))), pred, beta


@dataclasses.dataclass(frozen=True)
class Attribution:
    """The terms found, in order: each group's name, labels, coefficients, units, reading, its
    family-wise p-value and gain; the held-out RMSE before and after the terms on the fixed
    held-out phase (least squares on the training blocks, so ``before`` is
    ``Improved.fixed_phase_rmse_nm``) and cross-validated over the phases the test crosses (the
    terms with the model's linearised refit; ``cv_rmse_*``); ``tests``: every step's per-group statistics. ``fits`` and ``partials`` (per
    term, every sample): the term's torque in the joint least squares of all terms with the model's
    linearised refit on the training blocks, and the residual with that refit and the other terms
    taken out (a partial residual: what the term is fitted to, which its coefficient alone against
    the raw residual is not, since the refit takes part of its shape)."""

    terms: tuple
    validation_rmse_before_nm: float
    validation_rmse_after_nm: float
    tests: tuple
    columns: tuple = dataclasses.field(default=(), repr=False, compare=False)  # each term's regressors (n x k)
    fits: tuple = dataclasses.field(default=(), repr=False, compare=False)
    partials: tuple = dataclasses.field(default=(), repr=False, compare=False)
    cv_rmse_before_nm: float = float("nan")
    cv_rmse_after_nm: float = float("nan")
    fit_rms_nm: tuple = ()  # each term's fit, rms over the kept samples
    sum_rms_nm: float = float("nan")  # the terms' fits summed, rms over the kept samples

    @property
    def found(self) -> bool:
        return bool(self.terms)

    @property
    def signals(self) -> list[str]:
        return [t["signal"] for t in self.terms]

    @property
    def nearly_cancel(self) -> bool:
        """Whether the terms' joint fits sum to under :data:`CANCEL_SHARE` of their quadrature sum:
        nearly collinear terms (jerk and the torque's rate, both mostly J*jerk) take large
        coefficients of opposite sign, and the data determine only their sum, not each."""
        return len(self.fit_rms_nm) > 1 and self.sum_rms_nm < CANCEL_SHARE * float(np.hypot.reduce(self.fit_rms_nm))

    def to_json(self) -> dict:
        terms = [{**t, "fit_rms_nm": f} for t, f in zip(self.terms, self.fit_rms_nm)] if self.fit_rms_nm \
            else list(self.terms)
        return {"signals": self.signals, "terms": terms,
                "validation_rmse_before_nm": self.validation_rmse_before_nm,
                "validation_rmse_after_nm": self.validation_rmse_after_nm,
                "cv_rmse_before_nm": self.cv_rmse_before_nm, "cv_rmse_after_nm": self.cv_rmse_after_nm,
                **({"terms_sum_rms_nm": self.sum_rms_nm, "terms_nearly_cancel": self.nearly_cancel}
                   if self.fit_rms_nm else {}),
                "tests": list(self.tests)}


def term_sizes(fits, keep) -> tuple[tuple, float]:
    """Each term's joint fit and the fits summed, rms over the kept samples ``keep``
    (``Attribution.fit_rms_nm`` and ``sum_rms_nm``)."""
    return tuple(_rms(f, keep) for f in fits), (_rms(np.sum(fits, axis=0), keep) if fits else float("nan"))


def cancel_words(sizes, sum_rms: float, unit: str) -> str:
    """The report's words for terms that nearly cancel: each term's size ``sizes`` and their sum's."""
    each = ", ".join("%.3g" % x for x in sizes)
    return (f"the terms nearly cancel (each {each} {unit} rms, their sum {sum_rms:.3g} {unit}): only their sum "
            "is determined, not each")


# two terms whose fits sum to under this share of their quadrature sum (for two of equal size, a
# correlation below -0.75) are reported as nearly cancelling: each term's size alone then says
# more than the data do
CANCEL_SHARE = 0.5


# groups built from the acceleration's derivatives or magnitude: with derivatives of a quantised
# position their error is correlated for as long as the joint takes to cross an encoder step, and
# no null bounded from the data exists (the same rule keeps locate's a, jerk and |a|*sign(v)
# cross-correlations off there)
ACCELERATION_GROUPS = ("torque_rate", "jerk", "transmitted_torque")


def groups_on(model, ctx, kin, window: int, quantised_derivatives: bool) -> list[tuple[TermGroup, np.ndarray]]:
    """The library along the kinematics ``kin`` for ``model``'s torque, without the
    :data:`ACCELERATION_GROUPS` when the derivatives are of a quantised position."""
    tau_model = np.asarray(M._parts(model, kin)[2])
    return [(g, X) for g, X in library(ctx, kin, tau_model, window)
            if not (quantised_derivatives and g.name in ACCELERATION_GROUPS)]


def _line_frequency(t, r, mask, lines=None) -> float:
    """The time line's frequency: the strongest of ``r`` off the motion's ``lines`` (fitted on
    ``mask``) on the samples ``mask`` (0 elsewhere, as on the null draws, so that samples held out
    stay unseen)."""
    r = _off_lines(r, lines, mask)[:, 0]
    return float(_time_line_freqs(t, np.where(mask, r, 0.0)[None, :], mask)[0])


def attribute(model, specs, ctx, kin, rows, val, blocks, null, n_draws: int, alpha: float, window: int,
              max_terms: int = 2, seed: int = 0, nuisance=None, quantised_derivatives: bool = False,
              at_floor_nm: float | None = None, motion=None, cond=None, keep=None, folds=()) -> Attribution:
    """Greedy, calibrated attribution of ``ctx.residual`` (module docstring); with
    ``quantised_derivatives`` the :data:`ACCELERATION_GROUPS` are left out. The time line is
    searched and fitted off the motion's lines ``motion`` (:func:`motion_lines`) that an error of
    the kinematics conditioned as ``cond`` can explain (:func:`kinematic_lines`). A term is
    confirmed on the phases ``folds`` of the kept samples ``keep`` (cross-validated, as a
    candidate's held-out test; without them, on the fixed held-out phase ``val``). Where the
    cross-validated RMSE with a term stays above ``at_floor_nm`` (the at-floor bound) the residual
    holds misfit the null draws do not describe, so the term's held-out p is the larger of the
    draws' and the analytic one (which allows any colour). Every draw's columns are built from the
    kinematics its residual was made through (:class:`._calibrate.Views`)."""
    r = np.asarray(ctx.residual, float)
    t = np.asarray(ctx.rec.time, float)
    keep = (rows | val) if keep is None else np.asarray(keep, bool)
    folds_m = fold_masks(keep, blocks, folds) if folds else [val & keep]
    cv_mask = np.any(folds_m, axis=0)

    def terms_on(k):
        return groups_on(model, ctx, k, window, quantised_derivatives)

    groups = terms_on(kin)
    lines = kinematic_lines(model, kin, t, r, rows, motion, cond)

    # the lines' least squares on the training rows, solved once for every draw's time line
    P_lines = (np.linalg.pinv(lines[rows], rcond=max(lines[rows].shape) * np.finfo(float).eps)
               if lines is not None and lines.shape[1] else None)

    def off_lines(X):
        """:func:`_off_lines` on the training rows, with the lines' pseudo-inverse kept."""
        X = np.atleast_2d(np.asarray(X, float).T).T
        return X if P_lines is None else X - lines @ (P_lines @ X[rows])

    def line_at(f):
        return off_lines(_sincos(t, f))

    widths = np.cumsum([0] + [X.shape[1] for _, X in groups])
    nb = C.NullBasis(model, specs, kin, rows, null, n_draws, seed, nuisance)
    E, Rn, views = nb.draws.E, nb.R, nb.views
    lib = views.build(lambda k: np.column_stack([X for _, X in terms_on(k)]))

    def columns(d):
        """Draw ``d``'s library, group by group (every sample)."""
        L_ = views.at(lib, d)
        return [L_[:, widths[i]:widths[i + 1]] for i in range(len(groups))]

    QB, JB = nb.QB, nb.JB  # JB on every sample, for held-out prediction
    names = [g.name for g, _ in groups]
    chosen: list[tuple[TermGroup, np.ndarray]] = []
    chosen_i: list = []  # library index of each chosen group (None: the time line, at its frequency)
    tests = []
    terms = []
    before = _rms(r, val)
    after = before
    joint = None  # the last accepted step's fit: every chosen term with the refit columns
    # a term is compared on held-out samples with the model's own linearised refit (its Jacobian
    # and nuisance columns fitted on the other samples), as on every null draw
    cv_before = _rms(cv_residual(JB, r, keep, folds_m), cv_mask)
    cv_after = cv_before
    line_X_chosen = None  # the chosen time line's columns (at the recording's frequency, every draw)

    def draw_chosen(d, cols):
        return [cols[i] if i is not None else line_X_chosen for i in chosen_i]

    for _ in range(max_terms):
        Q = C._orth(np.column_stack([QB] + [X[rows] for _, X in chosen])) if chosen else QB
        left = [i for i in range(len(groups)) if names[i] not in [c[0].name for c in chosen]]
        have_line = TIME_LINE.name in [c[0].name for c in chosen]
        line_X = None
        if not have_line:
            f_obs = _line_frequency(t, r, rows, lines)
            line_X = line_at(f_obs)
            full = np.zeros((r.size, n_draws))
            full[rows] = Rn
            full = np.where(rows[:, None], off_lines(full), 0.0)
            fb = _time_line_freqs(t, full.T, rows)
        def draw_groups(d, cols):
            """Draw ``d``'s columns of the groups left (its time line at its own frequency)."""
            return [cols[i] for i in left] + ([line_at(fb[d])] if line_X is not None else [])

        # each draw: its own basis (the model's on its kinematics, the chosen terms' on them), its
        # residual with that basis taken out, and every group's gain on it (training rows)
        T = np.zeros((n_draws, len(left) + (line_X is not None)))
        for d in range(n_draws):
            cols = columns(d)
            Qd = C._orth(np.column_stack([nb.Q(d)] + [X[rows] for X in draw_chosen(d, cols)])) if chosen \
                else nb.Q(d)
            rd = Rn[:, d:d + 1]
            rd = rd - Qd @ (Qd.T @ rd) if chosen else rd
            T[d] = [C._gains(Qd, X[rows], rd)[0] for X in draw_groups(d, cols)]
        cands = [groups[i] for i in left]
        obs = [float(C._gains(Q, X[rows], r[rows][:, None])[0]) for _, X in cands]
        idx = list(left)
        if line_X is not None:
            obs.append(float(C._gains(Q, line_X[rows], r[rows][:, None])[0]))
            Tu = ctx.rec.units["torque"]
            cands = cands + [(dataclasses.replace(TIME_LINE, labels=(f"sin(2*pi*{f_obs:.4g}*t)",
                                                                     f"cos(2*pi*{f_obs:.4g}*t)"),
                                                  units=(Tu, Tu)), line_X)]
            idx.append(None)
        p_raw, p_adj, z = C.min_p(np.asarray(obs), T)
        tests.append([{"signal": g.name, "gain_nm2": o, "gain_over_null_mean": float(zz), "p_raw": float(pr),
                       "p_family": float(pa)} for (g, _), o, zz, pr, pa in zip(cands, obs, z, p_raw, p_adj)])
        obs_a = np.asarray(obs)
        sig = np.flatnonzero(C.rejects(p_adj, alpha))
        if sig.size == 0:
            break
        # the held-out test: every group's cross-validated gain against the same on every draw,
        # family-wise by min-P over the groups, so that choosing the group on training blocks the
        # cross-validation reuses costs nothing (the draws' own choice is inside their minimum)
        T_cv = np.array([cv_gains(np.column_stack([nb.JB_at(d)] + draw_chosen(d, cols)), draw_groups(d, cols),
                                  E[d], keep, folds_m) for d, cols in ((d, columns(d)) for d in range(n_draws))])
        base = np.column_stack([JB] + [Xc for _, Xc in chosen])
        obs_cv = cv_gains(base, [X for _, X in cands], r, keep, folds_m)
        _, p_cv, _ = C.min_p(obs_cv, T_cv, tail=C.normal_log_sf)
        r0_cv = cv_residual(base, r, keep, folds_m)
        # as for the candidates: the significant groups in order of what they explain beyond their
        # null, the first whose term holds up on the held-out samples taken
        excess = obs_a - obs_a / np.maximum(z, 1e-300)
        taken = None
        for k in sig[np.argsort(-excess[sig])]:
            g, X = cands[k]
            r1_cv = cv_residual(np.column_stack([base, X]), r, keep, folds_m)
            cv_new = _rms(r1_cv, cv_mask)
            p_analytic = C.held_out_p(r0_cv, r1_cv, blocks, cv_mask)
            p_held = float(p_cv[k])
            if at_floor_nm is not None and cv_new > at_floor_nm:
                p_held = max(p_held, p_analytic)
            # what the term removes from the held-out error, per sample (reported)
            share = float(np.sqrt(max(cv_after ** 2 - cv_new ** 2, 0.0)))
            if cv_new < cv_after and C.rejects(p_held, alpha):
                new, pred, beta = _held_out(X, base, r, rows, val)
                taken = int(k), g, X, new, cv_new, p_held, p_analytic, pred, beta, share
                break
            tests[-1].append({"rejected": g.name,
                              "because": f"cross-validated RMSE {cv_after:.4g} -> {cv_new:.4g}, p {p_held:.3g} "
                                         f"(analytic {p_analytic:.3g}), share {share:.3g}"})
        if taken is None:
            break
        k, g, X, new, cv_new, p_held, p_analytic, pred, beta, share = taken
        joint = r - pred, beta
        chosen.append((g, X))
        chosen_i.append(idx[k])
        if idx[k] is None:
            line_X_chosen = line_X
        nb_cols = JB.shape[1]
        coef = beta[nb_cols + sum(Xc.shape[1] for _, Xc in chosen[:-1]):][: X.shape[1]]
        terms.append({"signal": g.name, "columns": list(g.labels), "coefficients": [float(c) for c in coef],
                      "units": list(g.units), "reading": g.read(coef), "p_family": float(p_adj[k]),
                      "gain_nm2": float(obs[k]), "validation_rmse_nm": new, "cv_rmse_before_nm": cv_after,
                      "cv_rmse_nm": cv_new, "p_held_out": p_held, "p_held_out_analytic": float(p_analytic),
                      "held_out_share_nm": share})
        after, cv_after = new, cv_new
    fits, partials = _partials(JB.shape[1], [X for _, X in chosen], *joint) if joint else ((), ())
    return Attribution(tuple(terms), before, after, tuple(tests), tuple(X for _, X in chosen), fits, partials,
                       cv_before, cv_after, *term_sizes(fits, keep))


def _rms(r, mask) -> float:
    return float(np.sqrt(np.mean(r[mask] ** 2))) if np.any(mask) else float("nan")


def _partials(n_refit: int, Xs, resid, beta) -> tuple[tuple, tuple]:
    """(fits, partial residuals) of the terms ``Xs`` from their joint least squares with the refit's
    ``n_refit`` columns first (coefficients ``beta``, residual ``resid``: the last accepted step's
    :func:`_held_out` fit, :class:`Attribution`)."""
    fits, i = [], n_refit
    for X in Xs:
        fits.append(X @ beta[i:i + X.shape[1]])
        i += X.shape[1]
    return tuple(fits), tuple(resid + f for f in fits)


@dataclasses.dataclass(frozen=True)
class Rivals:
    """The library's rival explanations of a residual (:func:`rivals`): ``terms``, one
    ``(group, cross-validated residual, reading)`` per library group and the time line, and
    ``refit``, the cross-validated residual of the model's linearised refit alone, which every
    term's residual includes (a term is credited only with what it removes beyond it)."""

    terms: list
    refit: np.ndarray


def rivals(model, specs, ctx, kin, keep, blocks, folds, window: int, quantised_derivatives: bool = False,
           nuisance=None, motion=None, cond=None) -> Rivals:
    """Every library group and the time line as a rival explanation of the current residual
    ``ctx.residual`` (:class:`Rivals`), each phase of ``folds`` predicted by the term with the
    current model's linearised refit (its Jacobian and the ``nuisance`` columns) fitted on the
    other kept samples, the time line's frequency searched on those samples too, off the motion's
    lines ``motion`` a kinematic error can explain (:func:`kinematic_lines`); 0 elsewhere. A
    candidate is compared with these by :func:`._calibrate.held_out_p` on the same phases as its own
    cross-validated residual."""
    r = np.asarray(ctx.residual, float)
    t = np.asarray(ctx.rec.time, float)
    n = r.size
    groups = groups_on(model, ctx, kin, window, quantised_derivatives) + [(TIME_LINE, None)]
    JB = C.jacobian(model, specs, kin, np.ones(n, bool))
    if nuisance is not None:
        JB = np.column_stack([JB, np.asarray(nuisance, float).reshape(n, -1)])
    folds_m = fold_masks(keep, blocks, folds)
    lines = kinematic_lines(model, kin, t, r, keep, motion, cond)

    def time_line(fit):
        # its frequency searched, and its columns fitted off the lines, on each fold's fit
        return np.column_stack([JB, _time_line(t, _line_frequency(t, r, fit, lines), lines, fit)])

    def reading(g, X):
        # the sign-dependent reading (v*|v| falling is not drag) of the term fitted on every kept sample
        if X is None:
            return g.reading
        X = np.asarray(X, float).reshape(n, -1)
        coef = np.linalg.lstsq(np.column_stack([JB, X])[keep], r[keep], rcond=None)[0]
        return g.read(coef[-X.shape[1]:])

    return Rivals([(g, cv_residual(time_line if X is None else np.column_stack([JB, X]), r, keep, folds_m),
                    reading(g, X)) for g, X in groups], cv_residual(JB, r, keep, folds_m))
