"""diagnose on recordings from the INDEPENDENT generator (lugre_jax.testing, scipy solve_ivp): the
generator against the project's simulator, the null case, each candidate, and conditioning."""

from __future__ import annotations

import numpy as np
import pytest

import lugre_jax
from lugre_jax import testing as T
from lugre_jax.diagnose import diagnose
from lugre_jax.diagnose._condition import hf_noise_std, quantisation_step


def test_generator_agrees_with_project_simulator():
    """Same plant, PI and reference (a 3-deg position sine as a velocity reference, the paper's
    sine-tracking run) in both: the scipy LSODA reference and lugre_jax.simulate (adaptive, rtol 1e-10)
    agree to 1e-5 in velocity and torque -- two codes written separately from the equations."""
    plant = T.Plant(sigma2=2.0)  # passive: sigma2 >= sigma1*(Fs - Fc)/Fc, as lugre_jax.LuGre requires
    pi = T.VelocityPIController()
    g = T.generate(T.PositionSineExcitation(3.0, 0.4, duration=2.5), (), plant, pi,
                   T.Sensors(fs=100.0, torque_noise=0.0, velocity_noise=0.0, quantisation=0.0))
    sysm = lugre_jax.System(
        friction=lugre_jax.LuGre(Fc=plant.Fc, Fs=plant.Fs, vs=plant.vs, sigma2=plant.sigma2,
                                 sigma0=plant.sigma0, sigma1=plant.sigma1),
        joint=lugre_jax.Joint(J=plant.J), controller=lugre_jax.VelocityPID(kp=pi.kp, ki=pi.ki),
        reference=lugre_jax.PositionSine(3.0, 0.4))
    sol = lugre_jax.simulate(sysm, 2.5, 100.0, stepping=lugre_jax.Adaptive(rtol=1e-10, atol=1e-12))
    assert int(sol.result) == 0
    om = np.asarray(sol.ys[:, 1])
    np.testing.assert_allclose(g.true["omega"], om, atol=1e-5 * np.max(np.abs(om)))
    np.testing.assert_allclose(g.true["torque"], np.asarray(sol.torque_nm), atol=1e-5 * 6.0)


def test_generator_compliance_has_the_rigid_limit():
    """A stiff, damped spring (40 Hz, zeta 0.5, far above the 0.4 Hz sine) behind J_load = 0.02 of
    the joint's J = 0.1: the two masses move as one, so the torque is the rigid joint's (the lag's
    torque J_load*2*zeta/w*jerk is about 0.004 N*m here; tolerance 0.02). A load torque of the wrong
    sign on the motor would leave an inertia J - 2*J_load, 2*J_load*a = 0.77 N*m at the peak."""
    s = T.Sensors(fs=100.0, torque_noise=0.0, velocity_noise=0.0, quantisation=0.0)
    exc = T.PositionSineExcitation(3.0, 0.4, duration=2.5)
    rigid = T.generate(exc, (), sensors=s)
    stiff = T.generate(exc, [T.ComplianceEffect(40.0, 0.5, 0.02)], sensors=s)
    k = rigid.time > 0.5  # after the start's step of the velocity reference has rung out
    np.testing.assert_allclose(stiff.true["torque"][k], rigid.true["torque"][k], atol=0.02)


def test_noise_estimates_recover_generator_settings():
    g = T.generate(T.Multisine(duration=8.0), (), sensors=T.Sensors(fs=200.0, torque_noise=0.08,
                                                                      velocity_noise=0.003, quantisation=0.0005))
    assert abs(hf_noise_std(g.torque) / 0.08 - 1) < 0.05
    assert abs(hf_noise_std(g.velocity) / 0.003 - 1) < 0.05
    assert abs(quantisation_step(g.position) / 0.0005 - 1) < 1e-6


def test_coloured_torque_noise_is_generated_and_estimated():
    """Sensors(torque_noise_hz=10) at 200 Hz: the torque noise is an AR(1) of coefficient
    exp(-2*pi*10/200) = 0.73 (lag-1 autocorrelation within 0.03) and std 0.08 (within 5 %); the
    white-noise estimate sees about 0.035, the colour-aware one 0.08 within 10 %."""
    from lugre_jax.diagnose._condition import torque_noise_std

    g = T.generate(T.Multisine(duration=12.0), (), sensors=T.Sensors(fs=200.0, torque_noise=0.08,
                                                                       torque_noise_hz=10.0), seed=4)
    e = g.torque - g.true["torque"]
    assert abs(np.std(e) / 0.08 - 1) < 0.05
    assert abs(np.corrcoef(e[1:], e[:-1])[0, 1] - np.exp(-2 * np.pi * 10 / 200)) < 0.03
    assert hf_noise_std(g.torque) < 0.05
    est = torque_noise_std(g.torque)
    sd, phi = est.std, est.phi
    assert abs(sd / 0.08 - 1) < 0.10 and phi > 0.5


