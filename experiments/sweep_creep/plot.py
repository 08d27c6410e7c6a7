"""Figures of experiments/sweep_creep/run.py: Sobol' tornado plots of the 0.005 deg/s dead zone and
creep amplitude (with the band fraction and stick-slip flag), and the minimum-stable-velocity map.

    python experiments/sweep_creep/plot.py [--out DIR]

Writes OUT/sweep_creep_sobol.png and OUT/sweep_creep_msv.png.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
LABELS = {"friction.Fc": "Fc", "friction.Fs": "Fs", "friction.vs": "vs", "friction.sigma0": "σ0",
          "friction.sigma1": "σ1", "friction.sigma2": "σ2", "controller.kp": "kp", "controller.ki": "ki"}
TITLES = {"dead_zone": "dead zone [s]", "creep_amplitude": "creep amplitude [deg]",
          "band_fraction": "fraction in ±0.001 deg/s", "stick_slip": "stick-slip flag"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", "--results", dest="out", default=str(HERE / "results"))
    a = ap.parse_args(argv)
    out = Path(a.out)
    if not (out / "sobol" / "indices.json").exists() or not (out / "msv.json").exists():
        print(f"no results in {out}: run python experiments/sweep_creep/run.py first", file=sys.stderr)
        return 1
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    from lugre_jax.io import save_figure

    idx = json.loads((out / "sobol" / "indices.json").read_text())["outputs"]
    fig, axes = plt.subplots(1, len(idx), figsize=(4.2 * len(idx), 4.4), sharey=True, constrained_layout=True)
    for ax, (name, r) in zip(np.atleast_1d(axes), idx.items()):
        names = [LABELS.get(n, n) for n in r["names"]]
        y = np.arange(len(names))
        ax.barh(y + 0.2, r["ST"], 0.4, xerr=r["ST_conf"], color="tab:red", label="ST", capsize=2)
        ax.barh(y - 0.2, r["S1"], 0.4, xerr=r["S1_conf"], color="tab:blue", label="S1", capsize=2)
        ax.set_yticks(y, names)
        ax.axvline(0, color="k", lw=0.5)
        ax.set_title(f"{TITLES.get(name, name)}\nN={r['n_groups']}, dropped {r['n_dropped']}", fontsize=10)
        ax.set_xlabel("Sobol' index (95 % CI)")
    np.atleast_1d(axes)[0].legend(loc="lower right")
    fig.suptitle("0.005 deg/s step, velocity PI: sensitivity to LuGre parameters and gains")
    save_figure(fig, out / "sweep_creep_sobol.png")

    m = json.loads((out / "msv.json").read_text())
    msv = np.array(m["min_stable_velocity_deg_s"], dtype=float)  # (sigma0, Fs-Fc, ki)
    msv = np.where(np.isfinite(msv), msv, np.nan)
    s0, dF, ki = (np.asarray(m[k]) for k in ("sigma0", "Fs_minus_Fc", "ki"))
    low = np.array(m["lowest_stick_slip_velocity_deg_s"], dtype=float)
    fig, axes = plt.subplots(2, len(ki), figsize=(3.4 * len(ki) + 1, 6.4), sharex=True, sharey=True,
                             constrained_layout=True, squeeze=False)
    v = m["velocities_deg_s"]
    norm = LogNorm(vmin=min(v), vmax=max(v))
    for row, (data, what) in enumerate(((msv, "minimum stable velocity"), (low, "lowest stick-slip velocity"))):
        for k in range(len(ki)):
            ax = axes[row, k]
            pc = ax.pcolormesh(dF, s0, data[:, :, k], norm=norm, shading="nearest", cmap="viridis")
            ax.set_title(f"{what}\nki = {ki[k]:.0f} N·m/deg", fontsize=9)
            if row == 1:
                ax.set_xlabel("Fs − Fc [N·m]")
        axes[row, 0].set_ylabel("σ0 [N·m/deg]")
        fig.colorbar(pc, ax=axes[row, :], label="[deg/s]" + (" (blank: > 1; 0.001: stable on the whole ladder)" if row == 0 else " (blank: none)"))
    save_figure(fig, out / "sweep_creep_msv.png")
    print(f"wrote {out / 'sweep_creep_sobol.png'} and {out / 'sweep_creep_msv.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
