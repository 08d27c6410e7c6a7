"""The independent recording generator (lugre_jax.testing): the position PID against the project's
simulator and on point-to-point moves, the coloured torque noise, and each effect outside the
diagnose candidates against the torque its physical form predicts."""

from __future__ import annotations

import numpy as np
import pytest

import lugre_jax
from lugre_jax import testing as T

QUIET = T.Sensors(fs=200.0, torque_noise=0.0, velocity_noise=0.0, quantisation=0.0)


def test_position_pid_agrees_with_project_simulator():
    """The project's cascade PositionPID (position P kpp feeding a velocity PI kp, ki) is, from rest,
    the position PID ``(kp*kpp + ki)*e + ki*kpp*int(e) + kp*(v_ref - v)``: the generator's PID with
    an unfiltered derivative and ``kff = kd``. On a 3-deg, 0.4-Hz position sine the scipy LSODA
    generator and lugre_jax.simulate (adaptive, rtol 1e-10) agree to 1e-6 of the peaks in
    position, velocity and torque -- two codes written separately from the equations."""
    plant = T.Plant(sigma2=2.0)  # passive: sigma2 >= sigma1*(Fs - Fc)/Fc, as lugre_jax.LuGre requires
    kpp, kp, ki = 8.0, 3.0, 20.0
    g = T.generate(T.PositionSineExcitation(3.0, 0.4, duration=2.5), (), plant,
                   T.PositionPIDController(kp=kp * kpp + ki, ki=ki * kpp, kd=kp, tf=0.0, kff=kp),
                   T.Sensors(fs=100.0, torque_noise=0.0, velocity_noise=0.0, quantisation=0.0))
    sysm = lugre_jax.System(
        friction=lugre_jax.LuGre(Fc=plant.Fc, Fs=plant.Fs, vs=plant.vs, sigma2=plant.sigma2,
                                 sigma0=plant.sigma0, sigma1=plant.sigma1),
        joint=lugre_jax.Joint(J=plant.J), controller=lugre_jax.PositionPID(kpp=kpp, kp=kp, ki=ki),
        reference=lugre_jax.PositionSine(3.0, 0.4))
    sol = lugre_jax.simulate(sysm, 2.5, 100.0, stepping=lugre_jax.Adaptive(rtol=1e-10, atol=1e-12))
    assert int(sol.result) == 0
    th, om, tau = np.asarray(sol.ys[:, 0]), np.asarray(sol.ys[:, 1]), np.asarray(sol.torque_nm)
    np.testing.assert_allclose(g.true["theta"], th, atol=1e-6 * np.max(np.abs(th)))
    np.testing.assert_allclose(g.true["omega"], om, atol=1e-6 * np.max(np.abs(om)))
    np.testing.assert_allclose(g.true["torque"], tau, atol=1e-6 * np.max(np.abs(tau)))
    np.testing.assert_allclose(g.position_ref, 3.0 * np.sin(0.8 * np.pi * g.time), atol=1e-12)


def test_filtered_derivative_tends_to_the_unfiltered_one():
    """The derivative's low-pass (time constant tf) is a first-order lag of the velocity: as tf
    shrinks the loop tends to the unfiltered one, the torque's difference shrinking about in
    proportion to tf (a filter that were not applied, or applied to the wrong signal, would not)."""
    exc = T.PointToPoint(amplitudes=(3.0, -1.0), move_time=1.5, dwell=1.0)
    base = T.PositionPIDController.tuned(0.1, tf=0.0)
    ref = T.generate(exc, (), controller=base, sensors=QUIET).true["torque"]
    d = [np.max(np.abs(T.generate(exc, (), controller=T.PositionPIDController(base.kp, base.ki, base.kd, tf, base.kff),
                                  sensors=QUIET).true["torque"] - ref)) for tf in (4e-3, 1e-3)]
    assert d[1] < 0.4 * d[0] and d[0] > 1e-4, d


@pytest.mark.parametrize("feedforward, limit", [(True, 0.03), (False, 0.10)])
def test_position_pid_tracks_point_to_point_moves(feedforward, limit):
    """Issue #20's plant under the 3-Hz tuned position PID on point-to-point moves of 2-6 deg (2 s
    minimum-jerk moves, 3 s dwells): the rms tracking error is below 3 % of the mean move with the
    velocity feedforward and below 10 % without it, and at the end of every dwell the joint sits
    within 1 % of the mean move of its set point (the integral has removed the friction's offset)."""
    exc = T.PointToPoint()
    g = T.generate(exc, (), controller=T.PositionPIDController.tuned(0.1, feedforward=feedforward), sensors=QUIET)
    moves = np.abs(np.diff(np.concatenate([[0.0], exc.amplitudes])))
    err = g.true["theta"] - g.position_ref
    assert np.sqrt(np.mean(err ** 2)) < limit * moves.mean()
    period = exc.move_time + exc.dwell
    ends = np.searchsorted(g.time, period * np.arange(1, len(exc.amplitudes) + 1) - 0.01)
    np.testing.assert_allclose(g.true["theta"][ends], exc.amplitudes, atol=0.01 * moves.mean())