def _fast_multisine_coloured(seed=1):
    # AR(1) 0.6 at 200 Hz under a 4 deg/s multisine up to 1.8 Hz: the profile's long lags, which tell
    # the colour, also hold the motion's fast torque changes
    return T.generate(T.Multisine(duration=37.5, amplitude=4.0, f0=0.055, f1=1.8, n=11), (),
                      sensors=T.Sensors(fs=200.0, torque_noise=0.08, torque_noise_ar=0.6, velocity_noise=0.003),
                      seed=seed)


def test_torque_noise_through_a_prediction_leaves_the_signal_out():
    """On that recording the profile alone reads the noise more than 15 % high; with the noise-free
    torque as the prediction (refined_torque_noise) it is within 7 % of the generated noise's std,
    and so is the diagnosis's own estimate through its fitted baseline (the pipeline's _noise
    stage), while the estimate made before the fit stays high."""
    from lugre_jax.diagnose import DiagnoseConfig
    from lugre_jax.diagnose import _model as M
    from lugre_jax.diagnose import _select as S
    from lugre_jax.diagnose._condition import refined_torque_noise, torque_noise_std

    g = _fast_multisine_coloured()
    true = g.torque_noise_std
    s0 = torque_noise_std(g.torque).std
    assert s0 > 1.15 * true
    refined = refined_torque_noise(g.torque, g.true["torque"], s0)
    s1, phi = refined.std, refined.phi
    assert abs(s1 / true - 1) < 0.07 and phi > 0.4
    prep, _ = S._prepare(g.to_recording(), DiagnoseConfig(), None, "lugre", False)
    assert prep.cond.torque_noise > 1.15 * true
    refined = S._noise(prep, np.asarray(M.predict(prep.base, prep.kin), float), DiagnoseConfig())
    assert abs(refined.cond.torque_noise / true - 1) < 0.07
    assert refined.info["torque_noise_before_fit"]["std_nm"] == prep.cond.torque_noise


def _short_staircase(seed=0):
    return T.Staircase(speeds=(0.02, 0.1, 0.5, 2.0), dwell=4.0, seed=seed)


def test_null_independent_recording_gives_none_at_floor():
    g = T.generate(_short_staircase(), (), sensors=T.Sensors(fs=100.0), seed=5)
    rep = diagnose(g.to_recording(), progress=False)
    b = rep.baseline
    assert rep.verdict == "none", rep.mismatch
    # the estimated floor is the torque noise (0.08) within 5 %, and the baseline is within 10 % of it
    assert abs(b.noise_floor_nm / 0.08 - 1) < 0.05
    assert b.floor_ratio < 1.10 and b.at_floor


@pytest.mark.parametrize("q", [0.0005, 0.005])
def test_no_velocity_column_conditions_from_position(q):
    """An encoder only (no velocity column; 0.0005 and 0.005-deg steps): the kinematics come from
    the position, the torque noise is estimated within 5 %, the baseline is within 10 % of its floor,
    nothing is located and no candidate is named. The attribution is not asserted on this one
    recording: at 0.005 deg its v|v| term sits at p_family 2/120, exactly alpha/3 (3/100 with 99
    draws), where a calibrated test fires with that probability; its level is checked over many
    recordings in test_diagnose_calibration."""
    g = T.generate(_short_staircase(1), (), sensors=T.Sensors(fs=100.0, velocity_column=False, quantisation=q),
                   seed=6)
    rec = g.to_recording()
    assert rec.meta["velocity_measured"] is False
    rep = diagnose(rec, progress=False)
    b = rep.baseline
    assert b.conditioning["source"] == "position"
    assert abs(b.torque_noise_nm / 0.08 - 1) < 0.05
    assert b.noise_floor_nm >= b.torque_noise_nm
    assert b.floor_ratio < 1.10, b
    assert not rep.mismatch and set(rep.named) <= {"unexplained"}, (rep.verdict, rep.mismatch)


@pytest.mark.slow
def test_gravity_not_named_on_small_position_span():
    """Issue #20's +-3 deg sine: a gravity fitted there is a line in disguise; it must not be named."""
    g = T.generate(T.PositionSineExcitation(3.0, 0.4, duration=30.0), [T.GravityEffect(0.3, 0.5)],
                   sensors=T.Sensors(fs=100.0), seed=2)
    rep = diagnose(g.to_recording(), progress=False, candidates=["gravity", "asymmetry"])
    assert "gravity" not in rep.named, rep.selection_log


