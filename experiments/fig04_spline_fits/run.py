"""Fig. 4 of Li et al. 2020: cubic-spline fits of each segment (accelerating and decelerating branch
tangent at the minimum-torque velocity) and the 4-term sum-of-sines curves of eq. (12).

    python experiments/fig04_spline_fits/run.py [--data data/stribeck_paper_like.csv] [--edges 0.05,1.2]
"""

import argparse
from pathlib import Path

import numpy as np

from lugre_jax.identify import smooth_segments
from lugre_jax.io import load_stribeck_csv, write_csv, write_json
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=str(ROOT / "data" / "stribeck_paper_like.csv"))
    ap.add_argument("--edges", default=None, help="VMIN,VCRIT in deg/s (default: detected)")
    ap.add_argument("--out", default=str(Path(__file__).with_name("results")))
    a = ap.parse_args()
    out = Path(a.out)
    d = load_stribeck_csv(a.data)
    edges = None if a.edges is None else tuple(float(x) for x in a.edges.split(","))
    sm = smooth_segments(d, edges)
    b = sm.boundaries
    curves = {}
    for name, (lo, hi) in sm.ranges.items():
        seg = sm.segments[name]
        g = np.linspace(max(lo, float(seg.velocity.min())), hi, 200)
        spline = sm.decel_curve(g) if name == "1 decel" else sm.splines[name](g)
        curves[name] = dict(v=g, spline=spline, sines=sm.sines[name](g))
        write_csv(out / f"segment_{name.replace(' ', '_')}.csv",
                  dict(velocity_deg_s=g, spline_nm=spline, sum_of_sines_nm=sm.sines[name](g)))
    write_csv(out / "averaged.csv", dict(velocity_deg_s=d.velocity, torque_nm=d.torque, torque_se_nm=d.torque_se,
                                         decel=(d.branch == "decel").astype(float)))
    tangent = {}
    if sm.decel_curve is not None:
        tangent = dict(value_gap_nm=float(sm.decel_curve(b.v_min) - sm.splines["1"](b.v_min)),
                       slope_gap_nm_s_per_deg=float(sm.decel_curve.derivative(b.v_min) - sm.splines["1"].derivative(b.v_min)))
    write_json(out / "fig04.json", dict(
        data=a.data, v_min_deg_s=b.v_min, v_crit_deg_s=b.v_crit, detected=b.detected,
        sum_of_sines_eq12={k: s.to_json() for k, s in sm.sines.items()}, tangency_at_v_min=tangent,
        n_points={k: len(v) for k, v in sm.segments.items()},
    ))
    for k, s in sm.sines.items():
        print(f"segment {k}: {sm.ranges[k][0]:.4g}-{sm.ranges[k][1]:.4g} deg/s, {len(sm.segments[k])} points, "
              f"eq. (12) vs spline RMS {s.rms:.2e} N*m")
    print(f"tangency at v_min: {tangent}")


if __name__ == "__main__":
    main()
