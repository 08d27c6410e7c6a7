"""Whole vs piecewise identification on the shipped synthetic data (paper section 4.2.2 / Fig. 12):
residuals per set-point and RMS near the minimum-torque velocity (0.05 deg/s in the paper) and near
the critical Stribeck velocity (1.2 deg/s).

    python experiments/whole_vs_piecewise/run.py [--method lm] [--seeds 16]
"""

import sys
from pathlib import Path

import jax
import numpy as np

from lugre_jax.identify import identify_piecewise, identify_whole
from lugre_jax.io import load_stribeck_csv, write_csv, write_json
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import identification_parser  # noqa: E402

WINDOWS = {"near_0.05": (0.02, 0.08), "near_1.2": (1.05, 1.35), "all": (0.0, 2.0)}


def main() -> None:
    a = identification_parser(__doc__, __file__, "lm", 16).parse_args()
    out = Path(a.out)
    d = load_stribeck_csv(a.data)
    acc = d.select(d.branch == "accel")
    kw = dict(n_seeds=a.seeds, refine=a.refine)
    whole = identify_whole(d, a.method, key=jax.random.key(0), **kw)
    piece = identify_piecewise(d, a.method, key=jax.random.key(1), **kw)
    paper = identify_piecewise(d, a.method, key=jax.random.key(2), edges=(0.05, 1.2), **kw)
    print(whole.table())
    print(piece.table())
    print(paper.table())
    rw = whole.predict(acc.velocity) - acc.torque
    rp = piece.predict(acc.velocity) - acc.torque
    re = paper.predict(acc.velocity) - acc.torque
    write_csv(out / "residuals.csv", dict(velocity_deg_s=acc.velocity, torque_nm=acc.torque, torque_se_nm=acc.torque_se,
                                          residual_whole_nm=rw, residual_piecewise_nm=rp, residual_paper_edges_nm=re))
    g = np.geomspace(float(acc.velocity[0]), 1.5, 800)
    write_csv(out / "curves.csv", dict(velocity_deg_s=g, whole_nm=whole.predict(g), piecewise_nm=piece.predict(g),
                                     paper_edges_nm=paper.predict(g)))
    summary = {}
    for name, (lo, hi) in WINDOWS.items():
        m = (acc.velocity >= lo) & (acc.velocity <= hi)
        summary[name] = dict(range_deg_s=[lo, hi], n=int(m.sum()),
                             rms_whole_nm=float(np.sqrt(np.mean(rw[m] ** 2))),
                             rms_piecewise_nm=float(np.sqrt(np.mean(rp[m] ** 2))),
                             rms_piecewise_paper_edges_nm=float(np.sqrt(np.mean(re[m] ** 2))),
                             max_abs_whole_nm=float(np.max(np.abs(rw[m]))),
                             max_abs_piecewise_nm=float(np.max(np.abs(rp[m]))),
                             mean_se_nm=float(np.mean(acc.torque_se[m])))
        print(f"{name:10s} {lo}-{hi} deg/s: RMS whole {summary[name]['rms_whole_nm']:.4f}, piecewise "
              f"{summary[name]['rms_piecewise_nm']:.4f} (detected edges), {summary[name]['rms_piecewise_paper_edges_nm']:.4f} "
              f"(paper edges 0.05/1.2) N*m (noise SE {summary[name]['mean_se_nm']:.4f})")
    write_json(out / "whole_vs_piecewise.json", dict(method=a.method, seeds=a.seeds, refine=a.refine, windows=summary,
                                                     whole=whole.to_json(), piecewise=piece.to_json(),
                                                     piecewise_paper_edges=paper.to_json()))


if __name__ == "__main__":
    main()
