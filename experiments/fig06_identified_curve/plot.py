"""Plot Fig. 6 (identified Stribeck curve over the data's fitting curve) from results/."""

import sys
from pathlib import Path

import matplotlib.pyplot as plt

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import read_results, write_figure  # noqa: E402


def main(argv=None) -> None:
    r, (res, c, av) = read_results(__doc__, Path(__file__).with_name("results"),
                                   ("identification.json", "curves.csv", "averaged.csv"), argv)
    b = res["boundaries"]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.4))
    for ax, xmax, logx in zip(axes, (1.55, 1.55), (False, True)):
        for dec, mk in ((0.0, "o"), (1.0, "s")):
            m = av["decel"] == dec
            ax.plot(av["velocity_deg_s"][m], av["torque_nm"][m], mk, ms=3, color="0.6",
                    label="averaged data (decel)" if dec else "averaged data (accel)")
        ax.plot(c["velocity_deg_s"], c["spline_nm"], "k-", lw=1.2, label="fitting curve of the test data (spline)")
        ax.plot(c["velocity_deg_s"], c["identified_accel_nm"], "r--", lw=1.8, label=f"identified Stribeck ({res['method']}, piecewise)")
        ax.plot(c["velocity_deg_s"], c["identified_decel_nm"], "m--", lw=1.4, label="identified, decelerating branch")
        for v in (b["v_min_deg_s"], b["v_crit_deg_s"]):
            ax.axvline(v, color="gray", ls=":", lw=0.8)
        ax.set_xlabel("velocity [deg/s]")
        ax.set_ylabel("friction torque [N*m]")
        if logx:
            ax.set_xscale("log")
            ax.set_xlim(0.004, xmax)
    axes[0].legend(fontsize=7)
    axes[0].set_title(f"Fig. 6 analogue: RMS {res['rms_nm']:.3g} N*m over {res['data']['n_set_points']} set-points", fontsize=10)
    axes[1].set_title("same, log velocity axis", fontsize=10)
    write_figure(fig, r / "fig06_identified_curve.png")


if __name__ == "__main__":
    main()
