"""PNG figures of the reproduced experiments (Li et al., Electronics 2020, 9, 284, Figs. 8-15), drawn
from the scenario dicts of :mod:`lugre_jax.reproduce._scenarios`. Units: s, deg, deg/s."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io import save_figure
from ._scenarios import BAND, RAMP_WINDOWS


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _step_axes(ax, traces: dict, v: float, title: str, band: bool = True):
    t = next(iter(traces.values()))["t"]
    # Reference lines in black/grey, outside the colour cycle the traces use: with four or more
    # traces the cycle reaches red, which a red "ideal" line would share (Fig. 10c).
    ax.plot(t, v * t, "k-", lw=1.5, label=f"ideal {v:g} deg/s")
    if band:
        ax.plot(t, (v + BAND) * t, ":", color="0.45", lw=1, label=f"+{BAND:g} deg/s bound")
        ax.plot(t, max(v - BAND, 0.0) * t, "-.", color="0.45", lw=1, label=f"-{BAND:g} deg/s bound")
    for i, (k, tr) in enumerate(traces.items()):
        ax.plot(tr["t"], tr["theta"], lw=1.2, color=f"C{i % 10}", label=k)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("angle [deg]")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def _sine_axes(ax_pos, ax_err, tr: dict, label: str):
    ax_pos.plot(tr["t"], tr["theta_ref"], "r-", lw=1.5, label="input 3 sin(0.8 pi t)")
    ax_pos.plot(tr["t"], tr["theta"], "b--", lw=1.2, label=f"output ({label})")
    ax_pos.set_xlabel("t [s]")
    ax_pos.set_ylabel("angle [deg]")
    ax_pos.legend(fontsize=7)
    ax_pos.grid(alpha=0.3)
    ax_err.plot(tr["t"], tr["theta_ref"] - tr["theta"], "k-", lw=1)
    ax_err.set_xlabel("t [s]")
    ax_err.set_ylabel("position error [deg]")
    ax_err.set_title(f"error ({label})", fontsize=10)
    ax_err.grid(alpha=0.3)


def plot_fig08(res: dict, path: Path):
    plt = _plt()
    open_loop = {k: v for k, v in res["traces"].items() if k.startswith("open loop")}
    closed = {k: v for k, v in res["traces"].items() if k not in open_loop}
    fig, axs = plt.subplots(1, 2 if open_loop else 1, figsize=(13 if open_loop else 7, 4.5), squeeze=False)
    _step_axes(axs[0, 0], closed, res["settings"]["v_deg_s"], "Fig. 8: 0.005 deg/s, no compensation")
    if open_loop:
        # Its own axes: the open-loop joint runs away to hundreds of deg/s (log scale of the velocity).
        ax = axs[0, 1]
        for k, tr in open_loop.items():
            ax.semilogy(tr["t"], np.maximum(np.abs(tr["omega"]), 1e-6), label=k)
        ax.axhline(res["settings"]["v_deg_s"], color="r", lw=1, label="command 0.005 deg/s")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("|velocity| [deg/s]")
        ax.set_title("Fig. 8 read as open loop: runaway", fontsize=10)
        ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path)


def _sine_and_step(res: dict, path: Path, label: str, sine_title: str, step_title: str, band: bool = True):
    """Figs. 9 and 10: the sine run of ``label`` (tracking, error) beside the 0.005 deg/s steps."""
    plt = _plt()
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.2))
    _sine_axes(axs[0], axs[1], res["traces"]["sine"][label], label)
    axs[0].set_title(sine_title, fontsize=10)
    _step_axes(axs[2], res["traces"]["step"], res["settings"]["v_deg_s"], step_title, band=band)
    fig.tight_layout()
    save_figure(fig, path)


def plot_fig09(res: dict, path: Path):
    _sine_and_step(res, path, "PID", "Fig. 9a: PID sine tracking", "Fig. 9c: velocity PI, 0.005 deg/s")


def plot_fig10(res: dict, path: Path):
    _sine_and_step(res, path, "GA-PSO piecewise", "Fig. 10a: compensated sine tracking",
                   "Fig. 10c: compensated 0.005 deg/s step", band=False)


def plot_fig12(res: dict, path: Path):
    plt = _plt()
    labels = [k for k in res["traces"] if "PID" not in k and "sigma1 = 0" not in k]
    fig, axs = plt.subplots(2, len(labels), figsize=(6 * len(labels), 7), squeeze=False)
    for j, k in enumerate(labels):
        tr = res["traces"][k]
        ax = axs[0, j]
        ax.plot(tr["t"], tr["theta_ref"], "b-", lw=1.5, label="theoretical")
        ax.plot(tr["t"], tr["theta"], "r--", lw=1.2, label="actual")
        ax.set_title(f"Fig. 12: {k}", fontsize=10)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("angle [deg]")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        ax = axs[1, j]
        ax.plot(tr["v_ref"], tr["omega"] - tr["v_ref"], "k-", lw=1, label="velocity error")
        for i, (name, (lo, hi)) in enumerate(RAMP_WINDOWS.items()):
            ax.axvspan(lo, hi, color="orange", alpha=0.2,
                       label=f"scored windows ({', '.join(RAMP_WINDOWS)})" if i == 0 else None)
        ax.legend(fontsize=7)
        ax.set_xscale("log")
        ax.set_xlabel("commanded velocity [deg/s] (log)")
        ax.set_ylabel("velocity error [deg/s]")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path)


def plot_fig13(res: dict, path: Path):
    plt = _plt()
    fig, axs = plt.subplots(2, 2, figsize=(11, 8))
    for ax, (k, tr), v in zip(axs.ravel(), res["traces"].items(), res["settings"]["velocities"]):
        _step_axes(ax, {"actual (velocity PI)": tr}, v, f"Fig. 13: {k}")
    fig.tight_layout()
    save_figure(fig, path)


def plot_fig14(res: dict, path: Path):
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.2))
    for ax, (k, tr) in zip(axs, res["traces"].items()):
        _step_axes(ax, {k: tr}, res["settings"]["v_deg_s"], f"Fig. 14: {k}")
    fig.tight_layout()
    save_figure(fig, path)


def plot_fig15(res: dict, path: Path):
    plt = _plt()
    fig, axs = plt.subplots(2, 2, figsize=(11, 7))
    for row, (k, tr) in enumerate(res["traces"].items()):
        _sine_axes(axs[row, 0], axs[row, 1], tr, k)
        axs[row, 0].set_title(f"Fig. 15: {k} (friction drifted x{res['settings']['friction_drift']})", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def plot_beyond(res: dict, path: Path):
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(12, 4.2))
    v = res["settings"]["v_deg_s"]
    _step_axes(axs[0], res["traces"], v, f"Beyond the paper: {v:g} deg/s", band=True)
    for k, tr in res["traces"].items():
        axs[1].plot(tr["t"], tr["omega"], lw=1, label=k)
    axs[1].axhspan(v - BAND, v + BAND, color="grey", alpha=0.15, label="+-0.001 deg/s band")
    axs[1].axhspan(0.9 * v, 1.1 * v, color="green", alpha=0.15, label="+-10% band")
    axs[1].set_xlabel("t [s]")
    axs[1].set_ylabel("velocity [deg/s]")
    axs[1].legend(fontsize=7)
    axs[1].grid(alpha=0.3)
    fig.tight_layout()
    save_figure(fig, path)


PLOTTERS = {"fig08": plot_fig08, "fig09": plot_fig09, "fig10": plot_fig10, "fig12": plot_fig12, "fig13": plot_fig13,
            "fig14": plot_fig14, "fig15": plot_fig15, "beyond": plot_beyond}


SEP = "::"


def save_traces_npz(res: dict, path: Path) -> None:
    """Raw traces of a scenario as a compressed .npz (key ``<group>::<label>::<signal>``; labels may hold '/')."""
    from ..io import atomic_path

    flat = {}

    def walk(prefix, d):
        for k, v in d.items():
            if isinstance(v, dict):
                walk(f"{prefix}{k}{SEP}", v)
            elif isinstance(v, np.ndarray):
                flat[f"{prefix}{k}"] = v
    walk("", res["traces"])
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            np.savez_compressed(fh, **flat)


def load_traces_npz(path: Path) -> dict:
    """Inverse of :func:`save_traces_npz`."""
    out: dict = {}
    with np.load(path) as z:
        for key in z.files:
            parts = key.split(SEP)
            d = out
            for p in parts[:-1]:
                d = d.setdefault(p, {})
            d[parts[-1]] = z[key]
    return out


def plot_creep(res: dict, path: Path):
    """Creep search: dead zone and creep amplitude over the velocity-PI gain grid."""
    plt = _plt()
    g = res["metrics"]["grid"]
    kps, kis = sorted({r["kp"] for r in g}), sorted({r["ki"] for r in g})
    fig, axs = plt.subplots(1, 3, figsize=(15, 4))
    for ax, key, title in zip(axs, ("max_velocity_over_command", "dead_zone_s", "creep_amplitude_deg"),
                              ("max velocity / command", "dead zone [s] (log10)", "creep amplitude [deg] (log10)")):
        Z = np.full((len(kps), len(kis)), np.nan)
        for r in g:
            val = r[key]
            Z[kps.index(r["kp"]), kis.index(r["ki"])] = val if key.startswith("max") else np.log10(max(abs(val), 1e-12))
        im = ax.imshow(Z, origin="lower", aspect="auto")
        ax.set_xticks(range(len(kis)), [f"{k:g}" for k in kis])
        ax.set_yticks(range(len(kps)), [f"{k:g}" for k in kps])
        ax.set_xlabel("ki [N*m/deg]")
        ax.set_ylabel("kp [N*m*s/deg]")
        ax.set_title(f"{title}, {res['settings']['v_deg_s']:g} deg/s", fontsize=10)
        fig.colorbar(im, ax=ax)
    fig.tight_layout()
    save_figure(fig, path)


PLOTTERS["creep"] = plot_creep


def plot_design(d: dict, path: Path) -> None:
    plt = _plt()
    g = d["grid"]
    amps, freqs = np.unique(g["amplitude_nm"]), np.unique(g["frequency_hz"])
    fig, axs = plt.subplots(1, 3, figsize=(15, 4))
    for ax, key, title in zip(axs, ("logdet", "relative_se_sigma0", "relative_se_sigma1"),
                              ("log det Fisher (D-optimality)", "relative SE sigma0", "relative SE sigma1")):
        Z = np.full((amps.size, freqs.size), np.nan)
        for a, f, z in zip(g["amplitude_nm"], g["frequency_hz"], g[key]):
            Z[np.searchsorted(amps, a), np.searchsorted(freqs, f)] = z if key == "logdet" else np.log10(max(z, 1e-12))
        im = ax.imshow(Z, origin="lower", aspect="auto", cmap="viridis" if key == "logdet" else "magma_r")
        ax.set_xticks(range(freqs.size), [f"{f:g}" for f in freqs])
        ax.set_yticks(range(amps.size), [f"{a:g}" for a in amps])
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("torque amplitude [N*m]")
        ax.set_title(title + ("" if key == "logdet" else " (log10)"), fontsize=10)
        fig.colorbar(im, ax=ax)
    fig.tight_layout()
    save_figure(fig, path)


def plot_table2(t: dict, path: Path) -> None:
    """Table 2 bars: paper, eq. 17/18 route and time-series fit (+-1 SE), sigma0 and sigma1 per segment."""
    def norm(d):  # segment keys are ints in memory, strings after a JSON round trip
        return None if d is None else {str(k): v for k, v in d.items()}

    t = dict(t, paper=norm(t["paper"]), route1_paper_method=norm(t["route1_paper_method"]),
             route2_time_series=norm(t.get("route2_time_series")))
    plt = _plt()
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    ks = ["1", "2", "3"]
    for ax, par in zip(axs, ("sigma0", "sigma1")):
        x = np.arange(3)
        ax.bar(x - 0.27, [t["paper"][k][par] for k in ks], 0.27, label="paper Table 2")
        ax.bar(x, [t["route1_paper_method"][k][par] for k in ks], 0.27, label="eq. 17 step + eq. 18")
        r2 = t.get("route2_time_series")
        if r2:
            ax.bar(x + 0.27, [r2[k][par] for k in ks], 0.27, yerr=[r2[k][par + "_se"] for k in ks], capsize=3,
                   label="time-series LM +- SE")
        ax.set_xticks(x, [f"segment {k}" for k in ks])
        ax.set_ylabel(par + (" [N*m/deg]" if par == "sigma0" else " [N*m*s/deg]"))
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    save_figure(fig, path)
