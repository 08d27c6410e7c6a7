"""Metrics of lugre_jax.metrics on synthetic trajectories with known answers (units s, deg, deg/s)."""

import numpy as np
import pytest

from lugre_jax import metrics as M

T = np.linspace(0.0, 20.0, 2001)  # 100 Hz
V = 0.005


def ramp_with_dead_zone(D, v=V, t=T):
    """A joint that stands still for D seconds, then follows the ramp exactly."""
    return v * np.maximum(t - D, 0.0)


@pytest.mark.parametrize("D", [0.0, 0.5, 2.0, 3.7])
def test_dead_zone_lag_exact_for_ideal_dead_zone(D):
    th = ramp_with_dead_zone(D)
    assert M.dead_zone_lag(T, th, V) == pytest.approx(D, abs=1e-12)


def test_dead_zone_lag_batched_and_command_time():
    th = np.stack([ramp_with_dead_zone(1.0), ramp_with_dead_zone(2.5)])
    np.testing.assert_allclose(M.dead_zone_lag(T, th, V), [1.0, 2.5], atol=1e-12)
    # command issued at t = 3 s; dead zone 1 s after it
    th2 = V * np.maximum(T - 4.0, 0.0)
    assert M.dead_zone_lag(T, th2, V, t_cmd=3.0) == pytest.approx(1.0, abs=1e-12)


def test_dead_zone_lag_constant_pi_lag():
    # PI velocity loop holding a constant position lag L: dead zone = L / v
    L = 0.01
    th = np.maximum(V * T - L, 0.0)
    assert M.dead_zone_lag(T, th, V) == pytest.approx(L / V, abs=1e-12)


@pytest.mark.parametrize("D", [0.0, 1.0, 2.0])
def test_dead_zone_onset(D):
    th = ramp_with_dead_zone(D)
    # window mean velocity over [t, t+0.5] reaches 50% when half the window is past D: t = D - 0.25
    expected = max(D - 0.25, 0.0)
    assert M.dead_zone_onset(T, th, V, frac=0.5, hold_s=0.5) == pytest.approx(expected, abs=0.011)


def test_dead_zone_onset_never_moves_is_inf():
    assert np.isinf(M.dead_zone_onset(T, np.zeros_like(T), V))


def test_creep_amplitude_of_stairs():
    # stick-slip staircase: steps of h every P seconds around the ramp
    h, P = 0.002, 0.4
    th = h * np.floor(T / P) + 0.5 * h  # mean slope h/P = 0.005 deg/s
    amp = M.creep_amplitude(T, th, V * T, t_from=5.0)
    assert amp == pytest.approx(h, rel=0.03)
    # a pure constant lag plus drift has no creep
    assert M.creep_amplitude(T, V * T - 0.01 + 1e-4 * T, V * T) == pytest.approx(0.0, abs=1e-12)


def test_band_fraction_known():
    om = np.full_like(T, V)
    om[T < 5.0] = 0.0  # 0 is outside +-0.001 around 0.005
    assert M.band_fraction(T, om, V, 0.001) == pytest.approx(np.mean(T >= 5.0), abs=1e-12)
    assert M.band_fraction(T, om, V, 0.001, t_from=5.0) == 1.0
    # 0.001 deg/s: +-0.001 contains standing still
    assert M.band_fraction(T, np.zeros_like(T), 0.001, 0.001) == 1.0


def test_cone_fraction_enters_at_vD_over_band():
    D = 2.0
    th = ramp_with_dead_zone(D)
    # inside (v - band) t <= v (t - D)  <=>  t >= v D / band = 10 s
    frac = M.cone_fraction(T, th, V, 0.001)
    t = T[T > 0]
    assert frac == pytest.approx(np.mean(t >= V * D / 0.001 - 1e-9), abs=1e-3)


def test_tracking_errors_sine():
    ref = 3.0 * np.sin(0.8 * np.pi * T)
    th = ref + 0.01 * np.sin(2.0 * T)
    e = M.tracking_errors(T, th, ref, t_from=0.0)
    assert e["max_abs_deg"] == pytest.approx(0.01, rel=1e-3)
    assert e["rms_deg"] == pytest.approx(0.01 / np.sqrt(2), rel=0.02)


def test_velocity_ripple():
    om = V + 0.001 * np.sin(2 * np.pi * T)
    assert M.velocity_ripple(T, om, V) == pytest.approx(0.001 / np.sqrt(2) / V, rel=1e-2)


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="v_cmd"):
        M.dead_zone_lag(T, T, 0.0)
    with pytest.raises(ValueError, match="band"):
        M.band_fraction(T, T, V, band=0.0)
    with pytest.raises(ValueError, match="window"):
        M.tracking_errors(T, T, T, t_from=100.0)
