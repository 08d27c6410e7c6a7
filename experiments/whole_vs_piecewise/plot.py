"""Plot whole vs piecewise residuals from experiments/whole_vs_piecewise/results/."""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import read_results, write_figure  # noqa: E402


def main(argv=None) -> None:
    r, (s, res, cur) = read_results(__doc__, Path(__file__).with_name("results"),
                                    ("whole_vs_piecewise.json", "residuals.csv", "curves.csv"), argv)
    fig, axes = plt.subplots(2, 3, figsize=(15, 7.5))
    spans = [(0.0, 1.55), (0.0, 0.15), (1.0, 1.45)]
    for j, (lo, hi) in enumerate(spans):
        ax = axes[0, j]
        m = (res["velocity_deg_s"] >= lo) & (res["velocity_deg_s"] <= hi)
        mc = (cur["velocity_deg_s"] >= lo) & (cur["velocity_deg_s"] <= hi)
        ax.errorbar(res["velocity_deg_s"][m], res["torque_nm"][m], yerr=2 * res["torque_se_nm"][m], fmt="o", ms=3, color="0.5", label="data (accel)")
        ax.plot(cur["velocity_deg_s"][mc], cur["whole_nm"][mc], "C0-", label="whole (one Stribeck set)")
        ax.plot(cur["velocity_deg_s"][mc], cur["piecewise_nm"][mc], "C3--", label="piecewise (detected edges)")
        ax.plot(cur["velocity_deg_s"][mc], cur["paper_edges_nm"][mc], "C2:", label="piecewise (paper edges 0.05/1.2)")
        ax.set_xlabel("velocity [deg/s]")
        ax.set_ylabel("torque [N*m]")
        ax2 = axes[1, j]
        ax2.axhline(0, color="k", lw=0.6)
        ax2.fill_between(res["velocity_deg_s"][m], -2 * res["torque_se_nm"][m], 2 * res["torque_se_nm"][m], color="0.85", label="+-2 SE of the data")
        ax2.plot(res["velocity_deg_s"][m], res["residual_whole_nm"][m], "C0o-", ms=3, label="whole")
        ax2.plot(res["velocity_deg_s"][m], res["residual_piecewise_nm"][m], "C3s-", ms=3, label="piecewise (detected)")
        ax2.plot(res["velocity_deg_s"][m], res["residual_paper_edges_nm"][m], "C2^-", ms=3, label="piecewise (paper edges)")
        ax2.set_xlabel("velocity [deg/s]")
        ax2.set_ylabel("model - data [N*m]")
    w = s["windows"]
    axes[0, 0].legend(fontsize=8)
    axes[1, 0].legend(fontsize=8)
    axes[0, 0].set_title(f"all: RMS whole {w['all']['rms_whole_nm']:.3f}, piecewise {w['all']['rms_piecewise_nm']:.3f} / {w['all']['rms_piecewise_paper_edges_nm']:.3f} N*m", fontsize=9)
    axes[0, 1].set_title(f"near 0.05 deg/s: RMS whole {w['near_0.05']['rms_whole_nm']:.3f}, piecewise {w['near_0.05']['rms_piecewise_nm']:.3f} / {w['near_0.05']['rms_piecewise_paper_edges_nm']:.3f}", fontsize=9)
    axes[0, 2].set_title(f"near 1.2 deg/s: RMS whole {w['near_1.2']['rms_whole_nm']:.3f}, piecewise {w['near_1.2']['rms_piecewise_nm']:.3f} / {w['near_1.2']['rms_piecewise_paper_edges_nm']:.3f}", fontsize=9)
    write_figure(fig, r / "whole_vs_piecewise.png")


if __name__ == "__main__":
    main()
