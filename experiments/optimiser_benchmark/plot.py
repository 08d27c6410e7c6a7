"""Draw the optimiser benchmark: success rate and evaluations to success per method.

    python experiments/optimiser_benchmark/plot.py [--results DIR]

Writes DIR/benchmark.png.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import read_results, write_figure  # noqa: E402


def main(argv=None) -> None:
    res, (d,) = read_results(__doc__, Path(__file__).resolve().with_name("results"), ("benchmark.json",), argv)
    labels = list(d["methods"])
    ms = [d["methods"][k] for k in labels]
    y = np.arange(len(labels))
    fig, axes = plt.subplots(1, 3, figsize=(14, 0.45 * len(labels) + 1.5), sharey=True)
    axes[0].barh(y, [m["success_rate"] for m in ms], color="C0")
    axes[0].set_xlabel("success rate (J <= 1.01 J_ref)")
    axes[0].set_xlim(0, 1)
    ev = [m["evals_to_success_median"] or np.nan for m in ms]
    per = [m["expected_evals_per_success"] or np.nan for m in ms]
    axes[1].barh(y - 0.2, ev, height=0.4, color="C1", label="median evals to success")
    axes[1].barh(y + 0.2, per, height=0.4, color="C2", label="evals used per success")
    axes[1].set_xscale("log")
    axes[1].set_xlabel("loss evaluations")
    axes[1].legend(fontsize=8)
    axes[2].barh(y, [1e3 * m["wall_time_per_seed_s"] for m in ms], color="C3")
    axes[2].set_xscale("log")
    axes[2].set_xlabel("wall time per seed [ms] (batched, compile excluded)")
    axes[0].set_yticks(y, labels, fontsize=8)
    axes[0].invert_yaxis()
    for ax in axes:
        ax.grid(alpha=0.3, axis="x")
    fig.suptitle(f"Static whole-range Stribeck identification, {d['seeds']} seeds per method", fontsize=10)
    write_figure(fig, res / "benchmark.png")


if __name__ == "__main__":
    main()
