"""Draw Fig. 13 from results/fig13.csv: position vs the ideal ramp, velocity with the band."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from lugre_jax.io import save_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402


def main(argv=None):
    out = results_for_plot(__doc__, Path(__file__).with_name("results"), ("fig13.json",), argv)
    meta = json.loads((out / "fig13.json").read_text())
    with open(out / "fig13.csv") as f:
        names = f.readline().strip().split(",")
    data = np.loadtxt(out / "fig13.csv", delimiter=",", skiprows=1)
    col = {n: data[:, i] for i, n in enumerate(names)}
    t = col["time_s"]
    vs = [s["velocity_cmd_deg_s"] for s in meta["summary"]]
    fig, ax = plt.subplots(2, len(vs), figsize=(4 * len(vs), 6), squeeze=False)
    for i, v in enumerate(vs):
        ax[0, i].plot(t, col[f"position_ref_deg_v{v}"], "r", label="command")
        ax[0, i].plot(t, col[f"position_deg_v{v}"], "k", label="joint")
        ax[0, i].set_title(f"({'abcd'[i]}) {v} deg/s")
        ax[0, i].set_xlabel("time [s]")
        ax[1, i].plot(t, col[f"velocity_deg_s_v{v}"], "k")
        ax[1, i].axhline(v + meta["band_deg_s"], color="b", ls="--")
        ax[1, i].axhline(v - meta["band_deg_s"], color="g", ls="--")
        ax[1, i].set_xlabel("time [s]")
    ax[0, 0].set_ylabel("position [deg]")
    ax[1, 0].set_ylabel("velocity [deg/s]")
    ax[0, 0].legend()
    fig.suptitle("Fig. 13: creep / stick-slip under velocity PI, no compensation "
                 f"(kp={meta['gains']['kp']}, ki={meta['gains']['ki']})")
    save_figure(fig, out / "fig13.png")
    m = json.loads((out / "stick_slip_map.json").read_text())
    fig, ax = plt.subplots(figsize=(6, 4.5))
    sw = np.asarray(m["relative_swing"], dtype=float)
    pc = ax.pcolormesh(m["velocities_deg_s"], m["ki"], np.log10(np.maximum(sw, 1e-6)).T, shading="nearest")
    st = np.asarray(m["stick_slip"], dtype=bool)
    V, K = np.meshgrid(m["velocities_deg_s"], m["ki"], indexing="ij")
    ax.plot(V[st], K[st], "w.", label="stick-slip (min velocity < 10% of command)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("velocity command [deg/s]")
    ax.set_ylabel("ki [N*m/deg]")
    ax.set_title(f"velocity swing (log10 of (max-min)/command), kp={m['kp']}")
    fig.colorbar(pc)
    ax.legend(loc="lower right", fontsize=8)
    save_figure(fig, out / "stick_slip_map.png")


if __name__ == "__main__":
    main()
