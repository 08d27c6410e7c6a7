"""Where a batched trajectory's time goes: the scipy-loop benchmark's 2,000 lanes (benchmarks/
sim_vs_scipy.py), two host devices, wall time per lane (best of 3 after compilation), one process.

    python benchmarks/trajectory_cost.py [--lanes 2000] [--out benchmarks/trajectory_cost.json]

Rows: ``LaneAdaptive()`` returning the trajectory (a Solution: 8 states and 4 signals per sample),
and only the positions (``SaveAt(fn=...)``: the function's values written where each sample is
interpolated);
the same steps returning one per-lane mean (``SaveAt(mean=...)``: nothing stored per sample);
``FixedStep(Tsit5(), dt=0.01)`` (2,000 cheap steps) returning the trajectory; and the floor of any
trajectory: a jitted function that only writes arrays of a Solution's size and layout, sharded as
``simulate`` shards them.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
from pathlib import Path

import numpy as np

import lugre_jax as lj
from _timing import best_of


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--lanes", type=int, default=2000)
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    lj.configure(host_devices=2)
    import diffrax
    import jax
    import jax.numpy as jnp
    from jax.sharding import Mesh, NamedSharding, PartitionSpec

    import sim_vs_scipy as S

    n = int(S.DURATION * S.HZ) + 1
    system = S.batch(*S.draw(a.lanes))
    mean = lj.SaveAt(mean=lambda smp: (smp.theta - smp.theta_ref) ** 2)
    rows = {
        "LaneAdaptive(), trajectory": lambda: lj.simulate(system, S.DURATION, S.HZ, batched=True,
                                                          stepping=lj.LaneAdaptive()).theta,
        "LaneAdaptive(), positions only (SaveAt(fn=...))": lambda: lj.simulate(
            system, S.DURATION, S.HZ, batched=True, stepping=lj.LaneAdaptive(), saveat=S.POSITIONS).value,
        "LaneAdaptive(), SaveAt(mean=...)": lambda: lj.simulate(system, S.DURATION, S.HZ, batched=True,
                                                                stepping=lj.LaneAdaptive(), saveat=mean).value,
        "FixedStep(Tsit5(), dt=0.01), trajectory": lambda: lj.simulate(
            system, S.DURATION, S.HZ, batched=True, stepping=lj.FixedStep(diffrax.Tsit5(), dt=0.01)).theta,
    }
    devices = jax.local_devices()[:2]
    mesh = Mesh(np.array(devices), ("lanes",))

    def write_only(x):
        ys = x[:, None, None] * jnp.ones((1, n, 8))
        return ys, ys[..., 0] * 2.0, ys[..., 1] * 3.0, ys[..., 2] + 1.0, ys[..., 3] - 1.0

    floor = jax.jit(jax.shard_map(write_only, mesh=mesh, in_specs=PartitionSpec("lanes"),
                                  out_specs=PartitionSpec("lanes")))
    x = jax.device_put(jnp.arange(float(a.lanes)), NamedSharding(mesh, PartitionSpec("lanes")))
    rows["writing a Solution's arrays only"] = lambda: floor(x)
    out = []
    for label, fn in rows.items():
        wall = best_of(lambda: jax.block_until_ready(fn()), 3)
        out.append(dict(row=label, per_lane_ms=1e3 * wall / a.lanes))
        print(f"{label:45s} {1e3 * wall / a.lanes:8.4f} ms per lane", flush=True)
    result = dict(lanes=a.lanes, samples=n, devices=[str(d) for d in devices], cpu=platform.processor() or platform.machine(),
                  jax=jax.__version__, loadavg=os.getloadavg(), rows=out)
    if a.out:
        Path(a.out).write_text(json.dumps(result, indent=1) + "\n")
        print(a.out)


if __name__ == "__main__":
    main()
