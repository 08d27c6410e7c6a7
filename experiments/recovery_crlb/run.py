"""Recovery of known Stribeck parameters from synthetic steady-state data, and the Cramer-Rao bound.

Truth: Fc = 0.9 N*m, Fs = 2.4 N*m, vs = 0.05 deg/s, sigma2 = 3.0 N*m*s/deg (whole scheme), sampled at
the 80 accelerating-branch set-points of the shipped data design, 30 samples each, white noise of
0.08 N*m per sample. For each of --n realisations: identify, record the estimate and its standard
errors. Reports, per parameter, the fraction of realisations with |estimate - truth| < 2 SE (target
>= 90 %) and the ratio of the estimator variance to the CRLB (target <= 1.5).

    python experiments/recovery_crlb/run.py [--n 100] [--method lm] [--seeds 16]
"""

import sys
from pathlib import Path

import jax
import numpy as np
from tqdm import tqdm

from lugre_jax.friction import Stribeck, from_vector
from lugre_jax.identify import crlb, identify_whole, paper_like_velocities, sample_stribeck_data
from lugre_jax.io import write_csv, write_json
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import identification_parser  # noqa: E402

TRUTH = np.array([0.9, 2.4, 0.05, 3.0])
NAMES = ("Fc", "Fs", "vs", "sigma2")
NOISE, REPEATS = 0.08, 30


def main() -> None:
    ap = identification_parser(__doc__, __file__, "lm", 16, data=False)
    ap.add_argument("--n", type=int, default=100)
    a = ap.parse_args()
    out = Path(a.out)
    v, _ = paper_like_velocities(0.09)
    bound = crlb(lambda x, vv: from_vector(Stribeck, x).steady_state(vv), TRUTH, v, NOISE / np.sqrt(REPEATS))
    xs, ses, losses = [], [], []
    for i in tqdm(range(a.n), desc="realisations"):
        d = sample_stribeck_data(Stribeck(*TRUTH), v, key=jax.random.key(10_000 + i), n_repeats=REPEATS, noise_sd=NOISE)
        s = identify_whole(d, a.method, key=jax.random.key(i), n_seeds=a.seeds, refine=a.refine).segments[0]
        xs.append(s.x)
        ses.append(s.uncertainty.se)
        losses.append(s.loss)
    xs, ses = np.array(xs), np.array(ses)
    z = (xs - TRUTH) / ses
    within = np.mean(np.abs(z) < 2, axis=0)
    var_ratio = np.var(xs, axis=0, ddof=1) / np.diag(bound)
    bias_in_se = (xs.mean(0) - TRUTH) / np.sqrt(np.diag(bound))
    cols = {f"{n}": xs[:, k] for k, n in enumerate(NAMES)}
    cols.update({f"{n}_se": ses[:, k] for k, n in enumerate(NAMES)})
    cols["loss"] = np.array(losses)
    write_csv(out / "estimates.csv", cols)
    summary = dict(
        truth=dict(zip(NAMES, TRUTH.tolist())), noise_sd_per_sample_nm=NOISE, repeats=REPEATS, n_set_points=int(v.size),
        n_realisations=a.n, method=a.method, seeds=a.seeds, refine=a.refine,
        crlb_sd=dict(zip(NAMES, np.sqrt(np.diag(bound)).tolist())),
        empirical_sd=dict(zip(NAMES, xs.std(0, ddof=1).tolist())),
        mean_reported_se=dict(zip(NAMES, ses.mean(0).tolist())),
        fraction_within_2se=dict(zip(NAMES, within.tolist())),
        variance_over_crlb=dict(zip(NAMES, var_ratio.tolist())),
        bias_in_crlb_sd=dict(zip(NAMES, bias_in_se.tolist())),
        pass_coverage=bool(np.all(within >= 0.9)), pass_efficiency=bool(np.all(var_ratio <= 1.5)),
    )
    write_json(out / "recovery.json", summary)
    for k, n in enumerate(NAMES):
        print(f"{n:7s} within 2 SE: {100 * within[k]:5.1f} %   var/CRLB: {var_ratio[k]:.3f}   "
              f"sd {xs[:, k].std(ddof=1):.3g} vs CRLB sd {np.sqrt(bound[k, k]):.3g}, bias {bias_in_se[k]:+.2f} CRLB-sd")
    print(f"coverage >= 90 %: {summary['pass_coverage']}; variance <= 1.5 CRLB: {summary['pass_efficiency']}")


if __name__ == "__main__":
    main()