# each candidate, well above the concealed level, on a short independent staircase of issue #20's
# kind (100 Hz); the candidate competes with two rivals (the full library competes in
# experiments/diagnose_independent). Each case has its own excitation: the 5-speed staircase shows
# most effects, but a Stribeck exponent needs speeds spread over the curve's fall (8 speeds, otherwise
# the baseline's Fs and vs absorb delta) and gravity a longer position span. Slow: a few minutes each.
_FIVE = T.Staircase(speeds=(0.02, 0.1, 0.5, 2.0, 4.0), dwell=6.0, seed=3)
EFFECT_CASES = {
    "position_ripple": ([T.PositionRippleEffect(0.12, 5.0, 1.0)], "period", 5.0, 0.05, _FIVE),
    "asymmetry": ([T.AsymmetryEffect(0.1)], "offset", 0.1, 0.3, _FIVE),
    "thermal_drift": ([T.ThermalDriftEffect(-0.1 / 64.0)], "rate", -0.1 / 64.0, 0.3, _FIVE),
    "stribeck_shape": ([T.StribeckShapeEffect(1.0)], "delta", 1.0, 0.15, T.Staircase(dwell=4.0, seed=3)),
    "load_dependent": ([T.LoadDependentEffect(0.15, 0.02)], "mu", 0.15, 0.3, _FIVE),
    "compliance": ([T.ComplianceEffect(3.0, 0.05, 0.02)], "fn_hz", 3.0, 0.1, _FIVE),
    # share 0.1 of the friction behind the gap is not located on this staircase (the baseline's Fs
    # and sigma0 absorb it, validation RMSE 1.03x the floor); 0.3 is
    "backlash": ([T.BacklashEffect(0.05, 0.3)], "share", 0.3, 0.4, _FIVE),
    "gravity": ([T.GravityEffect(0.3, -0.3)], "amplitude", 0.3, 0.3,
                T.Staircase(speeds=(0.02, 0.1, 0.5, 2.0, 4.0), dwell=12.0, seed=3)),
}
RIVALS = {"position_ripple": ["gravity", "asymmetry"], "asymmetry": ["gravity", "thermal_drift"],
          "thermal_drift": ["asymmetry", "gravity"], "stribeck_shape": ["asymmetry", "load_dependent"],
          "load_dependent": ["asymmetry", "compliance"], "compliance": ["load_dependent", "asymmetry"],
          "backlash": ["stribeck_shape", "asymmetry"], "gravity": ["position_ripple", "asymmetry"]}


@pytest.mark.slow
@pytest.mark.parametrize("effect", list(EFFECT_CASES))
def test_each_candidate_on_independent_recording(effect):
    effs, key, true, tol, exc = EFFECT_CASES[effect]
    g = T.generate(exc, effs, sensors=T.Sensors(fs=100.0), seed=9)
    rep = diagnose(g.to_recording(), progress=False, max_effects=1, candidates=RIVALS[effect] + [effect])
    assert rep.named[:1] == [effect], (effect, rep.verdict, rep.selection_log)
    first = rep.missing_physics[0]
    assert abs(first.params[key] - true) <= tol * abs(true), (effect, first.params)


def test_held_out_phase_keeps_periodic_reversals_in_the_fit():
    """A +-5-deg, 0.1-Hz position sine from rest (issue #20's plant, 100 Hz): it reverses 2.5 s
    into every 5 s, so with phases ``block % 5`` every reversal would fall in the held-out phase and
    a fit without a single reversal is 19x its floor. The drawn phases hold at most half of them
    in the held-out phase, and the diagnosis is `none`, within 10 % of the floor."""
    from lugre_jax.diagnose._model import block_ids, block_phase

    g = T.generate(T.PositionSineExcitation(5.0, 0.1, duration=60.0), (), sensors=T.Sensors(fs=100.0), seed=1)
    rec = g.to_recording()
    rep = diagnose(rec, progress=False)
    held = rep.recording.held_out_phase
    assert f"phase {held} (" in rep.recording.validation  # the words say the same phase
    t = np.asarray(rec.time)
    reversals = np.flatnonzero(np.diff(np.sign(g.velocity_ref)) != 0)
    ph = block_phase(block_ids(t))[reversals]
    assert np.mean(ph == held) <= 0.5, (held, np.bincount(ph, minlength=5))
    assert rep.baseline.floor_ratio < 1.10, rep.baseline
    assert rep.verdict == "none", rep.mismatch


