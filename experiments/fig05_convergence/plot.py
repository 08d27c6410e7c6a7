"""Draw Fig. 5-style convergence curves from run.py's results (best-so-far J vs iteration and vs evaluations).

    python experiments/fig05_convergence/plot.py [--results DIR]

Writes DIR/fig05_convergence.png.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import read_results, write_figure  # noqa: E402


def main(argv=None) -> None:
    res, (d,) = read_results(__doc__, Path(__file__).resolve().with_name("results"), ("convergence.json",), argv)
    j_ref = d["problem"]["reference_J"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for (label, m), c in zip(d["methods"].items(), ["C0", "C3", "C2"]):
        med, lo, hi = (np.asarray(m[k], float) - j_ref for k in ("median_history", "p10_history", "p90_history"))
        it = np.arange(len(med))
        ev = np.asarray(m["evals_history"], float)
        for ax, xs in zip(axes, (it, ev)):
            ax.plot(xs, med, color=c, label=label)
            ax.fill_between(xs, lo, hi, color=c, alpha=0.2, lw=0)
    for ax, xl in zip(axes, ("iteration", "loss evaluations")):
        ax.set_yscale("log")
        ax.axhline(0.01 * j_ref, color="k", ls=":", lw=1, label="1% of $J_{ref}$")
        ax.set_xlabel(xl)
        ax.set_ylabel("best-so-far $J - J_{ref}$ [N$^2$m$^2$]")
        ax.grid(alpha=0.3)
    axes[1].set_xscale("log")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"Segment (1) static identification, {d['seeds']} seeds: median and 10-90% band "
                 f"($J_{{ref}}$ = {j_ref:.4g})", fontsize=10)
    write_figure(fig, res / "fig05_convergence.png")


if __name__ == "__main__":
    main()
