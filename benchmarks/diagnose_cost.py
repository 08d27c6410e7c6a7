"""What a diagnosis costs on a long recording, and what share is the calibrated test.

One process: a 100-s staircase at 1 kHz (100,001 samples) from the independent generator
(lugre_jax.testing), with an asymmetry of 0.04 N*m, diagnosed three times: once cold (compilation
included), then warm with the default null draws (DiagnoseConfig().draws) and warm with 60 (the
fewest that can resolve a third of alpha 0.05), so that the difference is the cost of the draws
between. Prints one line per run and writes JSON.

    python benchmarks/diagnose_cost.py --out benchmarks/diagnose_cost.json
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import lugre_jax
from lugre_jax import testing as T
from lugre_jax.diagnose import DiagnoseConfig, diagnose


def _commit() -> str | None:
    """The checkout's commit, so that a figure names the code it measured (None outside git)."""
    import subprocess

    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="benchmarks/diagnose_cost.json")
    ap.add_argument("--seconds", type=float, default=100.0)
    ap.add_argument("--fs", type=float, default=1000.0)
    a = ap.parse_args()
    lugre_jax.configure()
    t0 = time.perf_counter()
    g = T.generate(T.Staircase(speeds=(0.05, 0.2, 1.0, 4.0), dwell=a.seconds / 16, seed=1), [T.AsymmetryEffect(0.04)],
                   sensors=T.Sensors(fs=a.fs), seed=3)
    rec = g.to_recording()
    gen_s = time.perf_counter() - t0
    rows = []
    d = DiagnoseConfig().draws
    for label, draws in ((f"cold, {d} null draws", d), (f"warm, {d} null draws", d), ("warm, 60 null draws", 60)):
        t0 = time.perf_counter()
        rep = diagnose(rec, progress=False, null_draws=draws)
        s = time.perf_counter() - t0
        rows.append({"run": label, "null_draws": draws, "seconds": s, "verdict": rep.verdict})
        print(f"{label}: {s:.1f} s, verdict {rep.verdict}", flush=True)
    out = {"samples": int(rec.n), "generation_s": gen_s, "runs": rows,
           "seconds_per_null_draw": (rows[1]["seconds"] - rows[2]["seconds"]) / (d - 60),
           "commit": _commit(),
           "machine": {"cpus": os.cpu_count(), "platform": platform.platform(), "load": os.getloadavg()}}
    with open(a.out, "w") as fh:
        json.dump(out, fh, indent=2)
    print(f"{rec.n} samples; a null draw costs {out['seconds_per_null_draw']:.2f} s; wrote {a.out}")


if __name__ == "__main__":
    main()
