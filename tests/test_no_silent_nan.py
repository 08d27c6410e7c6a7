"""No silent NaN: random parameter sets within the library's declared bounds (lj.bounds_of) either
simulate to finite outputs or carry a failure code, lane by lane, for both steppings."""

import diffrax
import equinox as eqx
import jax.numpy as jnp
import numpy as np

import lugre_jax as lj


def _swarm(n, seed):
    lo, hi = (np.asarray(b) for b in lj.bounds_of(lj.LuGre))
    p = np.random.default_rng(seed).uniform(lo, hi, (n, 6))
    base = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=0.128),
                     controller=lj.VelocityPID(kp=8.0, ki=60.0),
                     reference=lj.VelocitySteps([0.02, -0.5, 2.0], dwell_s=0.7))
    swarm = lj.broadcast_system(base, n)
    for j, name in enumerate(lj.names_of(lj.LuGre)):
        swarm = eqx.tree_at(lambda s, name=name: getattr(s.friction, name), swarm, jnp.asarray(p[:, j]))
    return swarm


def _finite(sol):
    outs = (sol.ys, sol.torque_nm, sol.friction_nm)
    return jnp.all(jnp.stack([jnp.all(jnp.isfinite(x)) for x in outs])), sol.result


def test_100k_random_lanes_fixed_step_are_finite_or_flagged():
    swarm = _swarm(100_000, seed=0)
    finite, result = lj.simulate(swarm, 2.0, 50.0, batched=True, stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02),
                                 saveat=lj.SaveAt(reduce=_finite))
    finite, result = np.asarray(finite), np.asarray(result)
    ok = result == lj.RESULT_OK
    assert np.all(finite[ok]), "a lane reported success with non-finite outputs"
    assert np.all(np.isin(result[~ok], [lj.RESULT_NONFINITE, lj.RESULT_SOLVER_FAILED]))
    assert 0 < ok.sum() < ok.size  # premise: the bounds produce both outcomes at this coarse step
    loss = np.asarray(lj.simulate(swarm, 2.0, 50.0, batched=True,
                                  stepping=lj.FixedStep(diffrax.Bosh3(), dt=0.02),
                                  saveat=lj.SaveAt(mean=lambda q: (q.theta - q.theta_ref) ** 2)).or_inf())
    assert not np.isnan(loss).any() and np.all(np.isinf(loss[~ok])) and np.all(np.isfinite(loss[ok]))


def test_random_lanes_adaptive_are_finite_or_flagged():
    swarm = _swarm(64, seed=1)
    finite, result = lj.simulate(swarm, 2.0, 50.0, batched=True, stepping=lj.Adaptive(diffrax.Kvaerno5(), max_steps=20_000),
                                 saveat=lj.SaveAt(reduce=_finite))
    finite, result = np.asarray(finite), np.asarray(result)
    ok = result == lj.RESULT_OK
    assert np.all(finite[ok])
    assert ok.mean() > 0.9  # the stiff solver handles nearly every in-bounds lane
