"""Plot Fig. 4 (spline fits per segment and eq. 12 curves) from experiments/fig04_spline_fits/results/."""

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from lugre_jax.io import save_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402


def main(argv=None) -> None:
    r = results_for_plot(__doc__, Path(__file__).with_name("results"), ("fig04.json", "averaged.csv"), argv)
    s = json.loads((r / "fig04.json").read_text())
    av = np.genfromtxt(r / "averaged.csv", delimiter=",", names=True)
    names = list(s["sum_of_sines_eq12"])
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    panels = {"1": 0, "1 decel": 0, "2": 1, "3": 2}
    titles = ["low-velocity segment (1): accel + decel", "low-velocity segment (2)", "high-velocity segment (3)"]
    for name in names:
        c = np.genfromtxt(r / f"segment_{name.replace(' ', '_')}.csv", delimiter=",", names=True)
        ax = axes[panels[name]]
        dec = name.endswith("decel")
        lo, hi = c["velocity_deg_s"][0], c["velocity_deg_s"][-1]
        m = (av["velocity_deg_s"] >= lo - 1e-12) & (av["velocity_deg_s"] <= hi + 1e-12) & ((av["decel"] == 1.0) == dec)
        ax.errorbar(av["velocity_deg_s"][m], av["torque_nm"][m], yerr=2 * av["torque_se_nm"][m], fmt="s" if dec else "o",
                    ms=3, alpha=0.7, label=f"data {name}")
        ax.plot(c["velocity_deg_s"], c["spline_nm"], "-", lw=1.5, label=f"cubic spline {name}")
        rms = s["sum_of_sines_eq12"][name]["rms"]
        ax.plot(c["velocity_deg_s"], c["sum_of_sines_nm"], "--", lw=1.2, label=f"eq. (12) sum of 4 sines (RMS {rms:.1e})")
    for ax, t in zip(axes, titles):
        ax.set_title(t, fontsize=10)
        ax.set_xlabel("velocity [deg/s]")
        ax.set_ylabel("friction torque [N*m]")
        ax.legend(fontsize=7)
    axes[0].axvline(s["v_min_deg_s"], color="gray", ls=":")
    fig.suptitle(f"Fig. 4 analogue: boundaries v_min = {s['v_min_deg_s']:.4f}, v_crit = {s['v_crit_deg_s']:.4f} deg/s "
                 f"({'detected' if s['detected'] else 'given'})", fontsize=10)
    save_figure(fig, r / "fig04_spline_fits.png")
    print(r / "fig04_spline_fits.png")


if __name__ == "__main__":
    main()
