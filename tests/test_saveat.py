"""SaveAt's three outputs against the whole Solution: ``fn`` per sample (diffrax's meaning, stacked
over the samples), ``reduce`` of the whole solution, ``mean`` elsewhere (test_simulate); and the
checks made when a SaveAt is built."""

import diffrax
import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import lugre_jax as lj

DURATION, HZ = 2.0, 100.0
N = int(DURATION * HZ) + 1


def _system():
    # a reversal: the friction changes sign and the bristles deflect, so every output moves
    return lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),
                     controller=lj.VelocityPID(kp=8.0, ki=60.0),
                     reference=lj.VelocitySteps([0.5, -0.5], dwell_s=1.0))


def _batch(js=(0.128, 0.2, 0.3)):
    return eqx.tree_at(lambda s: s.joint.J, lj.broadcast_system(_system(), len(js)), jnp.asarray(js))


def _everything(q):
    return dict(index=q.index, t=q.t, y=jnp.stack(q.y), theta=q.theta, omega=q.omega, z=q.z,
                torque_nm=q.torque_nm, friction_nm=q.friction_nm, theta_ref=q.theta_ref, v_ref=q.v_ref)


def _assert_fn_matches(out, sol, batched):
    assert isinstance(out, lj.SampleValues)
    lead = (3,) if batched else ()
    v = out.value
    assert v["theta"].shape == lead + (N,) and v["y"].shape == lead + (N, len(lj.STATE_NAMES))
    np.testing.assert_array_equal(np.asarray(out.result), np.asarray(sol.result))
    np.testing.assert_array_equal(np.asarray(v["index"]), np.broadcast_to(np.arange(N), lead + (N,)))
    np.testing.assert_allclose(np.asarray(v["t"]), np.broadcast_to(np.asarray(sol.ts), lead + (N,)),
                               rtol=0, atol=1e-14)
    tol = dict(rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(np.asarray(v["y"]), np.asarray(sol.ys), **tol)
    for name in ("theta", "omega", "z", "torque_nm", "friction_nm", "theta_ref", "v_ref"):
        np.testing.assert_allclose(np.asarray(v[name]), np.asarray(getattr(sol, name)), **tol, err_msg=name)


@pytest.mark.parametrize("batched", [False, True], ids=["single", "batched"])
@pytest.mark.parametrize("stepping", [lj.FixedStep(diffrax.Bosh3(), dt=0.02), None],
                         ids=["fixed-interpolated", "adaptive-default"])
def test_fn_per_sample_equals_the_solution_at_every_sample(stepping, batched):
    system = _batch() if batched else _system()
    sol = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=batched)
    out = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=batched, saveat=lj.SaveAt(fn=_everything))
    assert np.all(np.asarray(sol.result) == lj.RESULT_OK)
    _assert_fn_matches(out, sol, batched)


@pytest.mark.parametrize("stepping", [lj.FixedStep(diffrax.Heun(), dt=0.01), lj.ExponentialBristle(dt=0.02),
                                      lj.LaneAdaptive()], ids=["fixed-one-sample", "exponential", "lanewise"])
def test_fn_per_sample_other_steppings(stepping):
    system = _batch()
    sol = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=True)
    out = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=True, saveat=lj.SaveAt(fn=_everything))
    _assert_fn_matches(out, sol, True)


def test_fn_carries_each_lanes_result():
    # an inertia of 1e-6 blows the fixed step up: that lane's code comes with its values
    system = _batch((0.128, 0.2, 1e-6))
    stepping = lj.FixedStep(diffrax.Bosh3(), dt=0.02)
    out = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=True,
                      saveat=lj.SaveAt(fn=lambda q: (q.theta - q.theta_ref) ** 2))
    np.testing.assert_array_equal(np.asarray(out.result), [0, 0, lj.RESULT_NONFINITE])
    np.testing.assert_array_equal(np.asarray(out.ok), [True, True, False])
    err = np.asarray(out.or_inf())
    assert err.shape == (3, N) and np.isfinite(err[:2]).all() and np.all(err[2] == np.inf)
    js = out.to_json()
    assert np.shape(js["value"]) == (3, N) and js["result"] == [0, 0, lj.RESULT_NONFINITE]


def _loss(sol):
    return lj.trajectory_loss(sol, lambda s: jnp.mean((s.theta - s.theta_ref) ** 2, axis=-1))


@pytest.mark.parametrize("stepping", [lj.FixedStep(diffrax.Bosh3(), dt=0.02), lj.LaneAdaptive()],
                         ids=["fixed", "lanewise"])
def test_reduce_is_a_function_of_the_whole_solution(stepping):
    system = _batch((0.128, 0.2, 1e-6))
    sol = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=True)
    loss, result = lj.simulate(system, DURATION, HZ, stepping=stepping, batched=True,
                               saveat=lj.SaveAt(reduce=lambda s: (_loss(s), s.result)))
    np.testing.assert_array_equal(np.asarray(result), np.asarray(sol.result))
    np.testing.assert_allclose(np.asarray(loss), np.asarray(_loss(sol)), rtol=1e-12)
    if isinstance(stepping, lj.FixedStep):  # the premise: the failed lane's loss is +inf through result
        assert np.isinf(np.asarray(loss)[2]) and np.isfinite(np.asarray(loss)[:2]).all()


def test_reduce_single_lane_adaptive():
    sol = lj.simulate(_system(), DURATION, HZ)
    loss = lj.simulate(_system(), DURATION, HZ, saveat=lj.SaveAt(reduce=_loss))
    assert np.ndim(loss) == 0
    np.testing.assert_allclose(float(loss), float(_loss(sol)), rtol=1e-12)


def _g(q):
    return q.theta


@pytest.mark.parametrize("kw", [dict(fn=_g, reduce=_g), dict(fn=_g, mean=_g), dict(reduce=_g, mean=_g),
                                dict(fn=_g, reduce=_g, mean=_g)], ids=["fn+reduce", "fn+mean", "reduce+mean", "all"])
def test_more_than_one_output_is_refused(kw):
    with pytest.raises(ValueError, match="give one of"):
        lj.SaveAt(**kw)


@pytest.mark.parametrize("name", ["fn", "reduce", "mean"])
@pytest.mark.parametrize("value", [3.0, "theta", (_g,)], ids=["float", "str", "tuple"])
def test_a_non_callable_is_refused(name, value):
    with pytest.raises(TypeError, match=f"SaveAt.{name} must be a function"):
        lj.SaveAt(**{name: value})


def test_one_output_each_is_accepted():
    for name in ("fn", "reduce", "mean"):
        assert getattr(lj.SaveAt(**{name: _g}), name) is _g
