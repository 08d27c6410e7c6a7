"""Samples at rest are left out of the diagnosis: there the inverse model cannot know the bristle state.

Reference: the independent generator (scipy LSODA) and its true friction torque. With the TRUE
parameters, the inverse model's friction on the samples kept must match the true friction to a
small share of the torque noise; on the samples left out at rest it misses by more than the noise
(which is why they go: a correct model would leave structure there that no candidate may claim).
"""

import numpy as np
import pytest

from lugre_jax import testing as T
from lugre_jax.diagnose._condition import at_rest
from lugre_jax.diagnose._config import DiagnoseConfig
from lugre_jax.diagnose import _model as M
from lugre_jax.diagnose._select import _prepare


def test_at_rest_holds_its_level_on_noise():
    # velocity noise alone: |v| < 1.96 sd on 95 % of the samples (binomial sd 0.2 % at n 1e4)
    rng = np.random.default_rng(3)
    v = 0.002 * rng.standard_normal(10_000)
    assert abs(at_rest(v, 0.002, 0.05).mean() - 0.95) < 0.01
    # a motion ten noise std from rest is never taken for it
    assert not at_rest(0.02 + v, 0.002, 0.05).any()
    assert not at_rest(v, 0.0, 0.05).any()  # no noise estimate: nothing is at rest


def test_at_rest_takes_dwells_not_passages_through_zero():
    t = np.linspace(0.0, 4.0, 4001)
    v = np.where(t < 1.0, 0.0, np.sin(2.0 * np.pi * (t - 1.0)))  # a 1-s dwell, then reversals
    rest = at_rest(v, 0.01, 0.05, min_run=21)
    assert rest[t < 0.99].all() and not rest[t > 1.01].any()
    # a dwell's noise breaks it into runs; the gaps are closed, the reversals stay out
    noisy = v + 0.01 * np.random.default_rng(5).standard_normal(t.size)
    rest = at_rest(noisy, 0.01, 0.05, min_run=21)
    assert rest[(t > 0.02) & (t < 0.98)].mean() > 0.99 and rest[t > 1.01].mean() < 0.01
    # a creep at the noise level: no window tells it from rest, its 2-s mean does (z ~ 9)
    creep = 0.01 + 0.01 * np.random.default_rng(6).standard_normal(t.size)
    assert not at_rest(creep, 0.01, 0.05, min_run=21)[t < 3.0].any()
    # the reversals (7 samples each within 1.96*0.01 of zero) are flagged without the run length
    assert at_rest(v, 0.01, 0.05)[t > 1.01].sum() >= 6 * 5


