"""The simulator against independent references: scipy solve_ivp (Radau/LSODA, rtol 1e-10), closed
forms of LuGre (steady state, pre-sliding), finite differences for gradients."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lugre_jax as lj
import diffrax

from lugre_jax import vector_field


def _scipy_reference(system, duration, hz, method="LSODA"):
    f = jax.jit(lambda t, y: vector_field(t, y, system))
    jac = jax.jit(jax.jacfwd(lambda t, y: vector_field(t, y, system), argnums=1))
    ts = np.arange(int(round(duration * hz)) + 1) / hz
    r = solve_ivp(lambda t, y: np.asarray(f(t, y)), (0, duration), np.asarray(system.y0),
                  method=method, t_eval=ts, rtol=1e-10, atol=1e-12,
                  jac=(lambda t, y: np.asarray(jac(t, y))) if method != "LSODA" else None)
    assert r.status == 0, r.message
    return r.y.T


def _pi_system(v_ref, friction=None):
    return lj.System(friction=lj.paper_friction() if friction is None else friction,
                     joint=lj.Joint(J=0.128), controller=lj.VelocityPID(kp=8.0, ki=60.0),
                     reference=lj.VelocitySteps([v_ref]))


def test_creep_at_0005_matches_lsoda():
    # Paper's parameters, velocity PI at 0.005 deg/s: creep / stick-slip regime.
    system = _pi_system(0.005)
    ref = _scipy_reference(system, 20.0, 100.0)
    sol = lj.simulate(system, 20.0, 100.0)
    assert int(sol.result) == lj.RESULT_OK
    # Stated agreement: position within 1e-6 deg, velocity within 1e-5 deg/s (measured ~1e-8 / 1e-7).
    np.testing.assert_allclose(sol.theta, ref[:, 0], atol=1e-6, rtol=0)
    np.testing.assert_allclose(sol.omega, ref[:, 1], atol=1e-5, rtol=0)
    # It really creeps: the joint lags the ideal ramp by more than 0.01 deg at some time.
    assert np.max(np.asarray(sol.theta_ref - sol.theta)) > 0.01


def test_stick_slip_at_002_matches_lsoda():
    system = _pi_system(0.02)
    ref = _scipy_reference(system, 20.0, 100.0)
    sol = lj.simulate(system, 20.0, 100.0)
    np.testing.assert_allclose(sol.theta, ref[:, 0], atol=1e-6, rtol=0)
    np.testing.assert_allclose(sol.omega, ref[:, 1], atol=1e-5, rtol=0)
    # stick-slip: velocity overshoots the command by more than 3x during slips
    assert float(sol.omega.max()) > 3 * 0.02


def test_sine_tracking_matches_lsoda():
    system = lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=0.128),
                       controller=lj.PositionPID(kpp=20.0, kp=8.0, ki=60.0),
                       reference=lj.PositionSine(3.0, 0.4))
    ref = _scipy_reference(system, 5.0, 200.0)
    sol = lj.simulate(system, 5.0, 200.0, stepping=lj.FixedStep(dt=1e-3))
    # Stated agreement: 1e-5 deg (the start, where v_ref jumps to A*w, dominates: ~2e-6 measured).
    np.testing.assert_allclose(sol.theta, ref[:, 0], atol=1e-5, rtol=0)
    np.testing.assert_allclose(sol.omega, ref[:, 1], atol=5e-4, rtol=0)  # 7e-5 of the 7.5 deg/s amplitude
    assert float(jnp.abs(sol.theta - sol.theta_ref).max()) < 0.5  # it tracks


def test_motor_inductance_adaptive_matches_radau():
    # L/R = 2.5e-4 s: stiff; the adaptive implicit path against Radau with the exact Jacobian.
    system = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),
                       controller=lj.VelocityPID(kp=8.0, ki=60.0),
                       reference=lj.VelocitySteps([0.05]), actuator=lj.DCMotor())
    ref = _scipy_reference(system, 2.0, 100.0, method="Radau")
    sol = lj.simulate(system, 2.0, 100.0, stepping=lj.Adaptive(diffrax.Kvaerno5(), rtol=1e-9, atol=1e-11))
    assert int(sol.result) == lj.RESULT_OK
    np.testing.assert_allclose(sol.theta, ref[:, 0], atol=1e-7, rtol=0)
    # the explicit default stays correct on the stiff motor (it only needs smaller steps)
    default = lj.simulate(system, 2.0, 100.0)
    assert int(default.result) == lj.RESULT_OK
    np.testing.assert_allclose(default.theta, ref[:, 0], atol=1e-6, rtol=0)
    np.testing.assert_allclose(sol.omega, ref[:, 1], atol=1e-6, rtol=0)
    np.testing.assert_allclose(sol.ys[:, 3], ref[:, 3], atol=1e-6, rtol=0)  # current [A]
    # and the eq. (8) simplification (L neglected) stays close: the motor is fast
    simple = eqx.tree_at(lambda s: s.actuator, system, lj.DCMotor(neglect_inductance=True))
    sol8 = lj.simulate(simple, 2.0, 100.0, stepping=lj.Adaptive(diffrax.Kvaerno5(), rtol=1e-9, atol=1e-11))
    assert float(jnp.abs(sol8.theta - sol.theta).max()) < 1e-4


@pytest.mark.parametrize("v", [-1.0, -0.02, 0.003, 0.04, 0.5, 1.4])
def test_lugre_steady_state_is_stribeck(v):
    # Closed form: at constant v the bristle settles at z = sign(v) g(v)/sigma0 and F = Stribeck(v).
    m = lj.paper_segment(1)
    z = np.sign(v) * float(m.g(v)) / float(m.sigma0)
    assert float(m.derivative(z, v)) == pytest.approx(0.0, abs=1e-14)  # it is a fixed point
    F = float(m.torque(z, v))
    assert F == pytest.approx(float(m.steady_state(v)), rel=1e-12, abs=1e-12)
    assert F == pytest.approx(np.sign(v) * float(m.g(v)) + float(m.sigma2) * v, rel=1e-12)


def test_steady_state_by_simulation_equals_stribeck():
    # A constant-velocity sweep done by the simulator (velocity PI, long dwell) ends on the curve.
    f = lj.paper_segment(2)
    levels = np.array([0.2, 0.6, 1.0])
    systems = lj.stack_systems([_pi_system(v, friction=f) for v in levels])
    sol = lj.simulate(systems, 30.0, 10.0, batched=True)
    F_end = np.asarray(sol.friction_nm[:, -1])
    np.testing.assert_allclose(F_end, np.asarray(f.steady_state(levels)), rtol=1e-6)


def test_presliding_displacement_is_dF_over_sigma0():
    # Eq. (17): a tiny torque step dF below breakaway gives a displacement close to dF/sigma0.
    m = lj.paper_segment(1)
    dF = 0.05  # N*m, far below Fs = 6.48
    system = lj.System(friction=m, joint=lj.Joint(J=0.128), controller=lj.OpenLoop(bias=dF),
                       reference=lj.VelocitySteps([0.0]))
    sol = lj.simulate(system, 5.0, 100.0, stepping=lj.Adaptive())
    theta_end = float(sol.theta[-1])
    s0, g0 = float(m.sigma0), float(m.Fs)
    # exact for the LuGre bristle at rest: theta = -(g/sigma0) ln(1 - dF/g)
    assert theta_end == pytest.approx(-(g0 / s0) * np.log(1 - dF / g0), rel=2e-3)
    assert theta_end == pytest.approx(dF / s0, rel=1e-2)
    assert abs(float(sol.omega[-1])) < 1e-6


def test_gradients_match_central_differences():
    base = _pi_system(0.02, friction=lj.paper_segment(1))

    def final_theta(p):
        f = lj.LuGre(Fc=p[0], Fs=p[1], vs=p[2], sigma2=p[3], sigma0=p[4], sigma1=p[5])
        return lj.simulate(eqx.tree_at(lambda s: s.friction, base, f), 5.0, 20.0,
                           stepping=lj.FixedStep()).theta[-1]

    p0 = jnp.asarray(lj.friction.to_vector(lj.paper_segment(1)))
    jac = jax.jacfwd(final_theta)(p0)
    jrev = jax.grad(final_theta)(p0)
    fd = []
    for i in range(6):
        h = 1e-6 * max(1.0, abs(float(p0[i])))
        e = jnp.zeros(6).at[i].set(h)
        fd.append((final_theta(p0 + e) - final_theta(p0 - e)) / (2 * h))
    fd = np.asarray(fd)
    np.testing.assert_allclose(jac, fd, rtol=1e-4, atol=1e-9)
    np.testing.assert_allclose(jrev, jac, rtol=1e-10, atol=1e-14)


def test_adaptive_default_differentiates_in_both_modes():
    # The default (adaptive) solve: reverse mode through diffrax's checkpointed adjoint, forward
    # mode with ForwardMode(); both against central differences (stated rtol 1e-4: the adaptive
    # step sequence depends on the parameters, so differences see its rtol-sized noise).
    base = _pi_system(0.02, friction=lj.paper_segment(1))
    p0 = jnp.asarray(float(base.friction.sigma1))

    def final_theta(s1, stepping=None):
        s = eqx.tree_at(lambda s: s.friction.sigma1, base, s1)
        return lj.simulate(s, 2.0, 20.0, stepping=stepping).theta[-1]

    rev = jax.grad(final_theta)(p0)
    fwd = jax.jacfwd(lambda s1: final_theta(s1, lj.Adaptive(adjoint=diffrax.ForwardMode())))(p0)
    h = 1e-4 * float(p0)
    fd = (final_theta(p0 + h) - final_theta(p0 - h)) / (2 * h)
    np.testing.assert_allclose([rev, fwd], [fd, fd], rtol=1e-4)


def test_batched_equals_single_and_failed_lane_is_flagged():
    base = _pi_system(0.02)
    Js = jnp.array([0.128, 0.2, 1e-6])  # the last is far too light for a 2.5 ms step: blows up
    batch = eqx.tree_at(lambda s: s.joint.J, lj.broadcast_system(base, 3), Js)
    sol = lj.simulate(batch, 5.0, 100.0, batched=True, stepping=lj.FixedStep(), lanes=lj.Lanes(chunk_size=2))
    assert sol.theta.shape == (3, 501)
    np.testing.assert_array_equal(np.asarray(sol.result), [0, 0, lj.RESULT_NONFINITE])
    one = lj.simulate(eqx.tree_at(lambda s: s.joint.J, base, jnp.asarray(0.2)), 5.0, 100.0, stepping=lj.FixedStep())
    np.testing.assert_allclose(sol.theta[1], one.theta, rtol=1e-12, atol=1e-14)
    loss = lj.trajectory_loss(sol, lambda s: jnp.nanmean((s.theta - s.theta_ref) ** 2, axis=-1))
    assert np.isfinite(loss[:2]).all() and loss[2] == np.inf


def test_default_chunking_pads_and_matches_one_chunk():
    # 451 lanes: by default three 151-lane chunks (two padding lanes); results must not depend on the split
    base = _pi_system(0.02)
    Js = jnp.linspace(0.1, 0.3, 451)
    batch = eqx.tree_at(lambda s: s.joint.J, lj.broadcast_system(base, 451), Js)
    auto = lj.simulate(batch, 1.0, 100.0, batched=True, lanes=lj.Lanes(shard=False), stepping=lj.FixedStep(diffrax.Heun(), dt=1e-2))
    whole = lj.simulate(batch, 1.0, 100.0, batched=True, stepping=lj.FixedStep(diffrax.Heun(), dt=1e-2), lanes=lj.Lanes(chunk_size=451, shard=False))
    assert auto.theta.shape == (451, 101)
    np.testing.assert_array_equal(np.asarray(auto.theta), np.asarray(whole.theta))
    assert float(jnp.max(jnp.abs(auto.theta[0] - auto.theta[-1]))) > 0  # lanes really differ


def test_adaptive_max_steps_failure_is_a_result_code():
    sol = lj.simulate(_pi_system(0.02), 5.0, 10.0, stepping=lj.Adaptive(max_steps=10))
    assert int(sol.result) == lj.RESULT_SOLVER_FAILED


def test_nonpositive_inertia_is_refused_concrete_or_traced():
    # A concrete J is checked in Python (so the compiled program holds no host callback and can be
    # cached); a traced one by eqx.error_if inside the program.
    bad = eqx.tree_at(lambda s: s.joint.J, _pi_system(0.02), jnp.asarray(-0.1))
    with pytest.raises(ValueError, match="Joint.J must be > 0"):
        lj.simulate(bad, 1.0, 10.0)
    with pytest.raises(Exception, match="Joint.J must be > 0"):
        jax.jit(lambda s: lj.simulate(s, 1.0, 10.0, stepping=lj.FixedStep()).theta)(bad).block_until_ready()


def test_bad_static_input_raises_valueerror():
    with pytest.raises(ValueError, match="whole number of samples"):
        lj.simulate(_pi_system(0.02), 1.005, 100.0)
    with pytest.raises(TypeError, match="stepping must be"):
        lj.simulate(_pi_system(0.02), 1.0, 100.0, stepping="rk45")
    with pytest.raises(ValueError, match="explicit Runge-Kutta"):
        lj.FixedStep(diffrax.Kvaerno5())
    with pytest.raises(ValueError, match="batch axis"):
        lj.simulate(_pi_system(0.02), 1.0, 100.0, batched=True)


def test_unread_trajectories_are_not_stored():
    # Structural, not a timing: each state is its own scan output, so a loss that reads only theta
    # compiles to a program that stores no other state's trajectory, and under jacfwd no tangent
    # copy of them (a stacked (n, 8) row was written whole every step: 6x more under jacfwd).
    base = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),
                     controller=lj.VelocityPID(kp=8.0, ki=60.0), reference=lj.VelocitySteps([0.02]))
    n = 201

    def loss(s0):
        s = eqx.tree_at(lambda s: s.friction.sigma0, base, s0)
        return jnp.mean(lj.simulate(s, 2.0, 100.0, stepping=lj.FixedStep(diffrax.Heun(), dt=1e-2)).theta ** 2)

    s0 = jnp.asarray(base.friction.sigma0)
    for fn in (loss, jax.jacfwd(loss)):
        hlo = jax.jit(fn).lower(s0).compile().as_text()
        assert f"f64[{n}]" in hlo  # the theta trajectory is there ...
        assert f"f64[{n},8]" not in hlo  # ... the stacked rows (or their tangents) are not
    # sanity of the premise: asking for every state does store the (n, 8) trajectory
    hlo = jax.jit(lambda s0: lj.simulate(eqx.tree_at(lambda s: s.friction.sigma0, base, s0), 2.0, 100.0,
                                         stepping=lj.FixedStep(diffrax.Heun(), dt=1e-2)).ys).lower(s0).compile().as_text()
    assert f"f64[{n},8]" in hlo


def test_stage_inputs_stored_once_changes_only_rounding(monkeypatch):
    # Stage inputs are divided by a runtime 1.0 so that XLA stores them instead of recomputing them
    # in every later stage (a speed measure, see _stored_once). The division is exact, so the same
    # stick-slip run, batched, with and without it, agrees to rounding (stated: rtol 1e-10; measured
    # 6e-14, XLA contracts fused and stored expressions into multiply-adds differently), and a
    # blown-up lane is still flagged.
    from lugre_jax._simulation import _fixed, _simulate

    base = _pi_system(0.02)
    batch = eqx.tree_at(lambda s: s.joint.J, lj.broadcast_system(base, 3), jnp.array([0.128, 0.2, 1e-6]))
    dyn, static = eqx.partition(batch, eqx.is_array)

    def run():  # a fresh trace each call, so the monkeypatched helper is the one compiled
        one = lambda d: _simulate._solve_one(eqx.combine(d, static), 1001, 100.0,  # noqa: E731
                                             lj.FixedStep(diffrax.Bosh3(), dt=0.02), lj.SaveAt())
        return jax.jit(jax.vmap(one))(dyn)

    stored = run()
    monkeypatch.setattr(_fixed, "_stored_once", lambda y, one: y)
    fused = run()
    np.testing.assert_allclose(np.asarray(stored.ys[:2]), np.asarray(fused.ys[:2]), rtol=1e-10, atol=1e-15)
    np.testing.assert_array_equal(np.asarray(stored.result), [0, 0, lj.RESULT_NONFINITE])
    np.testing.assert_array_equal(np.asarray(fused.result), np.asarray(stored.result))
    assert float(jnp.max(jnp.abs(stored.omega[0]))) > 0.02  # premise: it moves (sticks and slips)


def test_pi_controller_integrates_no_derivative_filter():
    # kd = 0.0 as a Python number (the default) is a plain PI: the derivative-filter state is not
    # integrated. It must give the same joint motion as a traced kd = 0, which integrates the filter.
    static_kd = _pi_system(0.02)
    traced_kd = eqx.tree_at(lambda s: s.controller.kd, static_kd, jnp.asarray(0.0))
    a = lj.simulate(static_kd, 5.0, 100.0, stepping=lj.FixedStep(diffrax.Heun(), dt=0.01))
    b = lj.simulate(traced_kd, 5.0, 100.0, stepping=lj.FixedStep(diffrax.Heun(), dt=0.01))
    np.testing.assert_array_equal(np.asarray(a.ys[:, :3]), np.asarray(b.ys[:, :3]))
    assert float(jnp.max(jnp.abs(a.ys[:, 5]))) == 0.0  # xd stays at its initial value ...
    assert float(jnp.max(jnp.abs(b.ys[:, 5]))) > 0.0  # ... where a traced kd integrates it
    # and a non-zero derivative gain still acts
    pid = lj.simulate(eqx.tree_at(lambda s: s.controller.kd, static_kd, 0.05), 5.0, 100.0, stepping=lj.FixedStep(diffrax.Heun(), dt=0.01))
    assert float(jnp.max(jnp.abs(pid.theta - a.theta))) > 1e-6


def test_long_steps_interpolate_between_samples():
    # dt = 2 sample periods: one Bosh3 step per two samples, the middle sample cubic-Hermite
    # interpolated from the step's end values and slopes.
    system = _pi_system(0.02)
    ref = _scipy_reference(system, 20.0, 100.0)
    long = lj.simulate(system, 20.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02))
    at_steps = lj.simulate(system, 20.0, 50.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02))
    assert int(long.result) == lj.RESULT_OK
    # the steps themselves are unchanged by interpolating between them
    np.testing.assert_allclose(long.ys[::2], at_steps.ys, rtol=0, atol=1e-12)
    # interpolated samples are as accurate as the step points (third-order interpolant); stated
    # bounds vs the tight reference: 3e-3 deg, 2e-2 deg/s (measured 1.4e-3 / 9.3e-3, scipy LSODA at
    # its default rtol 1e-3 gives 1.9e-3 / 1.2e-2 on the benchmark's version of this run)
    err = np.abs(np.asarray(long.ys[:, :2]) - ref[:, :2])
    mid, ends = err[1::2].max(axis=0), err[::2].max(axis=0)
    assert np.all(mid <= 1.5 * ends), (mid, ends)
    assert ends[0] < 3e-3 and ends[1] < 2e-2, ends
    # a step that is neither a divisor nor a multiple of the sample period is refused
    with pytest.raises(ValueError, match="whole multiple"):
        lj.simulate(system, 1.0, 100.0, stepping=lj.FixedStep(dt=0.015))


def _printed_on_two_devices(code: str) -> list[str]:
    """What ``code`` prints, run in a fresh process with two XLA host devices (words)."""
    import os
    import subprocess
    import sys

    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stdout + out.stderr
    return out.stdout.split()


def test_auto_sharding_only_for_enough_work():
    # shard=None splits lanes over host devices only when the call has enough right-hand-side
    # evaluations to pay the split's fixed cost (measured ~2.5 ms); shard=True always splits.
    code = ("import lugre_jax as lj\n"
            "from lugre_jax._simulation import _lanes as L, _simulate as S, _fixed as F\n"
            "import diffrax\nlj.configure()\n"
            "s = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),\n"
            "              controller=lj.VelocityPID(kp=8.0, ki=60.0), reference=lj.VelocitySteps([0.02]))\n"
            "for b, shard in ((4, None), (4, True)):\n"
            "    L._CACHE.clear()\n"
            "    lj.simulate(lj.broadcast_system(s, b), 1.0, 100.0, batched=True,\n"
            "                stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02), lanes=lj.Lanes(shard=shard))\n"
            "    print(next(iter(L._CACHE))[0])\n"
            "st = lj.FixedStep(diffrax.Bosh3(), dt=0.02)\n"
            "print(2000 * F.rhs_evals(st, 2001, 100.0) >= S._SHARD_MIN_EVALS,\n"
            "      1000 * F.rhs_evals(st, 2001, 100.0) >= S._SHARD_MIN_EVALS)\n"
            "import jax.numpy as jnp\n"
            "for b in (127, 128):  # map_lanes splits from two default chunks (128 lanes) on\n"
            "    L._CACHE.clear()\n"
            "    lj.map_lanes(lambda x: 2 * x, jnp.arange(float(b)))\n"
            "    print(next(iter(L._CACHE))[0])\n")
    assert _printed_on_two_devices(code) == ["1", "2", "True", "False", "1", "2"]


def test_implicit_solver_batches_stay_on_one_device():
    # On two host devices a batched Kvaerno5 solve with enough work to be split by default runs on
    # one device and succeeds (its linear solves fail inside shard_map); Lanes(shard=True) with an
    # implicit solver is refused with one line.
    code = ("import lugre_jax as lj, diffrax, numpy as np\n"
            "from lugre_jax._simulation import _lanes as L\n"
            "lj.configure()\n"
            "s = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),\n"
            "              controller=lj.VelocityPID(kp=8.0, ki=60.0), reference=lj.VelocitySteps([0.02, 0.1], dwell_s=1.0))\n"
            "b = lj.broadcast_system(s, 150)\n"
            "st = lj.Adaptive(diffrax.Kvaerno5(), rtol=1e-6, atol=1e-9)\n"
            "L._CACHE.clear()\n"
            "out = lj.simulate(b, 10.0, 100.0, batched=True, stepping=st)\n"
            "print(next(iter(L._CACHE))[0], bool(np.all(np.asarray(out.result) == 0)))\n"
            "try:\n"
            "    lj.simulate(b, 10.0, 100.0, batched=True, stepping=st, lanes=lj.Lanes(shard=True))\n"
            "except ValueError as e:\n"
            "    print('refused' if 'implicit solver' in str(e) else e)\n"
            "from lugre_jax._simulation import _simulate as S\n"
            "print(150 * S._work(st, 1001, 100.0) >= S._SHARD_MIN_EVALS)\n")
    assert _printed_on_two_devices(code) == ["1", "True", "refused", "True"]


def _tracking(q):
    return (q.theta - q.theta_ref) ** 2


@pytest.mark.parametrize("kw", [dict(stepping=lj.FixedStep(diffrax.Heun(), dt=0.01)),
                                dict(stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02)),
                                dict(stepping=lj.Adaptive())], ids=["one-sample-steps", "interpolated", "adaptive"])
def test_sample_mean_equals_mean_over_stored_trajectory(kw):
    # sample_mean reduces each sample inside the time loop; it must equal the same mean taken over
    # the stored trajectory (stated: rtol 1e-12, only summation order differs), for every output a
    # Sample offers, including measured data looked up by the sample index.
    system = _pi_system(0.02, friction=lj.paper_segment(1))
    sol = lj.simulate(system, 5.0, 100.0, **kw)
    data = 0.5 * sol.theta + 0.01  # stand-in for a measured recording, one value per sample

    def fn(q):
        return dict(track=(q.theta - q.theta_ref) ** 2, data=(q.theta - data[q.index]) ** 2,
                    torque=q.torque_nm, friction=q.friction_nm, v_ref=q.v_ref, t=q.t, z=q.z, omega=q.omega)

    out = lj.simulate(system, 5.0, 100.0, saveat=lj.SaveAt(mean=fn), **kw)
    assert isinstance(out, lj.SampleMean) and int(out.result) == lj.RESULT_OK
    expect = dict(track=jnp.mean((sol.theta - sol.theta_ref) ** 2), data=jnp.mean((sol.theta - data) ** 2),
                  torque=jnp.mean(sol.torque_nm), friction=jnp.mean(sol.friction_nm), v_ref=jnp.mean(sol.v_ref),
                  t=jnp.mean(sol.ts), z=jnp.mean(sol.z), omega=jnp.mean(sol.omega))
    for k, v in expect.items():
        np.testing.assert_allclose(out.value[k], v, rtol=1e-12, atol=1e-15, err_msg=k)
    assert float(expect["track"]) > 0 and float(expect["friction"]) > 0  # premise: non-trivial means


def test_sample_mean_gradient_matches_trajectory_gradient_and_differences():
    base = _pi_system(0.02, friction=lj.paper_segment(1))

    def system(p):
        return eqx.tree_at(lambda s: s.friction, base, lj.friction.from_vector(lj.LuGre, p))

    def in_loop(p):
        return lj.simulate(system(p), 5.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02), saveat=lj.SaveAt(mean=_tracking)).value

    def stored(p):
        sol = lj.simulate(system(p), 5.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02))
        return jnp.mean((sol.theta - sol.theta_ref) ** 2)

    p0 = jnp.asarray(lj.friction.to_vector(lj.paper_segment(1)))
    g = jax.grad(in_loop)(p0)
    np.testing.assert_allclose(g, jax.grad(stored)(p0), rtol=1e-9, atol=1e-18)
    np.testing.assert_allclose(jax.jacfwd(in_loop)(p0), g, rtol=1e-9, atol=1e-18)
    fd = []
    for i in range(6):
        h = 1e-6 * max(1.0, abs(float(p0[i])))
        e = jnp.zeros(6).at[i].set(h)
        fd.append((in_loop(p0 + e) - in_loop(p0 - e)) / (2 * h))
    np.testing.assert_allclose(g, np.asarray(fd), rtol=1e-4, atol=1e-12)


def test_sample_mean_flags_failed_lanes_and_rejects_bad_input():
    base = _pi_system(0.02)
    batch = eqx.tree_at(lambda s: s.joint.J, lj.broadcast_system(base, 3), jnp.array([0.128, 0.2, 1e-6]))
    out = lj.simulate(batch, 5.0, 100.0, batched=True, stepping=lj.FixedStep(), saveat=lj.SaveAt(mean=_tracking))
    np.testing.assert_array_equal(np.asarray(out.result), [0, 0, lj.RESULT_NONFINITE])
    loss = np.asarray(out.or_inf())
    assert np.isfinite(loss[:2]).all() and loss[2] == np.inf
    sol = lj.simulate(batch, 5.0, 100.0, batched=True, stepping=lj.FixedStep())
    np.testing.assert_allclose(loss[:2], np.mean((sol.theta - sol.theta_ref)[:2] ** 2, axis=-1), rtol=1e-12)
    with pytest.raises(ValueError, match="give one of"):
        lj.SaveAt(mean=_tracking, reduce=lambda s: s.theta)
    with pytest.raises(TypeError, match="SaveAt.mean must be a function"):
        lj.SaveAt(mean=3.0)


def test_derivative_barriers_shrink_the_backward_pass_and_change_nothing(monkeypatch):
    # Structural, not a timing: dividing the tangents of the joint's net torque, dz/dt, g(v) and
    # interpolated samples by a runtime 1.0 makes XLA compute each cotangent once instead of in
    # every kernel that reads it. The compiled gradient holds fewer multiply/add/subtract ops (stated:
    # < 0.85x; measured 364 against 495) and more divisions (the barriers), and the same gradient.
    from lugre_jax._simulation import _fixed, _system
    from lugre_jax.friction import _models
    import re

    base = _pi_system(0.02, friction=lj.paper_segment(1))

    def loss(s0):
        s = eqx.tree_at(lambda s: s.friction.sigma0, base, s0)
        return lj.simulate(s, 2.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02), saveat=lj.SaveAt(mean=_tracking)).value

    def compiled_counts():
        hlo = jax.jit(jax.grad(loss)).lower(s0).compile().as_text()
        count = {op: len(re.findall(rf"= f64\[\d*\]\S* {op}\(", hlo))
                 for op in ("multiply", "add", "subtract", "divide")}
        return count["multiply"] + count["add"] + count["subtract"], count["divide"], jax.grad(loss)(s0)

    s0 = jnp.asarray(base.friction.sigma0)
    cheap, div, g = compiled_counts()
    monkeypatch.setattr(_system, "derivative_stored_once", lambda x, one: x)
    monkeypatch.setattr(_fixed, "derivative_stored_once", lambda x, one: x)
    monkeypatch.setattr(_models, "derivative_stored_once", lambda x, one: x)
    jax.clear_caches()  # simulate's inner jit would otherwise reuse its traced program
    cheap0, div0, g0 = compiled_counts()
    jax.clear_caches()
    assert div > div0  # premise: the barriers are in the program
    assert cheap < 0.85 * cheap0, (cheap, cheap0)
    np.testing.assert_allclose(g, g0, rtol=1e-12)


def test_map_lanes_equals_vmap_and_grad_through_chunks_is_exact():
    # map_lanes pads and chunks (7 lanes in chunks of 3: one padding lane) but computes vmap(fn);
    # jax.grad through a batched simulate of several chunks (each chunk recomputed before its
    # backward sweep) gives the same per-lane gradients.
    base = _pi_system(0.02, friction=lj.paper_segment(1))
    p0 = np.asarray(lj.friction.to_vector(lj.paper_segment(1)))
    P = jnp.asarray(p0 * np.random.default_rng(0).uniform(0.9, 1.1, (7, 6)))

    def loss(p):
        s = eqx.tree_at(lambda s: s.friction, base, lj.friction.from_vector(lj.LuGre, p))
        return lj.simulate(s, 2.0, 100.0, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02), saveat=lj.SaveAt(mean=_tracking)).value

    v, g = lj.map_lanes(jax.value_and_grad(loss), P, chunk_size=3, shard=False)
    v0, g0 = jax.vmap(jax.value_and_grad(loss))(P)
    np.testing.assert_allclose(v, v0, rtol=1e-12)
    np.testing.assert_allclose(g, g0, rtol=1e-10, atol=1e-20)
    assert float(jnp.max(jnp.abs(g[0] - g[-1]))) > 0  # premise: lanes differ

    def total(P):
        s = eqx.tree_at(lambda s: s.friction, lj.broadcast_system(base, 7),
                        lj.friction.from_vector(lj.LuGre, P))
        return jnp.sum(lj.simulate(s, 2.0, 100.0, batched=True, lanes=lj.Lanes(chunk_size=3, shard=False), stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02), saveat=lj.SaveAt(mean=_tracking)).value)

    np.testing.assert_allclose(jax.grad(total)(P), g0, rtol=1e-10, atol=1e-20)
    with pytest.raises(ValueError, match="same leading"):
        lj.map_lanes(loss, dict(a=jnp.zeros(3), b=jnp.zeros(4)))


def test_map_lanes_default_chunks_are_whole_vectors():
    # By default map_lanes balances ~64-lane chunks and rounds them up to a multiple of the 8 float64
    # lanes of a 512-bit vector (1,000 lanes: 16 chunks of 64, not of 63; measured 14 vs 23 ms for
    # gradients); below 8 lanes a chunk is the batch. The compiled function's key holds the chunk.
    from lugre_jax._simulation import _lanes

    for b, chunk in ((1000, 64), (130, 48), (5, 5)):  # 130: 3 chunks of 44, rounded up to 48
        _lanes._CACHE.clear()
        out = lj.map_lanes(lambda x: 2.0 * x, jnp.arange(float(b)), shard=False)
        np.testing.assert_array_equal(np.asarray(out), 2.0 * np.arange(b))
        assert [k[1] for k in _lanes._CACHE] == [chunk], (b, list(_lanes._CACHE))