def test_every_excitation_runs_under_both_controllers():
    """Any excitation drives either loop: a position PID follows the integral of a velocity
    reference (staircase, sweep) and a velocity PI the derivative of a point-to-point move; the
    recorded position reference is the integral of the velocity reference (trapezoid, 1 kHz)."""
    from scipy.integrate import cumulative_trapezoid

    s = T.Sensors(fs=1000.0, torque_noise=0.0, velocity_noise=0.0, quantisation=0.0)
    for exc in (T.Staircase(speeds=(0.5, 2.0), dwell=2.0, transition=0.0, repeats=1), T.SineSweep(duration=6.0),
                T.PointToPoint(amplitudes=(2.0, -1.0), move_time=1.0, dwell=1.0)):
        g = T.generate(exc, (), controller=T.PositionPIDController.tuned(0.1), sensors=s)
        integral = np.concatenate([[0.0], cumulative_trapezoid(g.velocity_ref, g.time)])
        assert np.max(np.abs(g.position_ref - integral)) < 1e-3 * max(np.max(np.abs(integral)), 1.0)
        assert np.sqrt(np.mean((g.true["theta"] - g.position_ref) ** 2)) < 0.1 * np.ptp(g.position_ref)
    g = T.generate(T.PointToPoint(amplitudes=(2.0, -1.0), move_time=1.0, dwell=1.0), (), sensors=s)
    assert g.position_ref is None and np.sqrt(np.mean((g.true["omega"] - g.velocity_ref) ** 2)) < 0.5


def test_ar1_torque_noise_has_its_coefficient():
    """Sensors(torque_noise_ar=0.6): the recorded torque noise's sample autocorrelation is 0.6 at
    lag 1 and 0.36 at lag 2 (within 0.05: the estimator's std is about 0.013 on 4,000 samples),
    its std 0.08 within 5 %; ``torque_noise_std`` is the std of the noise actually added."""
    g = T.generate(T.Multisine(duration=20.0), (), sensors=T.Sensors(fs=200.0, torque_noise=0.08,
                                                                       torque_noise_ar=0.6), seed=3)
    e = g.torque - g.true["torque"]
    np.testing.assert_allclose(e, g.true["torque_noise"], atol=1e-12)
    assert g.torque_noise_std == pytest.approx(np.std(e), rel=1e-12)
    assert abs(g.torque_noise_std / 0.08 - 1) < 0.05
    e = e - e.mean()
    acf = [np.dot(e[k:], e[:-k]) / np.dot(e, e) for k in (1, 2)]
    assert abs(acf[0] - 0.6) < 0.05 and abs(acf[1] - 0.36) < 0.05, acf
    white = T.generate(T.Multisine(duration=20.0), (), sensors=T.Sensors(fs=200.0, torque_noise=0.08), seed=3)
    w = white.true["torque_noise"]
    assert abs(np.dot(w[1:], w[:-1]) / np.dot(w, w)) < 0.05
    with pytest.raises(ValueError):
        T.Sensors(torque_noise_ar=0.5, torque_noise_hz=10.0)


# Outside effects: each against the torque its physical form predicts, on the last second of every
# dwell of a velocity staircase (speeds 0.5-3 deg/s, settled: the PI holds the speed, so the
# effect-free joint's friction there is known) or along the whole recording.
_STAIRS = T.Staircase(speeds=(0.5, 1.5, 3.0), dwell=4.0, transition=0.5, repeats=1)


def _settled(g):
    return ((g.time % _STAIRS.dwell) > _STAIRS.dwell - 1.0) & (np.abs(g.velocity_ref) >= 0.5)


def test_quadratic_drag_adds_c_v_abs_v():
    """At constant speed the loop's torque with the drag exceeds the effect-free one by c*v*|v|
    (to 1e-4 of the drag's peak, the loop's settling)."""
    c = 0.01
    free = T.generate(_STAIRS, (), sensors=QUIET)
    drag = T.generate(_STAIRS, [T.QuadraticDragEffect(c)], sensors=QUIET)
    k = _settled(drag)
    v = drag.true["omega"][k]
    np.testing.assert_allclose(drag.true["torque"][k] - free.true["torque"][k], c * v * np.abs(v),
                               atol=1e-4 * c * 9.0)


