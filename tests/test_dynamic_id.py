"""Dynamic LuGre parameters (paper section 4.2.5): eq. 17 pre-sliding step, eq. 18, time-series fit
through the simulator with Fisher standard errors, excitation design."""

import jax
import numpy as np
import pytest

import lugre_jax as lj
from lugre_jax.dynamic import (
    design_grid,
    fit_dynamic,
    inertia_eq18,
    lugre_from_static,
    presliding_step,
    sigma1_eq18,
    torque_sine_system,
    with_dynamics,
)
from lugre_jax.plant._paper import TABLE1, TABLE2

J = lj.PAPER_J


def test_sigma0_from_presliding_step_paper_plant():
    # Truth: segment 1 of Table 2 (the plant's pre-sliding stiffness). A 0.1 N*m step (1.5% of Fs) keeps
    # |v| below the 0.05 deg/s segment edge; the LuGre spring softens by ~F/(2 Fs) ~ 1%, so 2% tolerance.
    truth = TABLE2[1][0]
    r = presliding_step(lj.paper_friction(), J, 0.1)
    assert r.settled
    assert r.sigma0 == pytest.approx(truth, rel=0.02)
    # through a 1e-4 deg encoder (0.0009 deg displacement = 9 counts) the error stays within one count: ~6%
    rq = presliding_step(lj.paper_friction(), J, 0.1, encoder_res_deg=1e-4)
    assert rq.sigma0 == pytest.approx(truth, rel=0.06)


def test_sigma0_step_single_lugre_closed_form():
    # Monotone pre-sliding with constant g (Fc = Fs) and an over-damped bristle (sigma1 = 50): the bristle
    # follows z(x) = (g/s0)(1 - exp(-s0 x / g)) exactly, so at rest under force F the displacement is
    # x = -(g/s0) ln(1 - F/g) and eq. 17 gives F/x, not s0: the bias of the paper's formula, in closed form.
    g, s0 = 6.4808, 111.316
    seg = lj.LuGre(Fc=g, Fs=g, vs=0.0315, sigma2=2.9804, sigma0=s0, sigma1=50.0)
    for F in (0.3, 1.5):
        expected = F / (-(g / s0) * np.log(1 - F / g))
        r = presliding_step(seg, J, F, duration_s=6.0, sample_hz=100.0, settle_s=0.5)
        assert r.sigma0 == pytest.approx(expected, rel=2e-3)
    assert expected < 0.9 * s0  # a 1.5 N*m step underestimates sigma0 by >10%


def test_presliding_breakaway_raises():
    with pytest.raises(ValueError, match="broke the joint away"):
        presliding_step(lj.paper_friction(), J, 3.0)
    with pytest.raises(ValueError, match="positive"):
        presliding_step(lj.paper_friction(), J, -1.0)


def test_eq18_reproduces_table2_and_inconsistency():
    for k in (1, 3):
        s0, s1 = TABLE2[k]
        assert sigma1_eq18(J, s0, TABLE1[k][3]) == pytest.approx(s1, abs=2e-3)
    Js = [inertia_eq18(TABLE2[k][0], TABLE2[k][1], TABLE1[k][3]) for k in (1, 2, 3)]
    np.testing.assert_allclose(Js, [0.128, 0.1923, 0.128], atol=6e-4)


def test_lugre_from_static_keeps_steady_state():
    st = lj.Stribeck(Fc=1.0, Fs=6.5, vs=0.03, sigma2=2.7)
    m = lugre_from_static(st, 110.0, 2.5)
    v = np.array([-1.0, -0.01, 0.002, 0.05, 1.4])
    np.testing.assert_allclose(m.steady_state(v), st.steady_state(v), rtol=1e-12)
    seg = lugre_from_static(lj.Segmented((st, lj.CoulombViscous(Fc=4.5, sigma2=0.01)), np.array([1.2])), 110.0, [2.5, 4.0])
    assert float(seg.segments[1].Fs) == pytest.approx(4.5)
    assert float(seg.segments[1].sigma1) == pytest.approx(4.0)


def test_time_series_fit_recovers_sigma0_sigma1_within_3se():
    seg = lj.paper_segment(1)
    truth = np.array([float(seg.sigma0), float(seg.sigma1)])
    dur, hz, noise = 1.0, 100.0, 1e-4

    def build(p):  # 0.5 N*m at 3 Hz: near the pre-sliding resonance sqrt(sigma0/J) ~ 4.7 Hz
        return torque_sine_system(with_dynamics(seg, p[0], p[1]), J, 0.5, 3.0)

    th = np.asarray(lj.simulate(build(truth), dur, hz, stepping=lj.FixedStep()).theta)
    meas = th + noise * np.asarray(jax.random.normal(jax.random.key(7), th.shape))
    fit = fit_dynamic(build, meas, [60.0, 1.0], duration_s=dur, sample_hz=hz, noise_deg=noise, max_steps=40)
    assert fit.converged
    assert np.all(np.abs(fit.p - truth) < 3 * fit.se + 1e-9), (fit.p, fit.se)
    assert fit.rms_residual == pytest.approx(1.0, abs=0.2)  # residuals at the noise level
    assert np.all(fit.se / truth < 0.1)


def test_fisher_shows_sigma1_unidentifiable_under_slow_tiny_excitation():
    seg = lj.paper_segment(1)
    p = [float(seg.sigma0), float(seg.sigma1)]
    grid = np.array([[0.02, 0.2], [0.5, 3.0]])  # (amplitude N*m, frequency Hz): quasi-static vs near resonance
    d = design_grid(lambda q, e: torque_sine_system(with_dynamics(seg, q[0], q[1]), J, e[0], e[1]), p, grid,
                    duration_s=1.0, sample_hz=100.0, noise_deg=1e-4)
    assert d["best"] == 1
    rel = d["relative_se"]
    assert rel[0, 1] > 0.5  # quasi-static: sigma1 essentially undetermined
    assert rel[1, 1] < 0.1 * rel[0, 1]
