"""Plot recovery vs the CRLB from experiments/recovery_crlb/results/: estimate histograms with the
truth and the CRLB-width normal density, and the standardised errors."""

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from lugre_jax.io import save_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402

NAMES = ("Fc", "Fs", "vs", "sigma2")


def main(argv=None) -> None:
    r = results_for_plot(__doc__, Path(__file__).with_name("results"), ("recovery.json",), argv)
    s = json.loads((r / "recovery.json").read_text())
    e = np.genfromtxt(r / "estimates.csv", delimiter=",", names=True)
    fig, axes = plt.subplots(2, 4, figsize=(15, 6.5))
    for k, n in enumerate(NAMES):
        x, t, sd = e[n], s["truth"][n], s["crlb_sd"][n]
        ax = axes[0, k]
        ax.hist(x, bins=20, density=True, alpha=0.6, label=f"{s['n_realisations']} estimates")
        g = np.linspace(t - 4 * sd, t + 4 * sd, 200)
        ax.plot(g, np.exp(-0.5 * ((g - t) / sd) ** 2) / (sd * np.sqrt(2 * np.pi)), "k-", label="N(truth, CRLB)")
        ax.axvline(t, color="r")
        ax.set_title(f"{n}: var/CRLB = {s['variance_over_crlb'][n]:.2f}", fontsize=10)
        ax.legend(fontsize=7)
        ax2 = axes[1, k]
        z = (x - t) / e[n + "_se"]
        ax2.hist(z, bins=np.linspace(-4, 4, 33), alpha=0.7)
        for b in (-2, 2):
            ax2.axvline(b, color="k", ls=":")
        ax2.set_title(f"(est - truth)/SE: {100 * s['fraction_within_2se'][n]:.0f}% within 2 SE", fontsize=10)
    fig.suptitle(f"Recovery of known Stribeck parameters ({s['method']}, {s['n_realisations']} noise realisations)", fontsize=11)
    save_figure(fig, r / "recovery_crlb.png")
    print(r / "recovery_crlb.png")


if __name__ == "__main__":
    main()
