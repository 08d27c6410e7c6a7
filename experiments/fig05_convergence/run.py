"""Fig. 5 of Li et al. 2020 (section 4.2.4): convergence of PSO vs GA-PSO on the low-velocity segment (1).

The paper: "after 100 identification operations, the number of iterations of the GA-PSO converges at
(10-13) times ... the convergence velocity of PSO is significantly slower". We rerun both with the
paper's settings on synthetic segment-1 data (Table 1 segment 1 truth, 92 points over (0, 0.05] deg/s,
noise sd 0.015 N*m; see experiments/optimiser_benchmark/static_problem.py) over many seeds, and count
iterations AND loss evaluations (GA-PSO spends 5x more evaluations per iteration than PSO).

    python experiments/fig05_convergence/run.py [--seeds 200] [--out DIR]

Writes DIR/convergence.json (summary + per-seed metrics) and DIR/histories_<method>.csv
(best-so-far loss J per iteration, one row per seed).
"""

from __future__ import annotations

import sys
from pathlib import Path

import jax
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "optimiser_benchmark"))

from static_problem import study_parser, study_problem  # noqa: E402

from lugre_jax.identify import optimise  # noqa: E402
from lugre_jax.io import write_csv, write_json  # noqa: E402
import lugre_jax as _lj  # noqa: E402

_lj.configure()  # this script opts in to float64 and the XLA options

METHODS = {
    "PSO (paper)": ("pso", {}),
    "GA-PSO (paper, 20 GA gens/iter)": ("gapso", {}),
    "GA-PSO (1 GA gen/iter)": ("gapso", {"ga_steps": 1}),
}


def first_index(hist: np.ndarray, level: np.ndarray) -> np.ndarray:
    """First column where each row of ``hist`` is <= its ``level``; -1 if never."""
    ok = hist <= level[:, None]
    return np.where(ok.any(axis=1), ok.argmax(axis=1), -1)


def stats(a: np.ndarray) -> dict:
    a = np.asarray(a, dtype=float)
    a = a[np.isfinite(a)]
    if a.size == 0:
        return {"n": 0}
    return {"n": int(a.size), "mean": float(a.mean()), "median": float(np.median(a)), "p10": float(np.quantile(a, 0.1)),
            "p90": float(np.quantile(a, 0.9)), "min": float(a.min()), "max": float(a.max())}


def main(argv=None) -> int:
    a = study_parser(__doc__, 200, 5, HERE / "results").parse_args(argv)
    out = Path(a.out)
    prob, x_ref, j_ref = study_problem(a, "segment1")
    summary = {"problem": prob.describe(x_ref, j_ref), "seeds": a.seeds, "methods": {}}
    for label, (method, settings) in METHODS.items():
        print(f"{label}: {a.seeds} seeds ...", flush=True)
        r = optimise(method, prob.loss_fn, prob.lower, prob.upper, key=jax.random.key(a.key), n_seeds=a.seeds,
                     residual_fn=prob.residual_fn, **settings)
        h, ev = r.history, r.evals_history
        final = h[:, -1]
        it_own = first_index(h, final * 1.01)
        it_ref = first_index(h, np.full(len(h), 1.01 * j_ref))
        # What a fitness curve shows by eye: 99% of the seed's total improvement done.
        it_curve = first_index(h, final + 0.01 * (h[:, 0] - final))
        ev_own = ev[np.arange(len(h)), it_own]
        ev_ref = np.where(it_ref >= 0, ev[np.arange(len(h)), np.maximum(it_ref, 0)], np.nan)
        summary["methods"][label] = {
            "method": method, "settings": settings,
            "evals_per_iteration": float(ev[0, 2] - ev[0, 1]), "evals_total": float(ev[0, -1]),
            "wall_time_s": r.wall_time, "compile_time_s": r.compile_time,
            "final_J": stats(final),
            "success_rate_1pct_of_reference": float(np.mean(final <= 1.01 * j_ref)),
            "iters_to_1pct_of_own_final": stats(it_own),
            "evals_to_1pct_of_own_final": stats(ev_own),
            "iters_to_99pct_of_improvement": stats(it_curve),
            "evals_to_99pct_of_improvement": stats(ev[np.arange(len(h)), it_curve]),
            "iters_to_1pct_of_reference": stats(np.where(it_ref >= 0, it_ref, np.nan)),
            "evals_to_1pct_of_reference": stats(ev_ref),
            "reached_reference_fraction": float(np.mean(it_ref >= 0)),
            "median_history": np.median(h, axis=0), "p10_history": np.quantile(h, 0.1, axis=0),
            "p90_history": np.quantile(h, 0.9, axis=0), "evals_history": ev[0],
        }
        cols = {f"iter{t}": h[:, t] for t in range(h.shape[1])}
        write_csv(out / f"histories_{method}{'_g1' if settings else ''}.csv", cols)
        m = summary["methods"][label]
        print(f"  final J median {m['final_J']['median']:.6g} (ref {j_ref:.6g}); success {m['success_rate_1pct_of_reference']:.2f}; "
              f"iters to 1% of ref: median {m['iters_to_1pct_of_reference'].get('median')} "
              f"(evals {m['evals_to_1pct_of_reference'].get('median')}); iters to 99% of improvement: median "
              f"{m['iters_to_99pct_of_improvement']['median']} (evals {m['evals_to_99pct_of_improvement']['median']}); wall {r.wall_time:.2f}s", flush=True)
    write_json(out / "convergence.json", summary)
    print(f"wrote {out / 'convergence.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