def test_time_disturbance_is_a_sine_in_time():
    """The loop's torque with the disturbance exceeds the effect-free one by
    A*sin(2*pi*f*t + phase) on every settled sample, whatever the speed, direction or position
    (within 5 % of A: the PI rejects the 0.13-Hz disturbance with a small velocity error, whose
    viscous and inertial torques differ from the effect-free run's)."""
    d = T.TimeDisturbanceEffect(0.05, 0.13, 0.4)
    free = T.generate(_STAIRS, (), sensors=QUIET)
    dist = T.generate(_STAIRS, [d], sensors=QUIET)
    k = _settled(dist)
    want = d.amplitude * np.sin(2 * np.pi * d.frequency * dist.time[k] + d.phase)
    np.testing.assert_allclose(dist.true["torque"][k] - free.true["torque"][k], want, atol=0.05 * d.amplitude)


def test_torque_dependent_friction_grows_with_the_transmitted_torque():
    """At constant speed the mesh carries the whole motor torque (no acceleration), so the torque
    solves tau = tau_free + mu*|tau|*sign(v): tau = tau_free/(1 - mu) (to 1e-6 relative). Along
    the moves the extra torque is mu*|tau - rotor_share*J*a|*tanh(v/v_eps) (to 1e-6 of its peak),
    larger accelerating than braking, unlike the load_dependent candidate's mu*|J*a|."""
    mu = 0.05
    eff = T.TorqueDependentFrictionEffect(mu, 0.5, 0.02)
    free = T.generate(_STAIRS, (), sensors=QUIET)
    g = T.generate(_STAIRS, [eff], sensors=QUIET)
    k = _settled(g)
    np.testing.assert_allclose(g.true["torque"][k], free.true["torque"][k] / (1 - mu), rtol=1e-6)
    tau, a, v = g.true["torque"], g.true["acceleration"], g.true["omega"]
    want = mu * np.abs(tau - 0.5 * 0.1 * a) * np.tanh(v / 0.02)
    extra = g.true["effect_torque"]
    np.testing.assert_allclose(extra, want, atol=1e-6 * np.max(np.abs(want)))
    speeding = (a * v > 0.05) & (np.abs(v) > 0.2)
    braking = (a * v < -0.05) & (np.abs(v) > 0.2)
    assert np.mean(np.abs(extra[speeding])) > np.mean(np.abs(extra[braking]))


def test_actuator_lag_follows_the_torque_rate():
    """Behind a first-order lag of T = 20 ms the joint receives tau_j with T*d(tau_j)/dt = tau_cmd -
    tau_j (checked by the samples' central differences at 1 kHz, to 1 % of the command's peak
    change); the recording holds the command, which exceeds the joint's J*a + F (the effect's
    torque) by tau_cmd - tau_j, about T*d(tau_cmd)/dt; with T = 0.1 ms the recording is the
    lag-free one within 1 % of the peak torque."""
    s = T.Sensors(fs=1000.0, torque_noise=0.0, velocity_noise=0.0, quantisation=0.0)
    exc = T.PointToPoint(amplitudes=(3.0, -2.0), move_time=1.5, dwell=1.5)
    g = T.generate(exc, [T.ActuatorLagEffect(0.02)], sensors=s)
    u, tj = g.true["torque"], g.true["applied_torque"]
    dtj = np.gradient(tj, g.time)
    inner = slice(5, -5)
    np.testing.assert_allclose((0.02 * dtj + tj)[inner], u[inner], atol=0.01 * np.ptp(u))
    np.testing.assert_allclose(g.true["effect_torque"], u - tj, atol=1e-6 * np.max(np.abs(u)))
    assert np.corrcoef(u - tj, 0.02 * np.gradient(u, g.time))[0, 1] > 0.9
    free = T.generate(exc, (), sensors=s)
    quick = T.generate(exc, [T.ActuatorLagEffect(1e-4)], sensors=s)
    np.testing.assert_allclose(quick.true["torque"], free.true["torque"], atol=0.01 * np.max(np.abs(free.true["torque"])))


def test_outside_effects_are_exported_and_distinct_from_the_candidates():
    assert set(T.OUTSIDE_EFFECTS) == {"actuator_lag", "quadratic_drag", "torque_dependent_friction",
                                      "time_disturbance"}
    assert not set(T.OUTSIDE_EFFECTS) & set(T.EFFECTS)
    with pytest.raises(ValueError):
        T.generate(_STAIRS, [T.LoadDependentEffect(), T.TorqueDependentFrictionEffect()], sensors=QUIET)
