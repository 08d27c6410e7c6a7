"""A per-lane mean loss (mean squared position tracking error, ``SaveAt(mean=...)``) over 200 lanes
of the scipy-loop benchmark's scenario (benchmarks/sim_vs_scipy.py): CPU time per lane, min of 3
calls, and each stepping's largest relative error of the loss against a tight solve.

    python benchmarks/lane_mean.py
"""
import os
import time
import numpy as np, jax, jax.numpy as jnp, diffrax, equinox as eqx
import lugre_jax as lj
lj.configure()
B = 200
rng = np.random.default_rng(0)
Fs = rng.uniform(3, 8, B); s0 = rng.uniform(50, 200, B)
one = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=lj.PAPER_J), controller=lj.VelocityPID(kp=8.0, ki=60.0),
                reference=lj.VelocitySteps([0.02, 0.1, -0.05, 0.5], dwell_s=5.0))
sysb = eqx.tree_at(lambda s: (s.friction.Fs, s.friction.sigma0), lj.broadcast_system(one, B), (jnp.asarray(Fs), jnp.asarray(s0)))
sa = lj.SaveAt(mean=lambda smp: (smp.theta - smp.theta_ref) ** 2)
sts = {"lane": lj.LaneAdaptive(), "adaptive": lj.Adaptive(), "bosh3_5ms": lj.FixedStep(diffrax.Bosh3(), dt=0.005)}
vals = {}
for k, st in sts.items():
    vals[k] = np.asarray(lj.simulate(sysb, 20.0, 100.0, batched=True, stepping=st, saveat=sa).value)
tight = np.asarray(lj.simulate(sysb, 20.0, 100.0, batched=True, stepping=lj.Adaptive(rtol=1e-11, atol=1e-13), saveat=sa).value)
res = {k: [] for k in sts}
for r in range(3):
    for k, st in sts.items():
        c = time.process_time(); jax.block_until_ready(lj.simulate(sysb, 20.0, 100.0, batched=True, stepping=st, saveat=sa).value); res[k].append((time.process_time() - c) * 1e3 / B)
for k, v in res.items():
    print(f"{k:10s} mean-loss cpu ms/lane min {min(v):.3f} all {[round(x, 3) for x in v]}  max rel err of the loss {np.max(np.abs(vals[k] - tight) / np.abs(tight)):.1e}", flush=True)
print("load", os.getloadavg())
