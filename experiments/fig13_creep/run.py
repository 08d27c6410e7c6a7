"""Fig. 13: creep and stick-slip of the joint under velocity PI (no compensation) at 0.1, 0.01,
0.005 and 0.001 deg/s, the paper's friction (Tables 1-2) and J = 0.128 (eq. 18).

All four commands are one batched simulator call. Writes results/fig13.csv (time series, one column
group per velocity) and results/fig13.json (per-velocity summary). Units: deg, deg/s, N*m, s.

    python experiments/fig13_creep/run.py [--out DIR] [--duration 120] [--kp 8] [--ki 60]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import lugre_jax as lj
from lugre_jax.io import write_csv, write_json
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

VELOCITIES = (0.1, 0.01, 0.005, 0.001)  # deg/s, Fig. 13 a-d
BAND = 0.001  # deg/s: the +-0.001 deg/s velocity band of Fig. 13


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(Path(__file__).parent / "results"))
    ap.add_argument("--duration", type=float, default=120.0, help="seconds simulated per velocity")
    ap.add_argument("--kp", type=float, default=8.0, help="velocity P gain [N*m*s/deg]")
    ap.add_argument("--ki", type=float, default=60.0, help="velocity I gain [N*m/deg]")
    ap.add_argument("--hz", type=float, default=20.0, help="output sample rate [Hz]")
    a = ap.parse_args(argv)
    systems = [lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=lj.PAPER_J),
                         controller=lj.VelocityPID(kp=a.kp, ki=a.ki), reference=lj.VelocitySteps([v]))
               for v in VELOCITIES]
    sol = lj.simulate(lj.stack_systems(systems), a.duration, a.hz, batched=True, stepping=lj.FixedStep())
    if not bool(np.all(np.asarray(sol.result) == lj.RESULT_OK)):
        raise SystemExit(f"simulation failed: result codes {np.asarray(sol.result)}")
    ts = np.asarray(sol.ts)
    cols = {"time_s": ts}
    summary = []
    for i, v in enumerate(VELOCITIES):
        th, om, ref = (np.asarray(x[i]) for x in (sol.theta, sol.omega, sol.theta_ref))
        cols[f"position_deg_v{v}"] = th
        cols[f"velocity_deg_s_v{v}"] = om
        cols[f"position_ref_deg_v{v}"] = ref
        late = ts >= ts[-1] / 2  # second half: past the start-up transient
        summary.append(dict(
            velocity_cmd_deg_s=v,
            max_position_lag_deg=float(np.max(ref - th)),
            velocity_peak_deg_s=float(np.max(om)),
            velocity_min_deg_s_second_half=float(np.min(om[late])),
            fraction_in_band_second_half=float(np.mean(np.abs(om[late] - v) <= BAND)),
            sticks=bool(np.min(om[late]) < 0.1 * v),
        ))
    out = Path(a.out)
    stick_map = stick_slip_map(a.kp, a.duration)
    write_json(out / "stick_slip_map.json", stick_map)
    write_csv(out / "fig13.csv", cols)
    write_json(out / "fig13.json", dict(gains=dict(kp=a.kp, ki=a.ki), band_deg_s=BAND,
                                        duration_s=a.duration, summary=summary))
    for s in summary:
        print(f"{s['velocity_cmd_deg_s']:>6} deg/s: max lag {s['max_position_lag_deg']:.4f} deg, "
              f"peak {s['velocity_peak_deg_s']:.4f} deg/s, in band {100 * s['fraction_in_band_second_half']:.0f}%")


def stick_slip_map(kp, duration, n=15):
    """Where does the paper's joint stick and slip? One batched call over (command, ki).

    Metric: relative velocity swing in the second half, (max - min)/v_cmd; stick-slip when the joint
    also nearly stops (min < 10% of the command).
    """
    vs = np.logspace(-3, -1, n)
    kis = np.logspace(0, 3, n)
    V, K = np.meshgrid(vs, kis, indexing="ij")
    base = lj.System(friction=lj.paper_friction(), joint=lj.Joint(J=lj.PAPER_J),
                     controller=lj.VelocityPID(kp=kp, ki=1.0), reference=lj.VelocitySteps([0.01]))
    import equinox as eqx
    import jax.numpy as jnp

    batch = lj.broadcast_system(base, V.size)
    batch = eqx.tree_at(lambda s: (s.controller.ki, s.reference.levels), batch,
                        (jnp.asarray(K.ravel()), jnp.asarray(V.ravel())[:, None]))

    def reduce(sol):
        late = sol.ts >= sol.ts[-1] / 2
        om = jnp.where(late, sol.omega, jnp.nan)
        return jnp.nanmax(om), jnp.nanmin(om), sol.result

    hi, lo, res = (np.asarray(x) for x in lj.simulate(batch, duration, 10.0, batched=True, stepping=lj.FixedStep(),
                                                              saveat=lj.SaveAt(reduce=reduce)))
    v = V.ravel()
    swing = (hi - lo) / v
    sticks = (lo < 0.1 * v) & (res == 0)
    return dict(kp=kp, duration_s=duration, velocities_deg_s=vs, ki=kis,
                relative_swing=swing.reshape(V.shape), stick_slip=sticks.reshape(V.shape),
                result=res.reshape(V.shape))


if __name__ == "__main__":
    main()
