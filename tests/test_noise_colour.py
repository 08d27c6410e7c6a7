"""The colour-aware torque noise estimate (diagnose._condition.torque_noise_std) against noise of
known variance: white noise under a smooth signal, AR(1) noise (a first-order low-passed sensor),
and AR(1) noise under a staircase of set-points (steps between runs, as in TRO2021's chained runs)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from lugre_jax.diagnose._condition import (hf_noise_std, noise_estimate_open, noise_profile, refined_torque_noise,
                                          torque_noise_model, torque_noise_std)

N = 20_000


def _ar1(phi, n=N, seed=0):
    """Stationary AR(1) of unit variance."""
    e = np.random.default_rng(seed).standard_normal(n)
    e[0] /= np.sqrt(1.0 - phi ** 2)
    return lfilter([np.sqrt(1.0 - phi ** 2)], [1.0, -phi], e)


def _smooth(n=N):
    t = np.arange(n) / 500.0
    return 3.0 * np.sin(2 * np.pi * 0.3 * t) + np.sin(2 * np.pi * 1.1 * t + 0.4)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_white_noise_is_white(seed):
    """White noise of std 0.1 under a smooth 3-N*m signal: no colour is claimed, and the estimate is
    the third-difference one (the diagnosis of white recordings is unchanged), within 5 % of 0.1."""
    x = _smooth() + 0.1 * np.random.default_rng(seed).standard_normal(N)
    est = torque_noise_std(x)
    sd, phi = est.std, est.phi
    assert phi == 0.0 and sd == hf_noise_std(x)
    assert abs(sd / 0.1 - 1) < 0.05


@pytest.mark.parametrize("phi", [0.5, 0.8, 0.95])
def test_ar1_noise_full_std(phi):
    """AR(1) noise of std 0.1 (corner fs*(1-phi)/(2*pi)): the white-noise estimate sees only a part
    (0.95: about a fifth), the colour-aware one the whole std within 10 %."""
    x = _smooth() + 0.1 * _ar1(phi)
    est = torque_noise_std(x)
    sd, phi_hat = est.std, est.phi
    assert hf_noise_std(x) < 0.1 * np.sqrt(1.0 - 0.9 * phi) * 1.05
    assert abs(sd / 0.1 - 1) < 0.10, (sd, phi_hat)
    assert abs(phi_hat - phi) < 0.1


def test_steps_between_set_points_are_not_colour():
    """AR(1) noise (phi 0.9, std 0.1) over 40 set-points of 500 samples with steps of 0.5-2 (5-20
    std): the differences spanning a step are left out, so the estimate stays within 15 % of 0.1
    (measured 0.089-0.094 over four seeds); counting them, the long lags see the steps as noise
    (0.153; 0.119 with the per-lag outlier trim alone)."""
    rng = np.random.default_rng(3)
    levels = np.repeat(np.cumsum(rng.choice([-1, 1], 40) * rng.uniform(0.5, 2.0, 40)), 500)
    x = levels + 0.1 * _ar1(0.9)
    sd = torque_noise_std(x).std
    assert abs(sd / 0.1 - 1) < 0.15, sd
    assert torque_noise_std(x, jump_std=None).std > 0.115


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fast_resolved_reversals_are_not_colour(seed):
    """White noise (std 0.05) on a position-sine tracking torque: a slow sine plus a 2-N*m change of
    sign over ~8 samples at every reversal (the friction through its pre-sliding), every 300
    samples. The change is no jump at lag 1, but the differences spanning it are a share of the
    long lags that grows with the lag, as a colour's rise does; they are trimmed per lag, so no
    colour is claimed and the estimate is within 5 % (without the trim: coloured, 19-38 % high,
    the held-out recordings held_null08/09 of docs/diagnosis.md)."""
    n = 12_000
    i = np.arange(n)
    reversal = np.tanh(np.sin(2 * np.pi * i / 600.0) * 600.0 / (2 * np.pi * 4.0))
    x = 1.0 * reversal + 1.5 * np.sin(2 * np.pi * i / 600.0 + 1.2) + \
        0.05 * np.random.default_rng(seed).standard_normal(n)
    est = torque_noise_std(x)
    sd, phi = est.std, est.phi
    assert phi == 0.0 and abs(sd / 0.05 - 1) < 0.05, (sd, phi)


def test_a_colour_past_the_profile_is_reported_open():
    """AR(1) noise with phi 0.995 (a correlation of 200 samples, past the profile's 128 lags): the
    estimate is below the true 0.1 and the profile is reported open (a lower bound); for white and
    for phi 0.8 noise it is not. (A smooth signal that fills the longest lags opens it too: the
    report says the floor *may* be a lower bound.)"""
    x = 0.1 * _ar1(0.995)
    sd = torque_noise_std(x).std
    assert sd < 0.09 and noise_estimate_open(x, sd)
    for y in (0.1 * np.random.default_rng(0).standard_normal(N), 0.1 * _ar1(0.8)):
        assert not noise_estimate_open(y, torque_noise_std(y).std)


def _fast_motion(seed, n=N):
    """A slow sine plus six small sines of 25-80-sample periods: their lag-k third differences
    saturate (and oscillate) with k instead of growing as k^6, as a fast motion's do at a low rate."""
    rng = np.random.default_rng(seed)
    i = np.arange(n)
    f, ph = rng.uniform(1 / 80, 1 / 25, 6), rng.uniform(0, 2 * np.pi, 6)
    return 3.0 * np.sin(2 * np.pi * i / 4000) + sum(0.08 * np.sin(2 * np.pi * fk * i + p) for fk, p in zip(f, ph))


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_the_prediction_takes_a_fast_motion_out_of_the_colour(seed):
    """AR(1) noise (phi 0.8, std 0.1) under a fast motion, with the motion as the prediction: left
    out where it is large but not given as a signal column, the motion's remainder at the long lags
    reads as noise (measured 6-14 % high); with the prediction's own profile as a column the estimate
    is within 3 % (measured 0.989-1.002)."""
    sig = _fast_motion(seed)
    x = sig + 0.1 * _ar1(0.8, seed=seed)
    first = torque_noise_std(x).std
    left_out = torque_noise_model(x, noise_profile(x, signal=sig, limit=0.5 * np.sqrt(20.0) * first)).std
    assert left_out > 0.105
    assert abs(refined_torque_noise(x, sig, first).std / 0.1 - 1) < 0.03


@pytest.mark.parametrize("seed", [1, 2])
def test_a_noisy_prediction_does_not_lower_the_estimate(seed):
    """The prediction carries a noise of its own (the kinematics' errors through the model: AR(1)
    0.8, std 0.03, independent of the torque's): its profile rises as the torque noise's does, and
    the signal column's coefficient is held at most 1, so the estimate stays at or above the truth
    within 3 % (measured 1.008 and 1.014; with an unbounded coefficient 0.953 and 0.877)."""
    sig = _fast_motion(seed)
    x = sig + 0.1 * _ar1(0.8, seed=seed)
    pred = sig + 0.03 * _ar1(0.8, seed=100 + seed)
    assert refined_torque_noise(x, pred, torque_noise_std(x).std).std > 0.097


def test_the_signal_column_never_raises_the_estimate():
    """A profile shaped as a drive's averaged current (TRO2021 driveNo1's through its fitted model,
    rounded, in units of its lag-1 level): a rise to an overshoot at lags 24-32, a plateau, and the
    motion alone at lag 128, which the prediction's column holds. With the column the AR(1) fit
    follows the overshoot and reads higher (a shape AR(1) noise has not); the model keeps the lower
    estimate, the one without it."""
    lags = np.array([1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128])
    sd = np.array([0.039, 0.075, 0.1, 0.119, 0.16, 0.185, 0.231, 0.25, 0.282, 0.27, 0.229, 0.246, 0.214, 1.529])
    se = sd * np.array([0.049, 0.066, 0.097, 0.118, 0.132, 0.125, 0.123, 0.11, 0.069, 0.057, 0.09, 0.092, 0.496,
                        0.019])
    signal_var = np.zeros(lags.size)
    signal_var[-1] = 20.0 * sd[-1] ** 2
    x = 0.039 * np.random.default_rng(0).standard_normal(N)
    plain = torque_noise_std(x, profile=(lags, sd, se)).std
    assert torque_noise_std(x, profile=(lags, sd, se), signal_var=signal_var).std > 1.05 * plain
    assert torque_noise_model(x, (lags, sd, se), signal_var=signal_var).std == plain


def _filtered(kind, n=N, seed=0):
    """Unit-variance noise of a colour outside AR(1): a second- or fourth-order Butterworth low-pass
    of white noise (corner 1/12 and 1/10 of the rate), or half white, half AR(1) 0.85."""
    from scipy.signal import butter, sosfilt

    rng = np.random.default_rng(seed)
    w = rng.standard_normal(n + 3000)
    if kind == "butter2":
        x = sosfilt(butter(2, 1.0 / 12.0, fs=1.0, output="sos"), w)[3000:]
    elif kind == "butter4":
        x = sosfilt(butter(4, 1.0 / 10.0, fs=1.0, output="sos"), w)[3000:]
    else:
        x = np.sqrt(0.5) * rng.standard_normal(n) + np.sqrt(0.5) * _ar1(0.85, n, seed + 10)
    return x / np.std(x)


@pytest.mark.parametrize("kind", ["butter2", "butter4", "white_plus_ar1"])
def test_colours_beyond_ar1_full_std(kind):
    """Noise of std 0.1 under the smooth signal, of a colour AR(1) does not describe (AR(1) alone reads
    the Butterworth ones at 0.2-0.55x, the mixture at 0.9x): the broader family is claimed and the
    std read within 5 %."""
    x = _smooth() + 0.1 * _filtered(kind)
    est = torque_noise_std(x)
    assert est.arma and abs(est.std / 0.1 - 1) < 0.05, est


def test_broader_colour_null_draws_match_it():
    """The null model's draws of a broader colour (diagnose._calibrate.NullModel) have the fitted std
    within 2 %, the recording's lag-1 autocorrelation within 0.02 and its lag-5 one within 0.1 (the
    family's grid of poles is coarse in angle: 0.105 rad)."""
    from lugre_jax.diagnose._calibrate import NullModel

    n = 0.1 * _filtered("butter2", seed=3)
    est = torque_noise_std(_smooth() + n)
    sd, phi, arma = est.std, est.phi, est.arma
    d = NullModel(sd, phi, (), np.zeros(N, int), torque_arma=arma).torque_noise(np.random.default_rng(0), (8, N))
    assert abs(np.std(d) / sd - 1) < 0.02
    for lag, tol in ((1, 0.02), (5, 0.1)):
        rho = np.mean([np.corrcoef(x[:-lag], x[lag:])[0, 1] for x in d])
        assert abs(rho - np.corrcoef(n[:-lag], n[lag:])[0, 1]) < tol, (lag, rho)


def test_torque_noise_is_capped_by_the_residual():
    """Strong colour at a low rate (AR(1) 0.85 at 170 Hz, a 34-s sine sweep under a velocity PI: the
    independent generator): the noise profile's plateau lies where the motion's differences are large
    too, and it reads the noise 11 % high. A complete model cannot beat the floor, so the floor's
    torque noise is at most the upper bound of the baseline's mean square (diagnose._select._floor);
    it is then within 10 % of the true std, the profile's own estimate left in the conditioning."""
    from lugre_jax.diagnose import DiagnoseConfig
    from lugre_jax.diagnose import _model as M
    from lugre_jax.diagnose import _select as S
    from lugre_jax.testing import Plant, Sensors, SineSweep, VelocityPIController, generate

    plant = Plant(J=0.13, Fc=0.85, Fs=1.3, vs=0.05, sigma2=1.2, sigma0=210.0, sigma1=1.4)
    g = generate(SineSweep(amplitude=2.4, f0=0.06, f1=1.9, duration=34.0, bias=0.75), (), plant,
                 VelocityPIController(kp=6.5, ki=39.0),
                 Sensors(fs=170.0, torque_noise=0.16, torque_noise_ar=0.85, velocity_noise=0.0015, quantisation=0.0,
                         position_column=False), seed=21401)
    cfg = DiagnoseConfig()
    prep, split = S._prepare(g.to_recording(), cfg, None, "lugre", False)
    split = S._predicted(prep, split, False, cfg.resolved_share)
    pred = np.asarray(M.predict(prep.base, prep.kin))
    r0 = (np.asarray(prep.rec.torque) - pred) * split.keep
    prep = S._noise(prep, pred, cfg)
    floor = S._floor(prep, split, cfg, False, r0)
    true = g.torque_noise_std
    assert prep.cond.torque_noise / true > 1.1, prep.cond.torque_noise / true  # the profile alone
    assert floor.torque_nm ** 2 <= S._ms_bound(r0, split.keep, split.blocks) * (1 + 1e-12)
    assert abs(floor.floor_nm / true - 1) < 0.1, floor.floor_nm / true
    assert floor.null.torque_sd == floor.torque_nm
