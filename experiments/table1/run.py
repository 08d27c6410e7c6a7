"""Table 1 of Li et al. 2020 regenerated from the shipped synthetic data (data/stribeck_paper_like.csv),
piecewise scheme, beside the paper's values.

Configurations: boundaries detected from the data vs the paper's stated 0.05 / 1.2 deg/s; GA-PSO with
the paper's settings (+ LM refinement) vs multi-start Levenberg-Marquardt; fitting the averaged data
vs the eq. (12) sum-of-sines curves (the paper's route).

    python experiments/table1/run.py [--seeds 4] [--quick]
"""

import argparse
from pathlib import Path

import jax
import numpy as np

from lugre_jax.identify import identify_piecewise
from lugre_jax.io import load_stribeck_csv, write_csv, write_json
from lugre_jax.plant import TABLE1
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = {
    # name: (method, refine, edges, target, seeds multiplier, continuity weight)
    "gapso_detected": ("gapso", True, None, "data", 1, 3.0),
    "gapso_paper_edges": ("gapso", True, (0.05, 1.2), "data", 1, 3.0),
    "lm_detected": ("lm", False, None, "data", 4, 3.0),
    "lm_paper_edges": ("lm", False, (0.05, 1.2), "data", 4, 3.0),
    "lm_paper_edges_no_continuity": ("lm", False, (0.05, 1.2), "data", 4, 0.0),
    "lm_paper_edges_sines": ("lm", False, (0.05, 1.2), "sines", 4, 3.0),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=str(ROOT / "data" / "stribeck_paper_like.csv"))
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--quick", action="store_true", help="LM configurations only")
    ap.add_argument("--out", default=str(Path(__file__).with_name("results")))
    a = ap.parse_args()
    out = Path(a.out)
    d = load_stribeck_csv(a.data)
    rows = {k: [] for k in ("config", "segment", "v_lo", "v_hi", "Fc", "Fc_se", "Fs", "Fs_se", "vs", "vs_se",
                            "sigma2", "sigma2_se", "loss", "rms_nm", "evaluations", "wall_time_s")}
    results = {}
    for i, (name, (method, refine, edges, target, mult, cw)) in enumerate(CONFIGS.items()):
        if a.quick and method != "lm":
            continue
        r = identify_piecewise(d, method, key=jax.random.key(i), n_seeds=a.seeds * mult, refine=refine, edges=edges, target=target,
                               continuity_weight=cw)
        results[name] = r.to_json()
        print(f"\n== {name}\n{r.table()}")
        for s in r.segments:
            p, se = s.params, s.se
            rows["config"].append(i)
            rows["segment"].append({"1": 1, "1 decel": 1.5, "2": 2, "3": 3}[s.name])
            rows["v_lo"].append(s.v_range[0])
            rows["v_hi"].append(s.v_range[1])
            for n in ("Fc", "Fs", "vs", "sigma2"):
                rows[n].append(p.get(n, np.nan))
                rows[n + "_se"].append(se.get(n, np.nan))
            rows["loss"].append(s.loss)
            rows["rms_nm"].append(s.rms)
            rows["evaluations"].append(s.evaluations)
            rows["wall_time_s"].append(s.wall_time)
    write_csv(out / "table1.csv", rows)
    write_json(out / "table1.json", dict(
        data=a.data, configs={k: dict(method=v[0], refine=v[1], edges=v[2], target=v[3], continuity_weight=v[5])
                 for k, v in CONFIGS.items()},
        config_index={k: i for i, k in enumerate(CONFIGS)},
        paper_table1={str(k): dict(zip(("Fc", "Fs", "vs", "sigma2"), v)) for k, v in TABLE1.items()},
        results=results,
    ))
    print(f"\nwrote {out / 'table1.json'}")


if __name__ == "__main__":
    main()
