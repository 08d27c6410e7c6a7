"""Bar chart of the PSO speed study: jax (batched seeds) vs pyswarms vs the exp floor.

    python experiments/pso_speed/plot.py [--results DIR]

Writes DIR/pso_speed.png.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib.pyplot as plt

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import read_results, write_figure  # noqa: E402


def main(argv=None) -> None:
    res, (d,) = read_results(__doc__, Path(__file__).resolve().with_name("results"), ("pso_speed.json",), argv)
    n = d["exps_per_pso_run"]
    vals = {
        "pyswarms (loop over seeds)": d["pyswarms"]["per_seed_ms"],
        "lugre_jax PSO (vmapped seeds)": d["jax_pso"]["per_seed_ms"],
        "lugre_jax PSO, hash rng": d["jax_pso_hash_rng"]["per_seed_ms"],
        f"exp floor ({n} exps)": 1e3 * d["floor_time_all_seeds_s"] / d["seeds"],
    }
    fig, ax = plt.subplots(figsize=(7, 3.0))
    ax.barh(list(vals), list(vals.values()), color=["C7", "C0", "C1", "C2"])
    ax.set_xscale("log")
    ax.set_xlabel("time per seed [ms] (100 particles x 100 iterations, 92-point Stribeck loss)")
    ax.invert_yaxis()
    for i, v in enumerate(vals.values()):
        ax.text(v, i, f" {v:.2f}", va="center", fontsize=8)
    ax.set_title(f"speed-up {d['speedup_per_seed']:.1f}x ({d['speedup_per_seed_hash_rng']:.1f}x hash rng); "
                 f"{d['ours_over_floor']:.1f}x ({d['ours_hash_rng_over_floor']:.1f}x) the exp floor", fontsize=10)
    write_figure(fig, res / "pso_speed.png")


if __name__ == "__main__":
    main()