@pytest.fixture(scope="module")
def dwelling():
    plant = T.Plant(J=0.15, Fc=0.7, Fs=1.1, vs=0.08, sigma2=1.2, sigma0=280.0, sigma1=1.3)
    ctrl = T.VelocityPIController(kp=9.0, ki=54.0)
    sens = T.Sensors(fs=260.0, torque_noise=0.07, velocity_noise=0.003, quantisation=0.0,
                     velocity_column=True, position_column=False)
    exc = T.PointToPoint(amplitudes=(2.4, -2.0, 1.5, -2.6), move_time=1.4, dwell=2.2, repeats=1)
    g = T.generate(exc, [], plant, ctrl, sens, seed=404)
    p = {f: getattr(plant, f) for f in ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta")}
    prep, split = _prepare(g.to_recording(), DiagnoseConfig(), p | {"offset": 0.0, "friction_model": "LuGre"},
                           "lugre", False)
    friction = M.predict(prep.base, prep.kin) - plant.J * np.asarray(prep.kin.a)
    err = g.true["friction_and_load"] - friction
    return g, prep, split, err


def test_kept_samples_carry_no_inverse_model_error(dwelling):
    g, prep, split, err = dwelling
    keep = split.keep > 0
    sd = g.torque_noise_std
    assert 0.2 < prep.at_rest.mean() < 0.8  # the dwells are there and are left out
    # kept: the true model's friction error (smoothing of the kinematics) well below the noise
    assert np.sqrt(np.mean(err[keep] ** 2)) < 0.1 * sd
    # at rest: the bristle state is not resolved, the error exceeds the noise
    assert np.sqrt(np.mean(err[prep.at_rest] ** 2)) > sd


def test_velocity_path_keeps_sharp_steps(monkeypatch):
    """A measured velocity's own integral keeps the bristle path's turns at sharp velocity steps,
    which the smoothing window of the complementary path blurs; dwells are out either way. With
    the generator's parameters the inverse model's friction error on the kept samples, against the
    generator's true friction: the velocity path's well below the complementary one's, and the
    path the diagnosis chooses."""
    import equinox as eqx

    from lugre_jax.diagnose import _condition
    from lugre_jax.diagnose._condition import velocity_path

    # the steps' turns, whose acceleration the window does not resolve, leave the kept samples by
    # the narrower windows' check; the path is about the friction, so they stay in here
    monkeypatch.setattr(_condition, "_sharper_than_window", lambda t, x, *a: np.zeros(np.shape(x), bool))

    plant = T.Plant(J=0.09, Fc=0.5, Fs=0.8, vs=0.06, sigma2=0.9, sigma0=160.0, sigma1=0.8)
    sens = T.Sensors(fs=470.0, torque_noise=0.07, velocity_noise=0.0025, quantisation=0.0,
                     velocity_column=True, position_column=False)
    exc = T.Staircase(speeds=(0.07, 0.24, 0.8, 2.0, 3.8), dwell=2.4, transition=0.0, repeats=1, seed=7)
    g = T.generate(exc, [], plant, T.VelocityPIController(kp=5.5, ki=33.0), sens, seed=405)
    p = {f: getattr(plant, f) for f in ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta")}
    rec = g.to_recording()
    prep, split = _prepare(rec, DiagnoseConfig(), p | {"offset": 0.0, "friction_model": "LuGre"}, "lugre", False)
    keep = split.keep > 0
    th = velocity_path(rec.time, prep.rec.position, rec.velocity)
    kin_v = M.kinematics_of(eqx.tree_at(lambda r: r.position, prep.rec, th))

    def err(kin):
        e = g.true["friction_and_load"] - (M.predict(prep.base, kin) - plant.J * np.asarray(kin.a))
        return np.sqrt(np.mean(e[keep] ** 2)) / g.torque_noise_std

    kin_c = M.kinematics_of(prep.rec)
    e_c, e_v = err(kin_c), err(kin_v)
    assert e_v < 0.5 * e_c and e_v < 0.35, (e_c, e_v)
    # given parameters, the path is still chosen by the training SSE: here the velocity's
    assert prep.path == "velocity", prep.path


@pytest.mark.parametrize("velocity_measured, advice", [(True, "a higher sampling rate"), (False, "a velocity sensor")])
def test_a_recording_with_too_few_resolved_samples_is_refused_with_advice_that_fits_it(velocity_measured, advice):
    """The refusal names what would help: a velocity sensor only where the recording has none."""
    from lugre_jax.diagnose import make_recording
    from lugre_jax.diagnose._condition import Conditioning
    from lugre_jax.diagnose._select import _split

    rec, _ = make_recording(seed=2, duration=20.0)
    cond = Conditioning(torque_noise=0.05, velocity_noise=0.01, position_noise=0.0, quantisation=0.0,
                        source="velocity", window=33, accel_noise_torque=0.0, velocity_noise_after=0.0,
                        velocity_measured=velocity_measured)
    unresolved = np.ones(rec.n, bool)
    unresolved[:50] = False
    with pytest.raises(ValueError) as e:
        _split(rec, cond, unresolved, DiagnoseConfig())
    msg = str(e.value)
    assert f"only 50 of {rec.n} samples" in msg and advice in msg
    assert ("velocity sensor" in msg) == (not velocity_measured)


def test_a_window_that_fits_significantly_better_is_found():
    """The window check behind the conditioning (``_residual_window``): given kinematics smoothed
    over a window far too short for a noisy velocity sensor on a heavy joint, the generator's model's
    training residual is significantly lower on a longer window, and that window's model error
    against the generator's noise-free torque is lower too; the held-out confirmation prefers it."""
    from lugre_jax.diagnose._condition import condition
    from lugre_jax.diagnose._select import _predicts_better, _residual_window, _split

    plant = T.Plant(J=0.15, Fc=1.15, Fs=1.6, vs=0.065, sigma2=1.45, sigma0=245.0, sigma1=1.9)
    sens = T.Sensors(fs=500.0, torque_noise=0.03, velocity_noise=0.008, quantisation=0.0,
                     velocity_column=True, position_column=False)
    exc = T.Staircase(speeds=(0.04, 0.18, 0.75, 2.2, 4.1), dwell=2.1, transition=0.0, repeats=1, seed=5)
    g = T.generate(exc, [], plant, T.VelocityPIController(kp=7.5, ki=45.0), sens, seed=407)
    rec = g.to_recording()
    p = {f: getattr(plant, f) for f in ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta")}
    base = M.baseline_from_params(p | {"offset": 0.0, "friction_model": "LuGre"})
    cfg = DiagnoseConfig()

    def check(window):
        crec, cond, unresolved = condition(rec, plant.J, plant.sigma2, choices=[("velocity", window, 3)], cfg=cfg)
        split = _split(crec, cond, unresolved, cfg)
        kin = M.kinematics_of(crec)
        choice, gain = _residual_window(rec, crec, cond, base, kin, "complementary", split, cfg.alpha)
        keep = split.keep > 0
        err = np.sqrt(np.mean((g.true["torque"] - np.asarray(M.predict(base, kin)))[keep] ** 2))
        return choice, gain, err, (crec, base, kin, split)

    choice, gain, err_short, short = check(9)
    assert choice is not None and choice[0] == "velocity" and choice[1] > 9 and gain > 0, (choice, gain)
    _, _, err_found, found = check(choice[1]) if choice[2] == 3 else (None, 0.0, None, None)
    assert err_found is not None and err_found < 0.5 * err_short, (err_found, err_short, choice)
    # the refit's held-out confirmation (_predicts_better) takes the found window over the short one,
    # and not the other way round
    assert _predicts_better(short, found, cfg.min_resolved // 4)
    assert not _predicts_better(found, short, cfg.min_resolved // 4)


def test_a_window_whose_refit_predicts_no_better_is_refused(monkeypatch):
    """The held-out confirmation's wiring in ``_prepare``: with the window check made to offer a
    window twice as long, the refit on it is kept when ``_predicts_better`` says so (and the first
    window recorded in ``window_rechosen_from``), and refused otherwise: the first window, its
    conditioning and its baseline come back, and ``window_refused`` names the window offered."""
    import lugre_jax.diagnose._select as S

    plant = T.Plant(J=0.1, Fc=0.8, Fs=1.2, vs=0.05, sigma2=1.0, sigma0=190.0, sigma1=1.2)
    sens = T.Sensors(fs=400.0, torque_noise=0.05, velocity_noise=0.004, quantisation=0.0,
                     velocity_column=True, position_column=False)
    exc = T.Staircase(speeds=(0.05, 0.2, 0.8, 2.4), dwell=2.0, transition=0.3, repeats=1, seed=9)
    rec = T.generate(exc, [], plant, T.VelocityPIController(kp=5.0, ki=30.0), sens, seed=411).to_recording()
    cfg = DiagnoseConfig()
    # no blend and a few samples for the smoothing-bias rule, so that the rule's refit, on the paths
    # left by the window's choice, follows it directly
    import lugre_jax.diagnose._condition as C

    monkeypatch.setattr(C, "smoothing_blend", lambda *a, **k: 0.0)
    monkeypatch.setattr(C, "model_bias_unresolved", lambda rec_, *a, **k: np.arange(rec_.n) % 97 == 0)
    monkeypatch.setattr(S, "_residual_window", lambda *a, **k: (None, 0.0))
    first, _ = _prepare(rec, cfg, None, "lugre", False)
    w0 = first.cond.window
    offered = (first.cond.source, 2 * w0 + 1, first.cond.order)
    monkeypatch.setattr(S, "_residual_window", lambda *a, **k: (offered, 1.0))
    monkeypatch.setattr(S, "_predicts_better", lambda *a, **k: True)
    kept, _ = _prepare(rec, cfg, None, "lugre", False)
    assert kept.cond.window == 2 * w0 + 1 and kept.info["window_rechosen_from"]["window"] == w0, kept.info
    monkeypatch.setattr(S, "_predicts_better", lambda *a, **k: False)
    refused, _ = _prepare(rec, cfg, None, "lugre", False)
    assert refused.cond.window == w0 and "window_rechosen_from" not in refused.info, refused.info
    assert refused.info["window_refused"]["window"] == 2 * w0 + 1, refused.info
    # the smoothing-bias rule's refit runs on the first window's paths too
    assert "model_bias_unresolved" in refused.info, refused.info
    for f in ("v", "a"):
        np.testing.assert_allclose(np.asarray(getattr(refused.kin, f)), np.asarray(getattr(first.kin, f)),
                                   rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(np.asarray(M.predict(refused.base, refused.kin)),
                               np.asarray(M.predict(first.base, first.kin)), rtol=1e-6, atol=1e-9)


def test_kept_samples_of_sharp_steps_seen_by_the_position_alone_carry_no_inertial_error():
    # a velocity PI's steps made in a few samples, a quantised position the only sensor: the chosen
    # window and 2W-1 smear a step's acceleration alike, so their change does not see it. With the
    # TRUE parameters, the inertial torque's error on the kept samples (against the generator's exact
    # acceleration) must stay below the resolved share of the noise on every sample: the narrower
    # windows' check leaves the steps out (without it, 2.1 noise std at the first step)
    plant = T.Plant(J=0.09, Fc=0.65, Fs=1.0, vs=0.04, sigma2=0.85, sigma0=170.0, sigma1=1.0)
    ctrl = T.VelocityPIController(kp=4.0, ki=24.0)
    sens = T.Sensors(fs=300.0, torque_noise=0.1, velocity_noise=0.0, quantisation=0.001,
                     velocity_column=False, position_column=True)
    exc = T.Staircase(speeds=(0.05, 0.2, 0.8, 2.4, 4.5), dwell=2.0, transition=0.0, repeats=2, seed=7)
    g = T.generate(exc, [], plant, ctrl, sens, seed=4711)
    p = {f: getattr(plant, f) for f in ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta")}
    prep, split = _prepare(g.to_recording(), DiagnoseConfig(), p | {"offset": 0.0, "friction_model": "LuGre"},
                           "lugre", False)
    keep = split.keep > 0
    sd = g.torque_noise_std
    assert keep.mean() > 0.3  # the steps go, the constant-speed stretches stay
    inertial = plant.J * (np.asarray(prep.kin.a) - np.asarray(g.true["acceleration"]))
    assert np.max(np.abs(inertial[keep])) < DiagnoseConfig().resolved_share * sd
