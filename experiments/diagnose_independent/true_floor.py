"""The noise floor against what the TRUE model reaches: each effect-free recording of a study is
diagnosed with the generator's own plant as the baseline (``params=``, no fit), so the baseline's
held-out RMSE is the true model's through the tool's own conditioning; that is the floor a complete
model can reach (torque noise plus the kinematics' errors carried through the true model). Writes
one line per recording to <out>/true_floor_<study>.jsonl (with the verdict and the attribution the
true model's residual gets) and prints the floor against it and against the true torque noise.

    python experiments/diagnose_independent/true_floor.py --study calib3 --shard 0/2   # and 1/2
    python experiments/diagnose_independent/true_floor.py --study calib29 --only calib29_09_position_sine_pi

With ``--all-candidates`` the eight candidates are tested too (to <out>/true_floor_all_<study>.jsonl): what
the selection names on the true model's residual.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import run as R
from lugre_jax.diagnose import diagnose


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", choices=sorted(R.SETTINGS), required=True)
    ap.add_argument("--shard", default="0/1", help="i/n: every n-th recording starting at i")
    ap.add_argument("--only", default="", help="comma-separated keys (default: every effect-free recording)")
    ap.add_argument("--cache", default=None, help="generated-recording cache (default <results>/<study>/cache)")
    ap.add_argument("--all-candidates", action="store_true", help="test the eight candidates too")
    a = ap.parse_args()
    i, n = (int(x) for x in a.shard.split("/"))
    out = Path(__file__).resolve().with_name("results") / a.study
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"true_floor_{'all_' if a.all_candidates else ''}{a.study}.jsonl"
    done = {json.loads(line)["key"] for line in path.read_text().splitlines()} if path.exists() else set()
    jobs = [j for k, j in enumerate(R.jobs(a.study, [11], [1.0])) if k % n == i and j["key"] not in done
            and j.get("expected", "none") == "none" and (not a.only or j["key"] in a.only.split(","))]
    for job in jobs:
        g, _ = R.generated(job, Path(a.cache) if a.cache else out / "cache")
        rep = diagnose(g.to_recording(), params=R.true_params(job) | {"offset": 0.0, "friction_model": "LuGre"},
                       candidates=None if a.all_candidates else [], progress=False)
        b = rep.baseline
        row = {"key": job["key"], "true_torque_noise": g.torque_noise_std,
               "true_model_validation_rmse": b.validation_rmse_nm, "noise_floor": b.noise_floor_nm,
               "torque_noise_estimate": b.torque_noise_nm, "kinematic_noise": b.kinematic_noise_nm,
               "verdict": rep.verdict, "attribution": rep.attribution}
        with open(path, "a") as fh:
            fh.write(json.dumps(row) + "\n")
        print(f"{job['key']}: floor / true-model held-out RMSE {b.noise_floor_nm / b.validation_rmse_nm:.3f}, "
              f"floor / true torque noise {b.noise_floor_nm / g.torque_noise_std:.3f}, verdict {rep.verdict}",
              flush=True)


if __name__ == "__main__":
    main()
