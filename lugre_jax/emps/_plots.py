"""Figures of an EMPS study: measured vs simulated position and force, and residuals against time,
velocity and position (closed loop), and the benchmark protocol's free simulation."""

from __future__ import annotations

from pathlib import Path


def plot_report(report, out: Path, run_name: str, closed_key: str | None = None) -> list[Path]:
    """``run_name``: the run of the protocol panel; ``closed_key``: the closed-loop score shown
    (default ``run_name``; on a validation run with pulses, the one with the pulses as estimated)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..io import save_figure

    c = report.models[report.best_closed_loop].closed_loop[closed_key or run_name]
    b = report.models[report.best_benchmark].benchmark[run_name]
    paths = []

    fig, ax = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    ax[0].plot(c.t, 1e3 * c.q, "k", lw=1, label="measured (filtered)")
    ax[0].plot(c.t, 1e3 * c.q_sim, "r--", lw=1, label=f"closed loop, {report.best_closed_loop}")
    ax[0].set_ylabel("position [mm]")
    ax[0].legend(loc="best")
    ax[1].plot(c.t, c.force, "k", lw=0.6, label="measured gtau*vir")
    ax[1].plot(c.t, c.force_sim, "r", lw=0.6, alpha=0.8, label="simulated")
    ax[1].set_ylabel("motor force [N]")
    ax[1].legend(loc="best")
    ax[2].plot(b.t, 1e3 * b.y, "k", lw=1, label="measured qm")
    ax[2].plot(b.t, 1e3 * b.y_sim, "b--", lw=1,
               label=f"benchmark protocol (vir alone), {report.best_benchmark}: RMSE {b.rmse_mm:.2f} mm")
    ax[2].set_ylabel("position [mm]")
    ax[2].set_xlabel("time [s]")
    ax[2].legend(loc="best")
    fig.suptitle(f"EMPS {closed_key or run_name}: closed-loop force error {c.force_pct:.2f} %")
    paths.append(out / "measured_vs_simulated.png")
    save_figure(fig, paths[-1])

    fig, ax = plt.subplots(2, 3, figsize=(13, 6.5), sharey="row")
    ef = c.force - c.force_sim
    eq = 1e6 * (c.q - c.q_sim)
    for j, (x, lab) in enumerate(((c.t, "time [s]"), (c.v, "velocity [m/s]"), (1e3 * c.q, "position [mm]"))):
        ax[0, j].plot(x, ef, ".", ms=1, alpha=0.4)
        ax[1, j].plot(x, eq, ".", ms=1, alpha=0.4)
        ax[1, j].set_xlabel(lab)
    ax[0, 0].set_ylabel("force residual [N]")
    ax[1, 0].set_ylabel("position residual [um]")
    fig.suptitle(f"EMPS {closed_key or run_name}, closed loop, {report.best_closed_loop}: residuals (measured - simulated)")
    paths.append(out / "residuals.png")
    save_figure(fig, paths[-1])
    return paths
