"""Per-call time of a small batched solve: `lugre-jax bench`'s throughput configuration.

    python benchmarks/percall.py [BATCH=1] [CALLS=2000] [REPS=5]

The bench's system (the paper's segmented joint, J 0.128, velocity PI kp 8, ki 60 at 0.02 deg/s,
Fc, Fs, sigma0, sigma1, sigma2 scaled per lane by factors in [0.9, 1.1], seed 3), 20 s at 100 Hz,
``FixedStep(Bosh3(), dt=0.02)``, each lane reduced inside the call to its mean squared position and
velocity tracking errors (``SaveAt(reduce=...)``). CALLS calls are timed together, REPS times; prints
the minimum and median wall and CPU time per call. Public API only; the stepping, saveat and
system are built once, as a user holds them, so the timed loop measures the call.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

import lugre_jax as lj

DURATION, HZ, V_CMD, KP, KI = 20.0, 100.0, 0.02, 8.0, 60.0
SCALED = ("Fc", "Fs", "sigma0", "sigma1", "sigma2")


def bench_system(batch: int, seed: int = 3) -> lj.System:
    import equinox as eqx

    base = lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=lj.PAPER_J),
                     controller=lj.VelocityPID(kp=KP, ki=KI), reference=lj.VelocitySteps([V_CMD]))
    factors = np.random.default_rng(seed).uniform(0.9, 1.1, size=(batch, len(SCALED)))
    system = lj.broadcast_system(base, batch)
    segs = []
    for seg in system.friction.segments:
        for j, name in enumerate(SCALED):
            seg = eqx.tree_at(lambda m: getattr(m, name), seg, getattr(seg, name) * factors[:, j])
        segs.append(seg)
    return eqx.tree_at(lambda s: s.friction.segments, system, tuple(segs))


def tracking_errors(sol):
    """Per lane: mean squared position and velocity tracking errors, and the result code."""
    import jax.numpy as jnp

    return (jnp.mean((sol.theta - sol.theta_ref) ** 2), jnp.mean((sol.omega - sol.v_ref) ** 2)), sol.result


def main(argv):
    batch, calls, reps = (int(a) for a in (list(argv) + ["1", "2000", "5"][len(argv):]))
    lj.configure()
    import diffrax
    import jax

    system = bench_system(batch)
    stepping, saveat = lj.FixedStep(diffrax.Bosh3(), dt=0.02), lj.SaveAt(reduce=tracking_errors)

    def run():
        return lj.simulate(system, DURATION, HZ, batched=True, stepping=stepping, saveat=saveat)

    jax.block_until_ready(run())
    wall, cpu = [], []
    for _ in range(reps):
        t, c = time.perf_counter(), time.process_time()
        for _ in range(calls):
            jax.block_until_ready(run())
        wall.append((time.perf_counter() - t) / calls * 1e3)
        cpu.append((time.process_time() - c) / calls * 1e3)
    print(f"batch={batch} wall min {min(wall):.3f} med {np.median(wall):.3f}  cpu min {min(cpu):.3f} "
          f"med {np.median(cpu):.3f} ms/call  load {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
