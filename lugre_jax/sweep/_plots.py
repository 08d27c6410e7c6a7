"""Figures of a sweep: tornado plots of Sobol' indices, heatmaps of grid sweeps."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io import save_figure
from ._metrics import BandFraction, CreepAmplitude, DeadZone, StickSlip, TrackingError

# Units of the metrics (their docstrings, lugre_jax/sweep/_metrics.py), for axis and colour-bar labels.
_METRIC_UNITS = {DeadZone: "s", CreepAmplitude: "deg", BandFraction: "fraction of samples", TrackingError: "deg",
                 StickSlip: "0 = none, 1 = stick-slip"}


def _label(name: str, unit: str | None) -> str:
    return f"{name} [{unit}]" if unit else name


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def tornado_plot(idx, title: str, ax) -> None:
    """Horizontal bars of S1 and ST with their intervals, largest ST on top."""
    order = np.argsort(idx.ST)
    ypos = np.arange(len(order))
    ax.barh(ypos + 0.2, idx.ST[order], 0.4, xerr=idx.ST_conf[order], label="ST (total)", color="tab:red", capsize=3)
    ax.barh(ypos - 0.2, idx.S1[order], 0.4, xerr=idx.S1_conf[order], label="S1 (first order)", color="tab:blue", capsize=3)
    ax.set_yticks(ypos, [idx.names[i] for i in order])
    ax.axvline(0, color="k", lw=0.5)
    ax.set_xlabel(f"Sobol' index ({idx.conf_level:.0%} bootstrap interval)")
    ax.set_title(f"{title}  (N={idx.n_groups}, dropped {idx.n_dropped})")
    ax.legend(loc="lower right")


def tornado_plots(indices: dict, out: Path) -> None:
    plt = _plt()
    for name, idx in indices.items():
        fig, ax = plt.subplots(figsize=(6.5, 0.5 * len(idx.names) + 1.5))
        tornado_plot(idx, name, ax)
        save_figure(fig, Path(out) / f"tornado_{name}.png")


def grid_heatmaps(spec, X, Y, status, out: Path) -> None:
    """Per output: the first two names as axes, the mean over the other names' levels (failed
    points left out; a cell with none is blank)."""
    plt = _plt()
    D = len(spec.names)
    if D < 2:
        return
    levels = [len(np.unique(X[:, j])) for j in range(D)]
    shape = tuple(levels)
    ok = status != 2
    for k, name in enumerate(spec.output_names):
        y = np.where(ok, Y[:, k], np.nan).reshape(shape)
        cnt = np.sum(np.isfinite(y), axis=tuple(range(2, D)))
        m = np.where(cnt > 0, np.nansum(y, axis=tuple(range(2, D))) / np.maximum(cnt, 1), np.nan)
        ax0, ax1 = np.unique(X[:, 0]), np.unique(X[:, 1])
        fig, ax = plt.subplots(figsize=(6, 4.5))
        pc = ax.pcolormesh(ax1, ax0, m, shading="nearest")
        unit = _METRIC_UNITS.get(type(spec.outputs[k]))
        fig.colorbar(pc, ax=ax, label=_label(name, unit) + (" (mean over other names)" if D > 2 else ""))
        ax.set_xlabel(_label(spec.names[1], spec.paths[1].unit))
        ax.set_ylabel(_label(spec.names[0], spec.paths[0].unit))
        save_figure(fig, Path(out) / f"heatmap_{name}.png")
