"""The time periodogram's background (diagnose._locate): a red hump at the low end of a long
residual is not a line, a narrow line still is."""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from lugre_jax.diagnose._locate import time_periodogram


def _red_residual(seed, n=28800, fs=200.0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    white = 0.08 * rng.standard_normal(n)
    # a slow AR(1) component (time constant 5 s), rms 0.02: the hump errors in variables leave
    # along a repeated excitation
    a = np.exp(-1.0 / (5.0 * fs))
    red = lfilter([1.0], [1.0, -a], rng.standard_normal(n))
    red *= 0.02 / red.std()
    return t, white + red


def test_white_noise_holds_the_level():
    """300 white residuals: the 5 % test fires at most 21 times (binomial P(>= 22) = 0.045 if its
    level is right). Measured: 8 times; with the uncorrected exp(-R) tail for the ratio to an
    estimated background, 23 times."""
    rng = np.random.default_rng(3)
    t = np.arange(28800) / 200.0
    hits = sum(time_periodogram(t, rng.standard_normal(t.size))["p_value"] < 0.05 for _ in range(300))
    assert hits <= 21, hits


def test_red_hump_is_not_a_line():
    """60 residuals with a slow red part (the hump errors in variables leave along a repeated
    excitation): at most 6 alarms at 5 % (binomial P(>= 7) = 0.04). Measured: 4; with the fixed
    +-200-ordinate median background and the exp(-R) tail, 60 of 60 (the lowest ordinates)."""
    hits = sum(time_periodogram(*_red_residual(s))["p_value"] < 0.05 for s in range(60))
    assert hits <= 6, hits


def test_narrow_low_line_is_found():
    t, r = _red_residual(99)
    r = r + 0.02 * np.sin(2 * np.pi * 0.3 * t)  # a line a quarter of the noise, 0.3 Hz
    tp = time_periodogram(t, r)
    assert tp["p_value"] < 1e-6 and abs(tp["frequency"] - 0.3) < 0.01


def _direction_signal(n=28800, fs=200.0):
    t = np.arange(n) / fs
    v = np.where((t // 9.0) % 2 == 0, 1.0, -1.0)  # out and back every 9 s
    blocks = (t // 1.0).astype(int)
    return t, v, blocks


def test_trend_test_level_and_margin():
    """The friction-trend test (slope of the residual on sign(v)*(t - t_mid)): on white residuals
    it fires at most 8 of 100 times at 5 % (binomial P(>= 9) = 0.06); a drift whose half-to-half
    change is 0.03 N*m (noise 0.08, margin 0.012) is found; one of 0.006, below the margin, is not
    claimed."""
    from lugre_jax.diagnose._locate import trend_test

    t, v, blocks = _direction_signal()
    x = np.sign(v) * (t - t.mean())
    keep = np.ones(t.size, bool)
    D = t[-1] - t[0]
    margin = 0.15 * 0.08 / (0.5 * D)
    rng = np.random.default_rng(5)
    hits = sum(trend_test(0.08 * rng.standard_normal(t.size), x, blocks, keep, margin=0.0)["p_value"] < 0.05
               for _ in range(100))
    assert hits <= 8, hits
    noise = 0.08 * rng.standard_normal(t.size)
    big = trend_test(noise + (0.03 / (0.5 * D)) * x, x, blocks, keep, margin=margin)
    small = trend_test(noise + (0.006 / (0.5 * D)) * x, x, blocks, keep, margin=margin)
    assert big["p_value"] < 1e-6, big
    assert small["p_value"] == 1.0 and small["statistic"] == 0.0, small
