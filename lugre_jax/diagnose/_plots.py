"""Figures for a diagnose report: residual before/after vs time, velocity and position, and the shape
of each named effect (Li et al., Electronics 2020, 9, 284 joint model; recording units)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..io import save_figure
from . import _model as M
from ._attribute import cancel_words
from ._report import Diagnosis


def _binned(x, r, edges):
    idx = np.digitize(x, edges) - 1
    ok = (idx >= 0) & (idx < len(edges) - 1)
    c, m, s = [], [], []
    for k in range(len(edges) - 1):
        sel = ok & (idx == k)
        if sel.sum() < 5:
            continue
        c.append(0.5 * (edges[k] + edges[k + 1]))
        m.append(r[sel].mean())
        s.append(1.96 * r[sel].std() / np.sqrt(sel.sum()))
    return np.array(c), np.array(m), np.array(s)


def _symlog_velocity_axis(ax, V: float) -> None:
    """Symmetric-log velocity axis whose tick labels do not collide around zero: linear within
    +-1e-3*V, labelled ticks at 0 and at +-V*10^-k (k = 0, 1, 2) only -- one a decade apart, none
    at the edge of the linear region, where the default locator crowds labels onto 0."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator

    lt = V * 1e-3
    ax.set_xscale("symlog", linthresh=lt, linscale=0.5)
    pos = [float(f"{V * 10.0 ** -k:.1g}") for k in (0, 1, 2)]
    ticks = sorted([-p for p in pos] + [0.0] + pos)
    ax.xaxis.set_major_locator(FixedLocator(ticks))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: "0" if x == 0 else f"{x:g}"))
    ax.tick_params(axis="x", labelrotation=30)


def effect_torques(model: M.JointModel, kin) -> dict[str, np.ndarray]:
    """Torque contributed by each candidate of ``model`` (model minus model-without-it)."""
    full = M.predict(model, kin)
    out = {}
    for i, c in enumerate(model.candidates):
        rest = model.candidates[:i] + model.candidates[i + 1:]
        out[c.id] = full - M.predict(M.JointModel(model.J, model.friction, model.offset, rest), kin)
    return out


