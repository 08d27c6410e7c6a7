"""Plot Fig. 3b (synthetic stand-in) from experiments/fig03b_data/results/ -> fig03b_data.png."""

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from lugre_jax.io import save_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402


def main(argv=None) -> None:
    r = results_for_plot(__doc__, Path(__file__).with_name("results"), ("averaged.csv", "model.csv", "summary.json"), argv)
    av = np.genfromtxt(r / "averaged.csv", delimiter=",", names=True)
    mo = np.genfromtxt(r / "model.csv", delimiter=",", names=True)
    s = json.loads((r / "summary.json").read_text())
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, xmax in zip(axes, (1.55, 0.15)):
        for dec, mk, lab in ((0.0, "o", "accelerating"), (1.0, "s", "decelerating")):
            m = av["decel"] == dec
            ax.errorbar(av["velocity_deg_s"][m], av["torque_nm"][m], yerr=2 * av["torque_se_nm"][m], fmt=mk, ms=3.5,
                        label=f"mean of 30 samples ({lab}), +-2 SE")
        ax.plot(mo["velocity_deg_s"], mo["accel_nm"], "k-", lw=0.8, label="Table 1 model (generator)")
        ax.plot(mo["velocity_deg_s"], mo["decel_nm"], "k--", lw=0.8, label="decelerating branch (generator)")
        ax.axvline(s["detected_v_min_deg_s"], color="C3", ls=":", label=f"detected v_min {s['detected_v_min_deg_s']:.3f}")
        ax.axvline(s["detected_v_crit_deg_s"], color="C2", ls=":", label=f"detected v_crit {s['detected_v_crit_deg_s']:.3f}")
        ax.set_xlim(0, xmax)
        ax.set_xlabel("velocity [deg/s]")
        ax.set_ylabel("friction torque [N*m]")
    axes[1].set_ylim(0.8, 7)
    axes[0].set_title(f"Synthetic Fig. 3b: {s['n_set_points']} set-points (paper's data not public)")
    axes[1].set_title("low-velocity segment (zoom)")
    axes[0].legend(fontsize=7)
    save_figure(fig, r / "fig03b_data.png")
    print(r / "fig03b_data.png")


if __name__ == "__main__":
    main()
