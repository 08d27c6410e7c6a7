"""Fig. 6 of Li et al. 2020: identified (piecewise, GA-PSO) Stribeck curve over the fitting curve of
the test data (shipped synthetic data).

    python experiments/fig06_identified_curve/run.py [--method gapso] [--seeds 4] [--no-refine]
"""

import sys
from pathlib import Path

import jax
import numpy as np

from lugre_jax.identify import identify_piecewise
from lugre_jax.io import write_csv, write_json
from lugre_jax.identify import table1_static_model
from lugre_jax.io import load_stribeck_csv
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import identification_parser  # noqa: E402


def main() -> None:
    a = identification_parser(__doc__, __file__, "gapso", 4, refine=True).parse_args()
    out = Path(a.out)
    d = load_stribeck_csv(a.data)
    r = identify_piecewise(d, a.method, key=jax.random.key(6), n_seeds=a.seeds, refine=a.refine)
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
