"""One tree's time per call of batched forward solves of the paper's joint (20 s at 100 Hz, a
per-lane RMS tracking error returned), min of 5 calls, wall and CPU time. Run it on two trees in
turn to compare them in one session, e.g.

    git worktree add /tmp/landed <commit>
    for r in 1 2; do PYTHONPATH=/tmp/landed python benchmarks/landed_ab.py landed
                     PYTHONPATH=. python benchmarks/landed_ab.py new; done
"""
import os, sys, time
import numpy as np, jax, diffrax, equinox as eqx, jax.numpy as jnp
import lugre_jax as lj
lj.configure()
tag = sys.argv[1]
one = lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=lj.PAPER_J), controller=lj.VelocityPID(kp=8.0, ki=60.0),
                reference=lj.VelocitySteps([0.02, 0.1, -0.05, 0.5], dwell_s=5.0))
def track(sol):
    return jnp.sqrt(jnp.mean((sol.theta - sol.theta_ref) ** 2)), sol.result
cases = [("bosh3_20ms_b1000", lj.FixedStep(diffrax.Bosh3(), dt=0.02), 1000),
         ("tsit5_2.5ms_b200", lj.FixedStep(diffrax.Tsit5(), dt=2.5e-3), 200),
         ("bosh3_5ms_b1", lj.FixedStep(diffrax.Bosh3(), dt=0.005), 1),
         ("adaptive_b200", lj.Adaptive(), 200)]
for name, st, b in cases:
    s = lj.broadcast_system(one, b)
    f = lambda: jax.block_until_ready(lj.simulate(s, 20.0, 100.0, batched=True, stepping=st, saveat=lj.SaveAt(reduce=track)))
    f()
    walls, cpus = [], []
    for _ in range(5):
        t, c = time.perf_counter(), time.process_time(); f()
        walls.append(time.perf_counter() - t); cpus.append(time.process_time() - c)
    print(f"{tag:7s} {name:20s} wall {min(walls)*1e3:9.2f} cpu {min(cpus)*1e3:9.2f} ms/call  load {os.getloadavg()[0]:.1f}", flush=True)
