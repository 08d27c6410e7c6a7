"""Real steady-state friction data (TRO2021, Mablekos-Alexiou et al., IEEE T-RO 2021): Coulomb +
viscous (eq. 11) vs Stribeck (eq. 10), whole vs piecewise, on both drives and both directions.
RMS errors in mN*m. Skips cleanly when the data folder is absent.

    python experiments/real_data_tro2021/run.py [--data-root ../shared/data] [--seeds 8]

Bounds are scaled to the data (``auto``): these drives run at 10-1200 deg/s and ~1-4 mN*m, far
outside the paper's N*m / deg/s ranges. Each model is fitted with GA-PSO (+ LM refinement) and with
multi-start LM; the lower loss is kept and both are recorded.
"""

import argparse
import sys
from pathlib import Path

import jax
import numpy as np
from tqdm import tqdm

from lugre_jax.identify import identify_piecewise, identify_whole
from lugre_jax.io import load_epos_steady_state, write_csv, write_json
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

ROOT = Path(__file__).resolve().parents[2]
DRIVES = ("driveNo1", "driveNo3")
MODELS = ("coulomb_viscous_whole", "stribeck_whole", "stribeck_piecewise")


def fit(d, model, method, key, seeds):
    refine = method != "lm"
    n = seeds * (4 if method == "lm" else 1)
    if model == "coulomb_viscous_whole":
        return identify_whole(d, method, key=key, n_seeds=n, refine=refine, bounds="auto", kind="coulomb_viscous")
    if model == "stribeck_whole":
        return identify_whole(d, method, key=key, n_seeds=n, refine=refine, bounds="auto")
    return identify_piecewise(d, method, key=key, n_seeds=n, refine=refine, bounds="auto")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data-root", default=str(ROOT.parent / "shared" / "data"))
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--methods", default="gapso,lm")
    ap.add_argument("--out", default=str(Path(__file__).with_name("results")))
    a = ap.parse_args()
    root = Path(a.data_root) / "tro2021"
    if not root.is_dir():
        print(f"TRO2021 data not found at {root}; skipping (pass --data-root)", file=sys.stderr)
        return 0
    out = Path(a.out)
    methods = a.methods.split(",")
    table, details, curves = [], {}, {}
    jobs = [(dr, sgn, m) for dr in DRIVES for sgn in (1, -1) for m in MODELS]
    for i, (drive, sign, model) in enumerate(tqdm(jobs, desc="fits")):
        data = load_epos_steady_state(root / drive / "steady_state" / "0.096kg")
        d = data.direction(sign)
        direction = "positive" if sign > 0 else "negative"
        tag = f"{drive}/{direction}/{model}"
        per_method = {}
        for method in methods:
            try:
                r = fit(d, model, method, jax.random.key(i), a.seeds)
                per_method[method] = r
            except ValueError as e:
                details[f"{tag}/{method}"] = dict(error=str(e))
        if not per_method:
            table.append(dict(drive=drive, direction=direction, model=model, rms_mnm=None, method=None,
                              error=details[f"{tag}/{methods[0]}"]["error"]))
            continue
        losses = {m: sum(s.loss for s in r.segments) for m, r in per_method.items()}
        best = min(losses, key=losses.get)
        r = per_method[best]
        table.append(dict(drive=drive, direction=direction, model=model, method=best, rms_mnm=1e3 * r.rms(),
                          n_points=int(sum(s.n_points for s in r.segments)),
                          rms_by_method_mnm={m: 1e3 * rr.rms() for m, rr in per_method.items()},
                          loss_by_method=losses,
                          segments=[dict(name=s.name, v_range=list(s.v_range), params=s.params, se=s.se,
                                         statement=s.uncertainty.statement) for s in r.segments]))
        details[tag] = r.to_json()
        g = np.linspace(float(d.velocity.min()), float(d.velocity.max()), 400)
        curves[tag] = (g, r.predict(g), d.velocity, d.torque, d.torque_se)
    write_json(out / "real_data.json", dict(table=table, details=details, methods=methods, seeds=a.seeds,
                                            units="velocity deg/s, torque N*m; rms in mN*m"))
    for tag, (g, p, v, t, se) in curves.items():
        write_csv(out / f"curve_{tag.replace('/', '_')}.csv", dict(velocity_deg_s=g, model_nm=p))
        write_csv(out / f"data_{tag.replace('/', '_')}.csv", dict(velocity_deg_s=v, torque_nm=t, torque_se_nm=se))
    print(f"\n{'drive':9s} {'direction':9s} " + " ".join(f"{m:>24s}" for m in MODELS))
    for drive in DRIVES:
        for direction in ("positive", "negative"):
            cells = []
            for m in MODELS:
                row = next(x for x in table if x["drive"] == drive and x["direction"] == direction and x["model"] == m)
                cells.append("n/a (see json)" if row["rms_mnm"] is None else f"{row['rms_mnm']:.4f} ({row['method']})")
            print(f"{drive:9s} {direction:9s} " + " ".join(f"{c:>24s}" for c in cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
