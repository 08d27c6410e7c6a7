"""Batched solves split over the host devices or not: the evidence for simulate's split rule.

    python benchmarks/shard_split.py [--lanes 20,200,2000] [--rows default,lane]
                                     [--out benchmarks/shard_split.json]

The lanes of benchmarks/sim_vs_scipy.py (the paper's joint under velocity PI on the staircase, 20 s
at 100 Hz), whole trajectories, chunks of 200 lanes (fewer lanes: one chunk per device), timed as
the best of two calls after compilation with ``Lanes(shard=False)`` and ``Lanes(shard=True)``, and
what ``simulate`` chooses by itself (``Lanes()``). Prints one line per row and writes the JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import platform

import lugre_jax as lj
from _timing import best_of
from sim_vs_scipy import DURATION, HZ, batch, draw


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lanes", default="20,200,2000")
    ap.add_argument("--rows", default="default,lane")
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    lj.configure(host_devices=2)
    import jax

    steppings = {"default": ("Adaptive() (the default)", lj.Adaptive()), "lane": ("LaneAdaptive()", lj.LaneAdaptive())}
    rows = []
    for lanes in (int(x) for x in a.lanes.split(",")):
        system = batch(*draw(lanes))
        for key in a.rows.split(","):
            label, stepping = steppings[key]
            row = dict(lanes=lanes, stepping=label)
            for name, layout in (("one_device", lj.Lanes(chunk_size=min(200, lanes), shard=False)),
                                 ("two_devices", lj.Lanes(chunk_size=min(200, -(-lanes // 2)), shard=True)),
                                 ("chosen", lj.Lanes(chunk_size=None, shard=None))):
                wall = best_of(lambda: jax.block_until_ready(
                    lj.simulate(system, DURATION, HZ, batched=True, stepping=stepping, lanes=layout).theta), 2)
                row[name + "_ms_per_solve"] = 1e3 * wall / lanes
            rows.append(row)
            print(f"{lanes:6d} lanes  {label:26s} one device {row['one_device_ms_per_solve']:.3f}  two devices "
                  f"{row['two_devices_ms_per_solve']:.3f}  chosen {row['chosen_ms_per_solve']:.3f} ms per solve",
                  flush=True)
    result = dict(command="python benchmarks/shard_split.py " + " ".join(argv or []), rows=rows,
                  device=f"cpu: {platform.machine()}, {os.cpu_count()} cores, {len(jax.local_devices())} XLA devices",
                  jax=jax.__version__, loadavg=list(os.getloadavg()))
    if a.out:
        with open(a.out, "w") as f:
            json.dump(result, f, indent=1)
        print(a.out)


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
