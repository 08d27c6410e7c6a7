"""LaneAdaptive (each lane its own error-controlled step) against an independent stiff reference:
scipy Radau at rtol 1e-10 written in plain numpy, solved piece by piece between the staircase's
steps, on stiff lanes (sigma0 1e4 N*m/deg, sigma1 up to 100 N*m*s/deg) and on the paper's joint,
with steps on and off the sample grid. Also the fixed step's handling of a step landing on a
discontinuity (a Tsit5 stage at the step's end is evaluated at the left limit)."""


import diffrax
import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import lugre_jax as lj
from lugre_jax.testing import velocity_staircase

J, KP, KI = 0.128, 8.0, 60.0
# (Fc, Fs, vs, sigma0, sigma1, sigma2): passive sets (sigma2 >= sigma1*(Fs - Fc)/Fc)
LANES = {
    "stiff_damped": (1.0, 1.05, 0.05, 1.0e4, 100.0, 6.0),
    "stiff": (0.9, 1.5, 0.03, 1.0e4, 10.0, 7.0),
    "paper_like": (0.915, 1.2, 0.0315, 150.0, 2.3, 0.9),
}
STAIRS = {"on_grid": ([0.02, 0.1, -0.05, 0.5], 1.0, 4.0), "off_grid": ([0.05, -0.03, 0.3, -1.0], 0.8765, 3.5)}
POS_TOL_DEG, TORQUE_TOL_NM = 2e-6, 1e-4


def radau(p, levels, dwell, duration, hz):
    """theta [deg] and the loop's torque [N*m] at the samples: scipy Radau, rtol 1e-10, restarted
    at each reference step."""
    Fc, Fs, vs, s0, s1, s2 = p
    ts, ys = velocity_staircase(J, Fc, Fs, vs, s0, s1, s2, KP, KI, levels, dwell, duration, hz,
                                rtol=1e-10, atol=1e-12, first_step=1e-7)
    k = np.minimum(np.floor(ts / dwell + 1e-12).astype(int), len(levels) - 1)
    torque = KP * (np.asarray(levels)[k] - ys[:, 1]) + KI * ys[:, 3]
    return ys[:, 0], torque


def system(p, levels, dwell):
    Fc, Fs, vs, s0, s1, s2 = p
    return lj.System(friction=lj.LuGre(Fc=Fc, Fs=Fs, vs=vs, sigma0=s0, sigma1=s1, sigma2=s2), joint=lj.Joint(J=J),
                     controller=lj.VelocityPID(kp=KP, ki=KI), reference=lj.VelocitySteps(levels, dwell_s=dwell))


@pytest.mark.parametrize("stairs", sorted(STAIRS))
def test_lane_adaptive_matches_radau_on_stiff_lanes(stairs):
    levels, dwell, duration = STAIRS[stairs]
    names = sorted(LANES)
    batch = lj.stack_systems([system(LANES[k], levels, dwell) for k in names])
    sol = lj.simulate(batch, duration, 100.0, batched=True, stepping=lj.LaneAdaptive())
    assert np.all(np.asarray(sol.result) == lj.RESULT_OK)
    for i, k in enumerate(names):
        theta, torque = radau(LANES[k], levels, dwell, duration, 100.0)
        assert np.max(np.abs(np.asarray(sol.theta[i]) - theta)) <= POS_TOL_DEG, k
        assert np.max(np.abs(np.asarray(sol.torque_nm[i]) - torque)) <= TORQUE_TOL_NM, k
    # unbatched: the same steps for one lane (vectorised and scalar arithmetic round differently)
    one = lj.simulate(system(LANES[names[0]], levels, dwell), duration, 100.0, stepping=lj.LaneAdaptive())
    np.testing.assert_allclose(np.asarray(one.theta), np.asarray(sol.theta[0]), rtol=0, atol=1e-8)


def test_lane_adaptive_reports_exhausted_steps():
    sol = lj.simulate(system(LANES["stiff"], *STAIRS["on_grid"][:2]), 2.0, 100.0,
                      stepping=lj.LaneAdaptive(max_steps=20))
    assert int(sol.result) == lj.RESULT_SOLVER_FAILED