def test_block_phases_are_interleaved_and_not_periodic():
    """block_phase: every run of five consecutive blocks gives each phase one block and no two
    neighbouring blocks share a phase (no regime is lost to a phase), and events periodic in five blocks (a move every 5 s, 1-s blocks) spread over
    the phases: 20 such events are not all in one phase, and none holds more than half of them
    (blocks % 5 would put all 20 in one)."""
    from lugre_jax.diagnose._model import block_ids, block_phase

    t = np.arange(0.0, 100.0, 0.01)
    blocks = block_ids(t)
    ph = block_phase(blocks)
    per_block = np.array([ph[blocks == b][0] for b in range(blocks.max() + 1)])
    for run in range(len(per_block) // 5):
        assert sorted(per_block[5 * run:5 * run + 5]) == [0, 1, 2, 3, 4]
    events = per_block[2::5]
    assert np.bincount(events, minlength=5).max() <= 10, np.bincount(events, minlength=5)
    assert np.array_equal(block_phase(blocks), ph)  # seeded: the same split every time
    many = block_phase(np.arange(5000))
    assert not np.any(many[1:] == many[:-1])  # no two neighbouring blocks in one phase
    assert np.array_equal(np.bincount(many), [1000] * 5)


def test_validation_phase_moves_only_off_concentrated_events():
    """phase_off_events on phases_holding_events: the fixed phase 2 unless it holds more than 0.6 of
    some kind of event and more than chance allows (binomial p < 0.001); then the least loaded
    phase, the nearest to 2 on ties. Events are placed in the middle of blocks of a given phase."""
    from lugre_jax.diagnose import DiagnoseConfig
    from lugre_jax.diagnose._model import block_ids, block_phase, phase_off_events, phases_holding_events

    cfg = DiagnoseConfig()

    def phase(blocks, events):
        return phase_off_events(*phases_holding_events(blocks, events, max_share=cfg.max_event_share,
                                                        alpha=cfg.event_alpha))

    t = np.arange(0.0, 100.0, 0.01)
    blocks = block_ids(t)
    ph = block_phase(blocks)
    middle = np.round(t - np.floor(t), 2) == 0.5

    def at(p, first=None):
        """The middles of the blocks of phase p (the first ``first`` of them)."""
        m = middle & (ph == p)
        if first is not None:
            m &= np.cumsum(m) <= first
        return m

    assert phase(blocks, [at(2)]) == 1  # all 20 in phase 2
    assert phase(blocks, [middle]) == 2  # spread evenly
    assert phase(blocks, [at(2, 4)]) == 2  # four of four: p 0.0016
    assert phase(blocks, [at(2, 5)]) == 1  # five of five: p 0.0003
    assert phase(blocks, [at(2, 4) | at(0, 1) | at(4, 1)]) == 2  # 4/6: p 0.017
    assert phase(blocks, [at(2) | at(1)]) == 2  # 0.5
    assert phase(blocks, [at(2) | at(1, 4)]) == 3


@pytest.mark.slow
def test_held_out_test_crosses_all_block_phases():
    """A 5-s-dwell staircase with sharp steps (heavy joint, position only, Stribeck exponent 1.2
    instead of 2; the held-out study's recording): one phase's blocks hold few of the transitions
    (with phases ``block % 5``, only settled speeds, and a held-out test on that phase alone misses
    the change: p > 0.05 against a BIC drop of hundreds). Crossed over all five phases, the test
    sees the transitions and the change is named, its exponent within 20 %."""
    plant = T.Plant(J=0.4, Fc=2.0, Fs=3.0, vs=0.15, sigma2=0.8, sigma0=40.0, sigma1=3.0)
    g = T.generate(T.Staircase(dwell=5.0, transition=0.0, seed=3104), [T.StribeckShapeEffect(1.2)], plant,
                   T.VelocityPIController(kp=25.0, ki=150.0),
                   T.Sensors(fs=150.0, torque_noise=0.05, velocity_noise=0.0, quantisation=0.002,
                             velocity_column=False), seed=3104)
    rep = diagnose(g.to_recording(), progress=False)
    first = rep.selection_log[0]["joint_refits"]
    stribeck = next(t for t in first if t["name"] == "stribeck_shape")
    assert stribeck["p_family"] < rep.alpha / 3 and stribeck["rejected_because"] is None, stribeck
    assert rep.named == ["stribeck_shape"], (rep.verdict, rep.selection_log)
    assert abs(rep.missing_physics[0].params["delta"] / 1.2 - 1) < 0.2, rep.missing_physics[0].params


@pytest.mark.slow
def test_window_is_chosen_again_for_the_fitted_inertia():
    """A multisine through zero speed (nearly flat Stribeck curve, 500 Hz, velocity column; the fresh
    set's effect-free recording): friction's bristle dynamics make the linear inertia negative, it
    is clipped to ~0, and for no inertia the longest window (0.3 s) looked best. That window
    attenuated the 2-Hz top line's acceleration by ~20 %, the fit raised J by 22 % and the line was
    left 'unexplained'. Chosen again for the fitted inertia, the window is short enough: `none`, J
    within 5 % of the truth and the floor ratio within 10 %."""
    plant = T.Plant(J=0.08, Fc=1.5, Fs=1.7, vs=0.3, sigma2=0.3, sigma0=80.0, sigma1=2.0)
    g = T.generate(T.Multisine(amplitude=1.0, f0=0.1, f1=2.0, n=6, duration=60.0), [], plant,
                   T.VelocityPIController(kp=5.0, ki=30.0),
                   T.Sensors(fs=500.0, torque_noise=0.08, velocity_noise=0.005, quantisation=0.0005), seed=4006)
    rep = diagnose(g.to_recording(), progress=False)
    first = rep.baseline.fit["window_rechosen_from"]
    assert first["window"] * 0.002 > 0.25 and first["inertia"] < 0.01, first
    assert rep.baseline.conditioning["window"] * 0.002 < 0.2, rep.baseline.conditioning
    assert rep.verdict == "none", (rep.verdict, rep.selection_log)
    assert abs(rep.baseline.params["J"] / 0.08 - 1) < 0.05, rep.baseline.params
    assert rep.baseline.floor_ratio < 1.1


@pytest.mark.slow
def test_cross_validation_skips_a_phase_that_holds_every_step():
    """Issue #20's staircase with 10-s dwells (100 Hz) and a 0.08-N*m, 6-deg ripple: every step
    starts a block of phase 0, so a refit without that phase has no acceleration to fix the inertia
    (it fell to 0.006 and the ripple's cross-validated error rose, `asymmetry+unexplained`). That
    phase is left out of the test: the ripple is named, its period within 2 %."""
    g = T.generate(T.Staircase(dwell=10.0, seed=4102), [T.PositionRippleEffect(0.08, 6.0, 2.0)],
                   sensors=T.Sensors(fs=100.0), seed=4102)
    rep = diagnose(g.to_recording(), progress=False)
    assert rep.named == ["position_ripple"], (rep.verdict, rep.selection_log)
    assert abs(rep.missing_physics[0].params["period"] / 6.0 - 1) < 0.02, rep.missing_physics[0].params


def test_nothing_resolved_is_one_clear_error():
    """A coarse encoder on a joint creeping at one step per second: no sample's speed is resolved, so
    no baseline can be fitted; the diagnosis says so in one line instead of failing inside the fit."""
    from lugre_jax.io import recording_from_arrays

    rng = np.random.default_rng(0)
    t = np.arange(3000) / 100.0
    q = 0.01
    v = 0.01 * np.sign(np.sin(2 * np.pi * t / 15.0))
    th = q * np.round(np.cumsum(v) / 100.0 / q)
    tau = 1.2 * np.sign(v) + 0.05 * rng.standard_normal(t.size)
    rec = recording_from_arrays(t, th, None, tau, source="creep.csv")
    with pytest.raises(ValueError) as e:
        diagnose(rec, progress=False)
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith("creep.csv: only ") and "resolved" in msg


def test_supplied_acceleration_is_kept_only_where_the_data_prefer_it():
    """An acceleration that comes with the data (EMPS: computed upstream at 1 kHz) competes with the
    chosen Savitzky-Golay window on resolved samples per unit of the linear inverse model's residual.
    The exact acceleration of a sharp-step staircase at 100 Hz resolves the samples next to the steps
    that every window's bias leaves out, so it is kept (unresolved 3 % against 12 %); the same
    recording without it conditions from a window, as before. On a multisine, an acceleration
    delayed by 50 ms leaves more residual than the window (0.178 against 0.167 N*m^2) and is
    dropped."""
    from lugre_jax.diagnose._condition import condition
    from lugre_jax.io import recording_from_arrays

    p = T.Plant()

    def source_of(g, acc):
        rec = recording_from_arrays(g.time, g.position, g.velocity, g.torque, acceleration=acc)
        assert rec.meta["acceleration_supplied"] is (acc is not None)
        return condition(rec, p.J, p.sigma2)[1]

    stairs = T.generate(T.Staircase(speeds=(0.1, 0.5, 2.0), dwell=3.0, transition=0.0, repeats=1, seed=1), (),
                        sensors=T.Sensors(fs=100.0, velocity_noise=0.0, quantisation=0.0), seed=3)
    derived = source_of(stairs, None)
    kept = source_of(stairs, stairs.true["acceleration"])
    assert derived.source != "recording"
    assert kept.source == "recording" and kept.unresolved_fraction < derived.unresolved_fraction
    sine = T.generate(T.Multisine(duration=8.0), (), sensors=T.Sensors(fs=200.0, quantisation=0.0), seed=3)
    assert source_of(sine, np.roll(sine.true["acceleration"], 10)).source != "recording"


def test_window_order_five_near_the_top_frequency():
    """A multisine to 2.5 Hz seen by a 0.0005-deg encoder only (400 Hz; the held-out set's heavy
    joint): the best order-3 window attenuates the top lines' acceleration, and its smoothing bias
    leaves more than half of the samples unresolved. The choice over orders 3 and 5 takes order 5:
    against the exact acceleration, a smaller error and fewer unresolved samples."""
    from scipy.integrate import cumulative_trapezoid

    from lugre_jax.diagnose._condition import condition
    from lugre_jax.io import recording_from_arrays

    fs = 400.0
    t = np.arange(0.0, 70.0, 1.0 / fs)
    v = T.Multisine(amplitude=1.5, f0=0.05, f1=2.5, n=8, duration=70.0).v_ref(t)
    a = np.gradient(v, t)
    theta = np.concatenate([[0.0], cumulative_trapezoid(v, t)])
    rng = np.random.default_rng(0)
    rec = recording_from_arrays(t, np.round(theta / 0.0005) * 0.0005, None,
                                0.4 * a + 2.0 * np.sign(v) + 0.8 * v + rng.normal(0.0, 0.1, t.size))
    results = {}
    for label, choices in (("free", None), ("order 3", [("position", W, 3) for W in range(5, 122, 2)])):
        out, info, bad = condition(rec, 0.4, 0.8, choices=choices)
        err = np.asarray(out.acceleration)[~bad] - a[~bad]
        results[label] = (info.order, float(np.sqrt(np.mean(err ** 2))), float(bad.mean()))
    (order, err_free, bad_free), (_, err_3, bad_3) = results["free"], results["order 3"]
    assert order == 5, results
    assert err_free < 0.8 * err_3 and bad_free < 0.5 * bad_3, results


@pytest.mark.slow
def test_multisine_top_line_with_encoder_only():
    """The held-out set's heavy joint (J 0.4) under a multisine to 2.5 Hz, encoder only (0.0005 deg,
    400 Hz), with a 0.04-N*m asymmetry: the order-3 window (W 31) attenuated the 2.5-Hz line and
    left it 'unexplained' beside the asymmetry. Order 5 (W 61) resolves it: the asymmetry alone is
    named, its offset within 10 %, J within 2 %."""
    plant = T.Plant(J=0.4, Fc=2.0, Fs=3.0, vs=0.15, sigma2=0.8, sigma0=40.0, sigma1=3.0)
    g = T.generate(T.Multisine(amplitude=1.5, f0=0.05, f1=2.5, n=8, duration=70.0), [T.AsymmetryEffect(0.04)],
                   plant, T.VelocityPIController(kp=25.0, ki=150.0),
                   T.Sensors(fs=400.0, torque_noise=0.1, velocity_noise=0.002, quantisation=0.0005,
                             velocity_column=False), seed=3103)
    rep = diagnose(g.to_recording(), progress=False)
    assert rep.baseline.conditioning["order"] == 5, rep.baseline.conditioning
    assert rep.named == ["asymmetry"], (rep.verdict, rep.selection_log)
    assert abs(rep.missing_physics[0].params["offset"] / 0.04 - 1) < 0.1, rep.missing_physics[0].params
    assert abs(rep.baseline.params["J"] / 0.4 - 1) < 0.02, rep.baseline.params


@pytest.mark.slow
def test_drift_on_a_fast_sharp_staircase():
    """The fresh set's drift recording: a flat Stribeck curve whose viscous part doubles the
    friction at 5 deg/s, 2.5-s sharp steps at 1 kHz, friction -8 % over 50 s. The trend test on
    sign(v) missed it (t 3.0, 'none'); on the friction torque it is named, the change within 10 %."""
    plant = T.Plant(J=0.08, Fc=1.5, Fs=1.7, vs=0.3, sigma2=0.3, sigma0=80.0, sigma1=2.0)
    g = T.generate(T.Staircase(speeds=(0.02, 0.1, 0.4, 1.5, 5.0), dwell=2.5, transition=0.0, seed=4103),
                   [T.ThermalDriftEffect(-0.08 / 50.0)], plant, T.VelocityPIController(kp=5.0, ki=30.0),
                   T.Sensors(fs=1000.0, torque_noise=0.1, velocity_noise=0.003, quantisation=0.0005), seed=4103)
    rep = diagnose(g.to_recording(), progress=False)
    assert rep.named == ["thermal_drift"], (rep.verdict, rep.selection_log)
    change = rep.missing_physics[0].params["relative_change_over_recording"]
    assert abs(change / -0.08 - 1) < 0.1, rep.missing_physics[0].params


@pytest.mark.slow
def test_order_five_noise_band_is_not_a_line():
    """The held-out set's effect-free position-sine recording (paper-like joint, +-5 deg at 0.2 Hz,
    encoder only, 0.001 deg, 120 Hz): an order-5 window of 17 samples scored best, but its
    acceleration noise on the torque was 0.93 of the torque noise, concentrated just below its
    cut-off, and showed as a 10.6-Hz time line ('position_ripple+unexplained'). Order 5 is now
    considered only below half the torque noise: order 3, `none`, at the floor."""
    plant = T.Plant(J=0.128, Fc=1.0, Fs=1.6, vs=0.2, sigma2=0.5, sigma0=100.0, sigma1=2.0)
    g = T.generate(T.PositionSineExcitation(amplitude=5.0, frequency=0.2, duration=60.0), [], plant,
                   T.VelocityPIController(kp=4.0, ki=20.0),
                   T.Sensors(fs=120.0, torque_noise=0.05, velocity_noise=0.0, quantisation=0.001,
                             velocity_column=False), seed=3009)
    rep = diagnose(g.to_recording(), progress=False)
    c = rep.baseline.conditioning
    assert c["order"] == 3 or c["accel_noise_torque"] <= 0.5 * c["torque_noise"], c
    assert rep.verdict == "none", (rep.verdict, rep.selection_log)
    assert rep.baseline.floor_ratio < 1.1


def _run_module():
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "experiments" / "diagnose_independent" / "run.py"
    spec = importlib.util.spec_from_file_location("diagnose_independent_run", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_rebuilt_studies_cover_their_design():
    """The calib, fresh3 and outside studies as committed (no generation, no diagnosis): calib has
    >= 44 effect-free rows with every excitation x loop x sensor set, white and AR(1) noise, >= 2
    plants, 100-1,000 Hz; fresh3 three rows per in-library effect (expected: its id) and eight
    effect-free rows on plants no earlier study used; outside two rows per outside effect; every
    recording <= 60 s and <= 60,000 samples; keys unique."""
    run = _run_module()
    calib, fresh3, outside = run.calib_settings(), run.fresh3_settings(), run.outside_settings()
    for rows in (calib, fresh3, outside):
        assert len({r["key"] for r in rows}) == len(rows)
        for r in rows:
            exc = run.excitation_of(r["excitation"], r["fs"], r["seed"], kw=r["excitation_kw"])
            assert exc.duration <= 60.0 and exc.duration * r["fs"] + 1 <= 60_000, r["key"]
            assert 100.0 <= r["fs"] <= 1000.0
            run.controller_of(r)
            run.effects_of(r)
    assert len(calib) >= 44 and all(r["expected"] == "none" and not r["effects"] for r in calib)
    combos = {(r["excitation"], r["controller"].startswith("pid"), r["position_column"], r["velocity_column"])
              for r in calib}
    assert len(combos) == 6 * 2 * 3
    assert {r["torque_noise_ar"] > 0 for r in calib} == {True, False} and len({r["plant"] for r in calib}) >= 2
    effects = [r for r in fresh3 if r["expected"] != "none"]
    assert len(effects) == 24 and len(fresh3) - len(effects) == 8
    assert sorted(r["expected"] for r in effects) == sorted(3 * list(T.EFFECTS))
    assert all(r["effects"] == [r["expected"]] for r in effects)
    used_before = {"issue", "paper_like", "light", "heavy", "medium", "flat"}
    assert not {r["plant"] for r in fresh3 + outside} & used_before
    assert sorted(r["effects"][0] for r in outside) == sorted(2 * list(T.OUTSIDE_EFFECTS))
    assert all(r["expected"] == "unexplained" and r["expected_dependence"] for r in outside)


@pytest.mark.slow
def test_a_library_term_that_predicts_better_keeps_a_name_off(tmp_path):
    """outside6_06: a time-periodic disturbance (outside the eight candidates) on a point-to-point run
    under a position PID without velocity feedforward. `position_ripple` takes part of it and passes
    its held-out test (cross-validated 0.1160 -> 0.1103 N*m), but the time line predicts the same
    phases better (0.0902 N*m): no candidate is named, and the attribution finds the time line
    (held-out 0.1137 -> 0.0891 N*m)."""
    run = _run_module()
    job = {j["key"]: j for j in run.jobs("outside6", [11], [1.0])}["outside6_06_time_disturbance_g"]
    g, _ = run.generated(job, tmp_path)
    rep = diagnose(g.to_recording(), progress=False)
    refit = rep.selection_log[0]["joint_refits"][0]
    assert refit["name"] == "position_ripple" and refit["rival"] == "time_periodic", refit
    assert refit["p_rival"] <= 0.05 / 3 and refit["cv_rmse_rival_nm"] < refit["cv_rmse_nm"], refit
    assert rep.verdict == "unexplained", rep.verdict
    assert rep.attribution["signals"][0] == "time_periodic", rep.attribution
    assert rep.attribution["validation_rmse_after_nm"] < rep.attribution["validation_rmse_before_nm"]


@pytest.mark.parametrize("phase, tie", [(-0.3, False), (-1.3, True)])
def test_a_gravity_the_excitation_cannot_tell_from_an_asymmetry_is_reported_with_it(phase, tie):
    """A 0.15 N*m gravity under a +-35 deg position sine. At phase -0.3 the sine's slope spans the
    travel: gravity is named alone (the held-out blocks reject a direction asymmetry in its place).
    At -1.3 the travel sits near the sine's trough, where the torque is nearly constant, which while
    sliding is a direction asymmetry: both pass every check, one is named and the other is reported
    as its alternative, the named one predicting the held-out blocks no better at the held-out
    test's level (alpha)."""
    from lugre_jax.diagnose import DiagnoseConfig

    g = T.generate(T.PositionSineExcitation(35.0, 0.05, duration=50.0), [T.GravityEffect(0.15, phase)],
                   sensors=T.Sensors(fs=100.0), seed=4)
    rep = diagnose(g.to_recording(), progress=False, candidates=["gravity", "asymmetry"])
    assert len(rep.missing_physics) == 1, rep.selection_log
    found = rep.missing_physics[0].to_json()
    if not tie:
        assert found["name"] == "gravity" and found["alternatives"] == [], found
    else:
        assert {found["name"]} | {a["name"] for a in found["alternatives"]} == {"gravity", "asymmetry"}, found
        assert all(a["p_named_better"] > DiagnoseConfig().alpha_confirm for a in found["alternatives"]), found


def test_samples_the_kinematics_noise_decides_leave_the_fit(monkeypatch):
    """An effect-free point-to-point recording under a position PID (the plant of calib55's third,
    320 Hz, position encoder of 0.001 deg and velocity sensor of 0.0042 deg/s): between moves the loop
    creeps within a few encoder steps of the bristles' pre-sliding length (Fs/sigma0 = 0.005 deg),
    where the sensors' noise moves the model torque by more than half the torque noise. Fitted over
    those samples, the baseline's Stribeck hump is off by errors in variables (Fs or vs more than 30 %
    from the truth: a candidate then takes up the difference); without them both are within 15 %."""
    from lugre_jax.diagnose import DiagnoseConfig, _select

    plant = T.Plant(J=0.065, Fc=0.738, Fs=0.977, vs=0.0688, sigma2=1.171, sigma0=201.0, sigma1=1.45)
    pid = T.PositionPIDController(kp=24.66, ki=120.08, kd=2.0257, tf=0.002, kff=2.0257)
    g = T.generate(T.PointToPoint(amplitudes=(2.9, -3.2, 3.0, -2.6, -2.7, 2.9), move_time=1.4, dwell=2.3,
                                  repeats=2), [], plant, pid,
                   T.Sensors(fs=320.0, torque_noise=0.08, velocity_noise=0.0042, quantisation=0.001), seed=24901)
    rec = g.to_recording()
    cfg = DiagnoseConfig()

    def stribeck_error(prep):
        f = prep.base.friction
        return max(abs(float(f.Fs) / plant.Fs - 1), abs(float(f.vs) / plant.vs - 1))

    prep, _ = _select._prepare(rec, cfg, None, "lugre", False)
    assert prep.info.get("kinematic_noise_unresolved", 0) > 100, prep.info
    assert stribeck_error(prep) < 0.15, prep.base
    with monkeypatch.context() as m:
        m.setattr(_select, "_kinematic_noise_unresolved", lambda *a: np.zeros(rec.n, bool))
        kept, _ = _select._prepare(rec, cfg, None, "lugre", False)
    assert stribeck_error(kept) > 0.3, kept.base
