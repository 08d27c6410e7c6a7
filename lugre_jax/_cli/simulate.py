"""``lugre-jax simulate SCENARIO.json --out TRAJ.csv [--plot TRAJ.png]``."""

from __future__ import annotations

import argparse

import numpy as np


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help="simulate one scenario (JSON) and write its trajectory (CSV)",
                       description="Simulate the joint of a scenario file. Units: deg, deg/s, N*m, s.")
    p.add_argument("scenario", help="scenario JSON (see lugre_jax/io/_scenario.py for the schema)")
    p.add_argument("--out", required=True, help="trajectory CSV to write")
    p.add_argument("--plot", help="optional PNG figure of the trajectory")


def run(args) -> int:
    from .. import simulate
    from ..io import load_scenario, write_csv

    system, opts = load_scenario(args.scenario)
    sol = simulate(system, opts["duration_s"], opts["sample_hz"], stepping=opts.get("stepping"))
    if int(sol.result) != 0:
        raise ValueError(
            f"{args.scenario}: the solver failed (result code {int(sol.result)}: "
            + ("state blew up; try a smaller solver.dt or solver.method \"adaptive\")" if int(sol.result) == 1
               else "adaptive solver gave up; raise solver.max_steps or loosen rtol/atol)")
        )
    cols = {
        "time_s": sol.ts, "position_deg": sol.theta, "velocity_deg_s": sol.omega,
        "torque_nm": sol.torque_nm, "z_deg": sol.z, "position_ref_deg": sol.theta_ref,
        "velocity_ref_deg_s": sol.v_ref,
    }
    if args.plot:
        _plot(cols, args.plot)
    write_csv(args.out, {k: np.asarray(v) for k, v in cols.items()})
    return 0


def _plot(cols, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..io import save_figure

    t = np.asarray(cols["time_s"])
    fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ax[0].plot(t, cols["position_ref_deg"], "r--", label="reference")
    ax[0].plot(t, cols["position_deg"], "k", label="joint")
    ax[0].set_ylabel("position [deg]")
    ax[0].legend()
    ax[1].plot(t, cols["velocity_ref_deg_s"], "r--")
    ax[1].plot(t, cols["velocity_deg_s"], "k")
    ax[1].set_ylabel("velocity [deg/s]")
    ax[2].plot(t, cols["torque_nm"], "b")
    ax[2].set_ylabel("torque [N*m]")
    ax[2].set_xlabel("time [s]")
    save_figure(fig, path)