def test_lane_adaptive_flags_a_lane_that_cannot_be_solved_and_keeps_the_others():
    """A lane whose right-hand side is NaN (Fs NaN) among good lanes: its result is not OK, the
    good lanes' trajectories are finite and those of the same lanes solved without it."""
    levels, dwell = STAIRS["off_grid"][:2]
    good = [system(LANES[k], levels, dwell) for k in ("paper_like", "stiff")]
    bad = system((0.9, float("nan"), 0.03, 150.0, 2.3, 0.9), levels, dwell)
    sol = lj.simulate(lj.stack_systems([good[0], bad, good[1]]), 1.5, 100.0, batched=True, stepping=lj.LaneAdaptive())
    ref = lj.simulate(lj.stack_systems(good), 1.5, 100.0, batched=True, stepping=lj.LaneAdaptive())
    assert [int(r) for r in sol.result] == [lj.RESULT_OK, lj.RESULT_SOLVER_FAILED, lj.RESULT_OK]
    theta = np.asarray(sol.theta)[[0, 2]]
    assert np.all(np.isfinite(theta))
    np.testing.assert_allclose(theta, np.asarray(ref.theta), rtol=0, atol=1e-12)


def test_lane_adaptive_mean_and_mean_of_solution_match_a_tight_solve():
    # the mean (accumulated in the loop) and the trajectory's mean are each held to a tight solve
    # at the stepping's accuracy (rtol 1e-6 per step)
    s = system(LANES["paper_like"], *STAIRS["off_grid"][:2])
    tight = lj.simulate(s, 2.0, 100.0, stepping=lj.Adaptive(rtol=1e-11, atol=1e-13))
    ref = float(np.mean(np.asarray(tight.theta) ** 2))
    sol = lj.simulate(s, 2.0, 100.0, stepping=lj.LaneAdaptive())
    m = lj.simulate(s, 2.0, 100.0, stepping=lj.LaneAdaptive(), saveat=lj.SaveAt(mean=lambda smp: smp.theta ** 2))
    np.testing.assert_allclose(float(np.mean(np.asarray(sol.theta) ** 2)), ref, rtol=1e-6)
    np.testing.assert_allclose(float(m.value), ref, rtol=1e-6)


def test_frozen_states_are_exactly_those_whose_rate_is_structurally_zero():
    """A state is left out of the integration only where the right-hand side's program makes its
    rate the constant zero; a rate that is zero for some parameter values only is integrated."""
    from lugre_jax._simulation._lanewise import frozen_states

    levels, dwell = STAIRS["on_grid"][:2]
    pi = system(LANES["paper_like"], levels, dwell)
    names = lj.STATE_NAMES

    def frozen(s):
        return {k for k, f in zip(names, frozen_states(lj.broadcast_system(s, 2))) if f}

    assert frozen(pi) == {"current", "xd", "zh", "xp"}
    assert frozen(eqx.tree_at(lambda s: s.controller, pi, lj.VelocityPID(kp=KP, ki=KI, kd=0.01))) == {"current", "zh", "xp"}
    # kd as an array is a parameter (zero here, but it could be varied or differentiated)
    assert frozen(eqx.tree_at(lambda s: s.controller, pi, lj.VelocityPID(kp=KP, ki=KI, kd=np.asarray(0.0)))) == {
        "current", "zh", "xp"}
    assert frozen(eqx.tree_at(lambda s: s.actuator, pi, lj.DCMotor())) == {"xd", "zh", "xp"}


def test_a_frozen_state_keeps_its_initial_value_and_the_others_match_a_tight_solve():
    levels, dwell = STAIRS["off_grid"][:2]
    y0 = np.zeros(len(lj.STATE_NAMES))
    y0[lj.STATE_NAMES.index("xd")] = 0.3  # frozen (PI); no output depends on it
    y0[lj.STATE_NAMES.index("xi")] = 1e-3  # integrated
    s = eqx.tree_at(lambda s: s.y0, system(LANES["paper_like"], levels, dwell), y0)
    sol = lj.simulate(s, 1.5, 100.0, stepping=lj.LaneAdaptive())
    tight = lj.simulate(s, 1.5, 100.0, stepping=lj.Adaptive(rtol=1e-11, atol=1e-13))
    xd, xi = (lj.STATE_NAMES.index(k) for k in ("xd", "xi"))
    assert np.all(np.asarray(sol.ys[:, xd]) == 0.3)
    np.testing.assert_allclose(np.asarray(sol.theta), np.asarray(tight.theta), rtol=0, atol=POS_TOL_DEG)
    np.testing.assert_allclose(np.asarray(sol.ys[:, xi]), np.asarray(tight.ys[:, xi]), rtol=0, atol=1e-6)


