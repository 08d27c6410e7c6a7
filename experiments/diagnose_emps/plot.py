"""Figures of the EMPS diagnose study, from ``<results>/series_*.csv`` and ``summary.json``.

``residuals_<baseline>.png``: force residual vs time, velocity and position before/after modelling;
``effects_<baseline>.png``: the named effects' force vs their natural variable;
``errors.png``: relative force errors beside the published 4.08 % / 3.11 %.

    python experiments/diagnose_emps/plot.py [--results experiments/diagnose_emps/results]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402


def binned(x, r, nb=30):
    e = np.quantile(x, np.linspace(0, 1, nb + 1))
    idx = np.clip(np.digitize(x, e) - 1, 0, nb - 1)
    c = np.array([x[idx == k].mean() for k in range(nb)])
    m = np.array([r[idx == k].mean() for k in range(nb)])
    s = np.array([1.96 * r[idx == k].std() / np.sqrt(max((idx == k).sum(), 1)) for k in range(nb)])
    return c, m, s


def main(argv=None):
    res = results_for_plot(__doc__, Path(__file__).with_name("results"), ("summary.json",), argv)
    import matplotlib.pyplot as plt

    from lugre_jax.io import save_figure

    summary = json.loads((res / "summary.json").read_text())
    for p in sorted(res.glob("series_*.csv")):
        name = p.stem.replace("series_", "")
        d = np.genfromtxt(p, delimiter=",", names=True)
        y = d["force_N"]
        r0, r1 = y - d["pred_baseline_N"], y - d["pred_improved_N"]
        fig, axs = plt.subplots(2, 2, figsize=(12, 7))
        axs[0, 0].plot(d["time_s"], r0, lw=0.5, label="baseline")
        axs[0, 0].plot(d["time_s"], r1, lw=0.5, label="after modelling")
        axs[0, 0].set_xlabel("time [s]")
        axs[0, 0].set_ylabel("force residual [N]")
        axs[0, 0].legend(fontsize=8)
        axs[0, 1].plot(d["time_s"], y, lw=0.6, color="k", label="measured force")
        axs[0, 1].plot(d["time_s"], d["pred_improved_N"], lw=0.6, color="C3", label="model after")
        axs[0, 1].set_xlabel("time [s]")
        axs[0, 1].set_ylabel("force [N]")
        axs[0, 1].legend(fontsize=8)
        for ax, x, xl in ((axs[1, 0], d["velocity_m_s"], "velocity [m/s]"),
                          (axs[1, 1], d["position_m"], "position [m]")):
            for r, lab, col in ((r0, "baseline", "C0"), (r1, "after", "C3")):
                c, m, s = binned(x, r)
                ax.errorbar(c, m, s, fmt="o-", ms=3, color=col, label=lab)
            ax.axhline(0, color="k", lw=0.5)
            ax.set_xlabel(xl)
            ax.set_ylabel("mean residual [N] (95% CI, iid)")
            ax.legend(fontsize=8)
        row = next(r for r in summary["diagnose"] if r["baseline"] == name)
        fig.suptitle(f"EMPS, baseline '{name}': named {row['named']}; relative error (fit on all) "
                     f"{row['baseline_rel_err_fit_all_pct']:.2f}% -> {row['improved_rel_err_fit_all_pct']:.2f}%")
        save_figure(fig, res / f"residuals_{name}.png")

        effs = [n for n in d.dtype.names if n.startswith("effect_")]
        if effs:
            fig, axs = plt.subplots(1, len(effs), figsize=(5 * len(effs), 3.8), squeeze=False)
            for ax, n in zip(axs[0], effs):
                eid = n[len("effect_"):-2]
                x, xl = ((d["position_m"], "position [m]") if eid in ("position_ripple", "gravity")
                         else (d["velocity_m_s"], "velocity [m/s]") if eid in ("asymmetry", "stribeck_shape")
                         else (d["time_s"], "time [s]"))
                o = np.argsort(x)
                ax.plot(x[o], r0[o], ",", color="0.6", label="baseline residual")
                ax.plot(x[o], d[n][o], ".", ms=2, color="C3", label=f"{eid} (fitted)")
                lim = 4 * max(np.abs(d[n]).max(), 1e-9)
                ax.set_ylim(-lim, lim)
                ax.set_xlabel(xl)
                ax.set_ylabel("force [N]")
                ax.set_title(eid)
                ax.legend(fontsize=7, markerscale=6)
            save_figure(fig, res / f"effects_{name}.png")

    rows = summary["diagnose"]
    fig, ax = plt.subplots(figsize=(8, 4))
    labels, base, imp = [r["baseline"] for r in rows], [r["baseline_rel_err_fit_all_pct"] for r in rows], \
        [r["improved_rel_err_fit_all_pct"] for r in rows]
    x = np.arange(len(rows))
    ax.bar(x - 0.2, base, 0.4, label="baseline (fit on all)")
    ax.bar(x + 0.2, imp, 0.4, label="after modelling (fit on all)")
    ax.axhline(4.08, color="k", ls="--", lw=1, label="published IDIM-LS 4.08 %")
    ax.axhline(3.11, color="k", ls=":", lw=1, label="published asymmetric 3.11 %")
    rep = summary["idim_ls_reproduction"]
    ax.axhline(rep["symmetric"]["rel_err_pct"], color="C2", ls="--", lw=1,
               label=f"our IDIM-LS reproduction {rep['symmetric']['rel_err_pct']:.2f} %")
    ax.set_xticks(x, labels)
    ax.set_ylabel("relative force error [%]")
    ax.legend(fontsize=7)
    save_figure(fig, res / "errors.png")


if __name__ == "__main__":
    main()