def plot_report(report: Diagnosis, rec, outdir: str | os.PathLike) -> list[str]:
    """Write the diagnosis figures (PNG) into ``outdir``; returns their paths. ``rec`` is used only
    when ``report.arrays`` lacks the conditioned recording."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    outdir = Path(outdir)
    arr = report.arrays
    if arr is None:
        raise ValueError("plot_report needs the arrays diagnose() keeps in its result (Diagnosis.arrays is None)")
    rec = arr.rec if arr.rec is not None else rec  # the conditioned kinematics the residuals belong to
    r0, r1 = np.asarray(arr.r0), np.asarray(arr.r1)
    t, v, th = rec.time, rec.velocity, rec.position
    u = rec.units
    written = []

    fig, axs = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    te = np.linspace(t[0], t[-1], 101)
    for ax, r, lab in ((axs[0], r0, "baseline"), (axs[1], r1, "after modelling")):
        ax.plot(t, r, lw=0.3, color="0.6")
        c, m, s = _binned(t, r, te)
        ax.errorbar(c, m, s, fmt=".-", color="C3", lw=1, ms=3, label="binned mean, 95% CI")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_ylabel(f"residual [{u['torque']}]")
        ax.set_title(f"{lab}: residual vs time (held-out RMSE "
                     f"{(report.baseline if r is r0 else report.improved).validation_rmse_nm:.4g})")
        ax.legend(loc="upper right", fontsize=8)
    axs[1].set_xlabel(f"time [{u['time']}]")
    save_figure(fig, outdir / "residual_time.png")
    written.append(str(outdir / "residual_time.png"))

    V = np.percentile(np.abs(v), 99.5)
    lin = np.logspace(np.log10(max(V * 1e-3, 1e-12)), np.log10(V), 25)
    ve = np.concatenate([-lin[::-1], lin])
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    for r, lab, col in ((r0, "baseline", "C0"), (r1, "after", "C3")):
        c, m, s = _binned(v, r, ve)
        axs[0].errorbar(c, m, s, fmt="o-", ms=3, color=col, label=lab)
        pe = np.quantile(th, np.linspace(0, 1, 41))
        c, m, s = _binned(th, r, pe)
        axs[1].errorbar(c, m, s, fmt="o-", ms=3, color=col, label=lab)
    _symlog_velocity_axis(axs[0], V)
    axs[0].set_xlabel(f"velocity [{u['velocity']}]")
    axs[1].set_xlabel(f"position [{u['position']}]")
    for ax in axs:
        ax.axhline(0, color="k", lw=0.5)
        ax.set_ylabel(f"mean residual [{u['torque']}] (95% CI)")
        ax.legend(fontsize=8)
    fig.suptitle("Residual binned by velocity and by position, before and after modelling")
    save_figure(fig, outdir / "residual_velocity_position.png")
    written.append(str(outdir / "residual_velocity_position.png"))

    pp = arr.loc0["position_periodogram"]
    tp = arr.loc0["time_periodogram"]
    fig, axs = plt.subplots(1, 2, figsize=(11, 3.5))
    axs[0].semilogx(1 / pp["freqs"], pp["z"], lw=0.7)
    axs[0].set_xlabel(f"period [{u['position']}]")
    axs[0].set_ylabel("normalised power (Exp(1) under H0)")
    axs[0].set_title(f"vs position (family p = {pp['p_value']:.2g})")
    axs[1].semilogx(tp["freqs"], tp["ratio"], lw=0.3)
    axs[1].set_xlabel("frequency [Hz]")
    axs[1].set_ylabel("power / local median")
    axs[1].set_title(f"vs time (family p = {tp['p_value']:.2g})")
    save_figure(fig, outdir / "residual_periodograms.png")
    written.append(str(outdir / "residual_periodograms.png"))

    model = arr.improved_model
    if model.candidates:
        kin = arr.kin
        eff = effect_torques(model, kin)
        for c in model.candidates:
            e = eff[c.id]
            fig, ax = plt.subplots(figsize=(7, 4))
            if c.id in ("position_ripple", "gravity"):
                x, xl = th, f"position [{u['position']}]"
            elif c.id in ("asymmetry", "stribeck_shape"):
                x, xl = v, f"velocity [{u['velocity']}]"
            elif c.id == "load_dependent":
                x, xl = rec.acceleration, f"acceleration [{u['acceleration']}]"
            else:
                x, xl = t, f"time [{u['time']}]"
            o = np.argsort(x)
            ax.plot(x[o], r0[o], ",", color="0.7", label="baseline residual")
            ax.plot(x[o], e[o], ".", ms=1.5, color="C3", label=f"{c.id} torque (fitted)")
            if c.id in ("asymmetry", "stribeck_shape"):
                _symlog_velocity_axis(ax, V)
            lim = 4 * max(np.max(np.abs(e)), 1e-12)
            ax.set_ylim(-lim, lim)
            ax.set_xlabel(xl)
            ax.set_ylabel(f"torque [{u['torque']}]")
            ax.set_title(f"named effect: {c.id}")
            ax.legend(fontsize=8, markerscale=8)
            save_figure(fig, outdir / f"effect_{c.id}.png")
            written.append(str(outdir / f"effect_{c.id}.png"))
    terms = (report.attribution or {}).get("terms", [])
    if terms and arr.attribution is not None and arr.attribution.columns:
        a = arr.attribution
        written.append(_plot_attribution(report, rec, r1 != 0, terms, a.columns, a.fits, a.partials, outdir, plt))
    return written


def _plot_attribution(report, rec, keep, terms, columns, fits, partials, outdir, plt) -> str:
    """Each attributed term's partial residual (the residual left by the selection, less the model's
    linearised refit and the other terms, all fitted jointly) against its signal, binned, with the
    term's fitted torque drawn over it."""
    u = rec.units
    fig, axs = plt.subplots(1, len(terms), figsize=(5.5 * len(terms), 4), squeeze=False)
    for ax, term, X, fit, r in zip(axs[0], terms, columns, fits, partials):
        X, fit, r = (np.asarray(z, float) for z in (X, fit, r))
        coef = np.linalg.lstsq(X, fit, rcond=None)[0]  # the joint fit's coefficients
        if X.shape[1] == 1:
            x, xlabel = X[:, 0], f"{term['columns'][0]} [{_signal_unit(term, u)}]"
        else:  # a time line: against time
            x, xlabel = np.asarray(rec.time, float), f"time [{u['time']}]"
        edges = np.quantile(x[keep], np.linspace(0, 1, 31))
        c, m, sd = _binned(x[keep], r[keep], edges)
        ax.plot(x[keep], r[keep], ",", color="0.75", label="partial residual (samples)")
        ax.errorbar(c, m, sd, fmt="o", ms=3, color="C0", label="binned mean, 95% CI")
        o = np.argsort(x)
        ax.plot(x[o], fit[o], color="C3", lw=1.5,
                label="discovered term (joint fit): " + " + ".join(f"{b:.3g}*{lab}" for b, lab in
                                                                  zip(coef, term["columns"])))
        ax.set_ylim(np.percentile(r[keep], [0.5, 99.5]) * 1.2)
        if X.shape[1] == 1:
            # a derivative's few extreme samples (a reversal's jerk) would squeeze the bins to a line
            lo, hi = np.percentile(x[keep], [0.5, 99.5])
            ax.set_xlim(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
            xlabel += " (central 99 % of samples)"
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"partial residual [{u['torque']}]")
        ax.set_title(f"{term['signal']}: {term['reading'].split(':')[0]}", fontsize=9)
        ax.legend(fontsize=7, loc="upper left")
    a = report.attribution
    title = (f"attribution: cross-validated RMSE {a.get('cv_rmse_before_nm', float('nan')):.4g} -> "
             f"{a.get('cv_rmse_after_nm', float('nan')):.4g} {u['torque']} (fixed held-out phase "
             f"{a['validation_rmse_before_nm']:.4g} -> {a['validation_rmse_after_nm']:.4g})")
    if a.get("terms_nearly_cancel"):
        title += "\n" + cancel_words([t["fit_rms_nm"] for t in terms], a["terms_sum_rms_nm"], u["torque"])
    fig.suptitle(title, fontsize=10)
    fig.subplots_adjust(top=0.80 if "\n" in title else 0.87)
    path = Path(outdir) / "attribution.png"
    save_figure(fig, path)
    return str(path)


def _signal_unit(term, u) -> str:
    """The signal's unit: the torque unit over the coefficient's."""
    coef_unit = term["units"][0]
    return {"torque_rate": f"{u['torque']}/{u['time']}", "velocity_squared": f"{u['position']}^2/{u['time']}^2",
            "transmitted_torque": u["torque"], "jerk": f"{u['position']}/{u['time']}^3",
            "time": u["time"], "position": u["position"]}.get(term["signal"], f"{u['torque']}/({coef_unit})")
