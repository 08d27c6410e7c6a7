"""A sweep chunk's fast stepping: the SPEC's fixed step, Tsit5 at 2.5 ms, and LaneAdaptive (the
default without a "stepping" key), on the shipped sweep SPECs: time per chunk (second call, after
compilation, fallback re-solves included) and each output's largest deviation from a tight stiff
solve on ``--tight`` of the lanes.

    python benchmarks/sweep_stepping.py [--lanes 2048] [--tight 64] [--out benchmarks/sweep_stepping.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

import lugre_jax as lj

ROOT = Path(__file__).resolve().parents[1]
SPECS = ("experiments/scenarios/sweep_creep_sobol.json", "experiments/scenarios/sweep_wide_lhs.json")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lanes", type=int, default=2048)
    ap.add_argument("--tight", type=int, default=64)
    ap.add_argument("--out", default="benchmarks/results/sweep_stepping.json")
    a = ap.parse_args(argv)
    lj.configure(host_devices=2)
    import diffrax
    import jax
    from scipy.stats import qmc

    from lugre_jax.sweep import load_spec, run_chunk

    tight = lj.Adaptive(diffrax.Kvaerno5(), rtol=1e-9, atol=1e-11, max_steps=200_000)
    out = {"command": "python benchmarks/sweep_stepping.py " + " ".join(argv or __import__("sys").argv[1:]),
           "device": f"{platform.processor() or platform.machine()}, {len(jax.devices())} host devices",
           "jax": jax.__version__, "loadavg": os.getloadavg(), "specs": []}
    for path in SPECS:
        spec = load_spec(ROOT / path)
        lo, hi = spec.bounds[:, 0], spec.bounds[:, 1]
        X = lo + qmc.Sobol(len(spec.names), scramble=True, seed=1).random(a.lanes) * (hi - lo)
        idx = np.linspace(0, a.lanes - 1, a.tight).round().astype(int)
        Yt, st = run_chunk(dataclasses.replace(spec, fast=tight, stiff=None, chunk_size=a.tight), X[idx])
        rows = []
        # the SPEC's own stepping, then the other two where it is not one of them
        steppings = dict.fromkeys((spec.fast, lj.FixedStep(diffrax.Tsit5(), dt=2.5e-3), lj.LaneAdaptive()))
        for stepping in steppings:
            s2 = dataclasses.replace(spec, fast=stepping, chunk_size=a.lanes)
            run_chunk(s2, X)
            t = time.perf_counter()
            Y, status = run_chunk(s2, X)
            secs = time.perf_counter() - t
            ok = (st == 0) & (status[idx] != 2)
            dev = {name: float(np.max(np.abs(Y[idx][ok, k] - Yt[ok, k])) / max(np.max(np.abs(Yt[ok, k])), 1e-300))
                   for k, name in enumerate(spec.output_names)}
            rows.append({"stepping": stepping.describe(), "chunk_s": secs, "ms_per_lane": 1e3 * secs / a.lanes,
                         "status_counts": np.bincount(status, minlength=3).tolist(),
                         "max_relative_deviation": dev})
            print(f"{path.split('/')[-1]:28s} {stepping.describe():58s} {1e3 * secs / a.lanes:.4f} ms/lane "
                  f"status {rows[-1]['status_counts']} worst rel dev {max(dev.values()):.2g}", flush=True)
        out["specs"].append({"spec": path, "lanes": a.lanes, "tight_lanes": int(ok.sum()), "rows": rows})
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
