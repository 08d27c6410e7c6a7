"""Plot the TRO2021 fits (data +- 2 SE, each model) from experiments/real_data_tro2021/results/."""

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from lugre_jax.io import save_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402

MODELS = ("coulomb_viscous_whole", "stribeck_whole", "stribeck_piecewise")


def main(argv=None) -> None:
    r = results_for_plot(__doc__, Path(__file__).with_name("results"), ("real_data.json",), argv)
    res = json.loads((r / "real_data.json").read_text())
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    for i, drive in enumerate(("driveNo1", "driveNo3")):
        for j, direction in enumerate(("positive", "negative")):
            ax = axes[i, j]
            plotted = False
            for k, m in enumerate(MODELS):
                tag = f"{drive}_{direction}_{m}"
                cf = r / f"curve_{tag}.csv"
                if not cf.exists():
                    continue
                if not plotted:
                    dd = np.genfromtxt(r / f"data_{tag}.csv", delimiter=",", names=True)
                    ax.errorbar(dd["velocity_deg_s"], 1e3 * dd["torque_nm"], yerr=2e3 * dd["torque_se_nm"], fmt="ko", ms=3, label="data (mean of run)")
                    plotted = True
                c = np.genfromtxt(cf, delimiter=",", names=True)
                row = next(x for x in res["table"] if x["drive"] == drive and x["direction"] == direction and x["model"] == m)
                ax.plot(c["velocity_deg_s"], 1e3 * c["model_nm"], ["C0-", "C1--", "C3-."][k], label=f"{m}: RMS {row['rms_mnm']:.3f} mN*m")
            ax.set_title(f"{drive}, {direction} direction", fontsize=10)
            ax.set_xlabel("|velocity| [deg/s] (motor side)")
            ax.set_ylabel("|torque| [mN*m]")
            ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, r / "real_data_tro2021.png")
    print(r / "real_data_tro2021.png")


if __name__ == "__main__":
    main()
