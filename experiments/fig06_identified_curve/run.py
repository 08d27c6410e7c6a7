"""Fig. 6 of Li et al. 2020: identified (piecewise, GA-PSO) Stribeck curve over the fitting curve of
the test data (shipped synthetic data).

    python experiments/fig06_identified_curve/run.py [--method gapso] [--seeds 4] [--no-refine]
"""

import argparse
from pathlib import Path

import jax
import numpy as np

from lugre_jax.identify import identify_piecewise
from lugre_jax.io import write_csv, write_json
from lugre_jax.identify import table1_static_model
from lugre_jax.io import load_stribeck_csv
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=str(ROOT / "data" / "stribeck_paper_like.csv"))
    ap.add_argument("--method", default="gapso")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--no-refine", action="store_true")
    ap.add_argument("--out", default=str(Path(__file__).with_name("results")))
    a = ap.parse_args()
    out = Path(a.out)
    d = load_stribeck_csv(a.data)
    r = identify_piecewise(d, a.method, key=jax.random.key(6), n_seeds=a.seeds, refine=not a.no_refine)
    print(r.table())
    write_json(out / "identification.json", r.to_json())
    g = np.geomspace(0.004, 1.5, 600)
    dec = g < r.boundaries.v_min
    write_csv(out / "curves.csv", dict(
        velocity_deg_s=g,
        spline_nm=r.boundaries.spline(g),
        identified_accel_nm=r.predict(g),
        identified_decel_nm=np.where(dec, r.predict(g, "decel"), np.nan),
        table1_model_nm=np.asarray(table1_static_model().steady_state(g)),
    ))
    write_csv(out / "averaged.csv", dict(velocity_deg_s=d.velocity, torque_nm=d.torque, torque_se_nm=d.torque_se,
                                         decel=(d.branch == "decel").astype(float)))
    print(f"RMS over all set-points {r.rms():.4g} N*m; jumps at boundaries {r.jumps}")


if __name__ == "__main__":
    main()
