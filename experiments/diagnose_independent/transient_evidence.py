"""Where an effect's evidence lies on a study row: the noncentrality of the true effect's torque
(its squared sum over the torque noise variance, before the baseline's directions are taken off:
an upper bound) over the training samples the diagnosis keeps, over the samples it leaves out as
unresolved in moves (transients the kinematics do not resolve) and in dwells (the true speed under
1 % of its peak throughout), and what is left of the moves' part when the effect's torque is summed
over each unresolved run (one number a run, its noise std sqrt(n) times the sample's): the most a test
on each run's torque integral could see, which needs only the run's end velocities. Held-out
samples are left out. Writes <out>/transient_<study>.jsonl and prints a line a row.

    python experiments/diagnose_independent/transient_evidence.py --study fresh54 --only fresh54_effect17_load_dependent_e
"""

from __future__ import annotations

import numpy as np

import run as R
from lugre_jax.diagnose import diagnose
from oracle_power import effect_torque


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(int), [0]])))
    return list(zip(edges[::2], edges[1::2]))


def evidence(job, cache) -> dict:
    g, _ = R.generated(job, cache)
    rep = diagnose(g.to_recording(), progress=False)
    r0, val = np.asarray(rep.arrays.r0), np.asarray(rep.arrays.val)
    effect = effect_torque(g, R.true_params(job))
    var = g.torque_noise_std ** 2
    speed = np.abs(np.asarray(g.true["omega"], float))
    kept = (r0 != 0) & ~val
    lam_moves = lam_dwells = lam_summed = 0.0
    n_moves = 0
    for a, b in _runs(r0 == 0):
        if np.any(val[a:b]):
            continue
        e = effect[a:b]
        if np.max(speed[a:b]) < 0.01 * np.max(speed):
            lam_dwells += float(np.sum(e ** 2)) / var
            continue
        n_moves += 1
        lam_moves += float(np.sum(e ** 2)) / var
        lam_summed += float(np.sum(e) ** 2) / ((b - a) * var)
    return {"key": job["key"], "verdict": rep.verdict, "expected": job["expected"],
            "lam_kept": float(np.sum(effect[kept] ** 2) / var), "lam_unresolved_moves": lam_moves,
            "lam_unresolved_dwells": lam_dwells, "lam_moves_summed_per_run": lam_summed,
            "unresolved_move_runs": n_moves}


def main() -> None:
    R.run_effect_rows(__doc__, "transient", evidence, lambda row: (
        f"{row['key']}: {row['verdict']}; lam kept {row['lam_kept']:.1f}, unresolved moves "
        f"{row['lam_unresolved_moves']:.1f} (summed per run {row['lam_moves_summed_per_run']:.1f} over "
        f"{row['unresolved_move_runs']} runs), dwells {row['lam_unresolved_dwells']:.1f}"))

if __name__ == "__main__":
    main()
