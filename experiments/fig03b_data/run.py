"""Fig. 3b of Li et al. 2020: steady-state friction torque against velocity (synthetic stand-in).

Writes the per-set-point averages, the samples, the generating Table 1 model and the detected
boundaries to --out (default experiments/fig03b_data/results/).

    python experiments/fig03b_data/run.py [--data data/stribeck_paper_like.csv]
"""

import argparse
from pathlib import Path

import jax.numpy as jnp
import numpy as np

from lugre_jax.identify import decel_branch, detect_boundaries, minimum_torque_velocity, table1_static_model
from lugre_jax.io import load_stribeck_csv, write_csv, write_json
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=str(ROOT / "data" / "stribeck_paper_like.csv"))
    ap.add_argument("--out", default=str(Path(__file__).with_name("results")))
    a = ap.parse_args()
    out = Path(a.out)
    d = load_stribeck_csv(a.data)
    write_csv(out / "averaged.csv", dict(velocity_deg_s=d.velocity, torque_nm=d.torque, torque_se_nm=d.torque_se,
                                         torque_sd_nm=d.torque_sd, decel=(d.branch == "decel").astype(float)))
    m = table1_static_model()
    v_true, t_true = minimum_torque_velocity(m)
    g = np.linspace(0.001, 1.5, 1500)
    write_csv(out / "model.csv", dict(velocity_deg_s=g, accel_nm=np.asarray(m.steady_state(jnp.asarray(g))),
                                      decel_nm=np.where(g < v_true, np.asarray(decel_branch(m, g, v_true)), np.nan)))
    b = detect_boundaries(d)
    write_json(out / "summary.json", dict(
        data=a.data, n_set_points=len(d), n_samples=int(d.count.sum()),
        n_accel=int(np.sum(d.branch == "accel")), n_decel=int(np.sum(d.branch == "decel")),
        model_v_min_deg_s=v_true, model_tau_min_nm=t_true,
        detected_v_min_deg_s=b.v_min, detected_tau_min_nm=b.tau_min, detected_v_crit_deg_s=b.v_crit,
        paper_v_min_deg_s=0.05, paper_v_crit_deg_s=1.2,
    ))
    print(f"{len(d)} set-points; model minimum {v_true:.4f} deg/s; detected v_min {b.v_min:.4f}, v_crit {b.v_crit:.4f} deg/s -> {out}")


if __name__ == "__main__":
    main()