def test_the_accelerators_scatter_writes_what_the_cpus_per_lane_writes_do(monkeypatch):
    """The sample buffers' two writes (per lane on a CPU, one scatter per step on an accelerator)
    give the same samples; the scatter's is run here on the CPU."""
    from lugre_jax._simulation import _lanes, _lanewise

    levels, dwell = STAIRS["off_grid"][:2]
    batch = lj.stack_systems([system(LANES[k], levels, dwell) for k in ("paper_like", "stiff")])
    theta = lj.SaveAt(fn=lambda smp: {"theta": smp.theta, "y": jnp.stack(smp.y)})
    runs = []
    for per_lane in (True, False):
        monkeypatch.setattr(_lanewise, "writes_per_lane", lambda per_lane=per_lane: per_lane)
        monkeypatch.setattr(_lanes, "_CACHE", {})  # compiled anew with this write
        runs.append((lj.simulate(batch, 1.5, 100.0, batched=True, stepping=lj.LaneAdaptive()),
                     lj.simulate(batch, 1.5, 100.0, batched=True, stepping=lj.LaneAdaptive(), saveat=theta)))
    (sol_a, fn_a), (sol_b, fn_b) = runs
    # the two programs round differently and the step-size control carries that along: equal to
    # far within the stepping's accuracy (a sample written one row off would be ~1e-3 deg off)
    tol = dict(rtol=0, atol=1e-7)
    np.testing.assert_allclose(np.asarray(sol_a.ys), np.asarray(sol_b.ys), **tol)
    np.testing.assert_allclose(np.asarray(sol_a.torque_nm), np.asarray(sol_b.torque_nm), **tol)
    for k in ("theta", "y"):
        np.testing.assert_allclose(np.asarray(fn_a.value[k]), np.asarray(fn_b.value[k]), **tol)
    np.testing.assert_allclose(np.asarray(fn_a.value["y"]), np.asarray(sol_a.ys), **tol)


def test_lane_adaptive_rejects_other_solvers():
    with pytest.raises(TypeError, match="Tsit5"):
        lj.LaneAdaptive(diffrax.Bosh3())


def test_fixed_tsit5_lands_on_grid_steps():
    # A Tsit5 stage at the step's end enters the update: evaluated at the left limit, a velocity
    # step on the grid is not seen one step early (first-order error, 1e-2 deg at 10 ms).
    levels, dwell, duration = STAIRS["on_grid"]
    p = LANES["paper_like"]
    theta, _ = radau(p, levels, dwell, duration, 100.0)
    for dt in (0.01, 0.005):
        sol = lj.simulate(system(p, levels, dwell), duration, 100.0, stepping=lj.FixedStep(diffrax.Tsit5(), dt=dt))
        assert np.max(np.abs(np.asarray(sol.theta) - theta)) < 1e-4


def test_check_stepping_reports_per_lane():
    levels, dwell, duration = STAIRS["off_grid"]
    batch = lj.stack_systems([system(LANES[k], levels, dwell) for k in sorted(LANES)])
    chk = lj.check_stepping(batch, duration, 100.0, lj.LaneAdaptive(), batched=True, n_lanes=3)
    assert chk.stepping.startswith("LaneAdaptive(") and chk.failed_lanes == ()
    assert len(chk.theta_deg_per_lane) == 3 and chk.theta_deg == max(chk.theta_deg_per_lane) <= POS_TOL_DEG


def test_batched_default_is_lane_adaptive_outside_transformations_and_adaptive_under_grad():
    """A batch of concrete arrays gets LaneAdaptive (the same numbers as passing it); a batch traced
    under jax.grad gets Adaptive, which reverse mode works through (LaneAdaptive's loop would raise);
    one lane gets Adaptive."""
    import equinox as eqx
    import jax
    import jax.numpy as jnp

    levels, dwell = STAIRS["on_grid"][:2]
    batch = lj.stack_systems([system(LANES[k], levels, dwell) for k in ("paper_like", "stiff")])
    default = lj.simulate(batch, 1.5, 100.0, batched=True)
    lane = lj.simulate(batch, 1.5, 100.0, batched=True, stepping=lj.LaneAdaptive())
    np.testing.assert_array_equal(np.asarray(default.theta), np.asarray(lane.theta))
    assert isinstance(lj.default_stepping(True, batch), lj.LaneAdaptive)
    assert isinstance(lj.default_stepping(False, batch), lj.Adaptive)

    def loss(fs):
        b = eqx.tree_at(lambda s: s.friction.Fs, batch, fs)
        return jnp.sum(lj.simulate(b, 1.5, 100.0, batched=True).theta[:, -1])

    g = jax.grad(loss)(jnp.asarray(batch.friction.Fs))
    assert g.shape == (2,) and np.all(np.isfinite(np.asarray(g)))
    with pytest.raises(Exception):
        jax.grad(lambda fs: jnp.sum(lj.simulate(eqx.tree_at(lambda s: s.friction.Fs, batch, fs), 1.5, 100.0,
                                                batched=True, stepping=lj.LaneAdaptive()).theta[:, -1]))(
            jnp.asarray(batch.friction.Fs))
