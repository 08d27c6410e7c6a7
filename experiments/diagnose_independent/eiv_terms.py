"""Where an attribution term on an effect-free recording comes from: the fitted baseline or the
kinematics' errors. Each recording is diagnosed without the attribution's margin (``resolution``
0, so that the calibrated tests alone decide) three ways:

* ``fitted``: as the CLI does;
* ``generator``: the generator's own plant as the baseline, taken as an estimate (``params=``,
  ``refit=True``: the tests keep the baseline's linearised refit, as for a fitted one);
* ``true_kinematics``: the recorded torque with the generator's exact position and velocity in
  place of the measured ones (the baseline fitted).

A term that stays with the generator's parameters but goes with exact kinematics is made by the
kinematics' errors through the model, not by where the fit landed. ``step1_below_bar`` lists the
candidates the naming test's first step finds significant each way (before the held-out test).
Writes one line per recording and way to <out>/eiv_terms_<study>.jsonl and prints it.

    python experiments/diagnose_independent/eiv_terms.py --study calib30 \\
        --only calib30_09_position_sine_pid_nff,calib30_17_sharp_steps_pi,calib30_21_position_sine_pid_nff
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import run as R
from lugre_jax.diagnose import diagnose
from lugre_jax.io import recording_from_arrays

WAYS = ("fitted", "generator", "true_kinematics")


def _row(job, way: str, rep) -> dict:
    j = rep.to_json()
    floor = j["baseline"]["noise_floor_nm"]
    # the diagnosis's rule: p_family <= alpha/3, with its tolerance for 2/120 against 0.05/3
    bar = j["alpha"] / 3.0 * (1.0 + 1e-9)
    return {"key": job["key"], "way": way, "verdict": j["verdict"], "floor_nm": floor,
            "fit": j["baseline"]["fit"].get("result"),
            "terms": [{"signal": t["signal"], "share_of_floor": t["held_out_share_nm"] / floor,
                       "p_family": t["p_family"], "p_held_out": t["p_held_out"]} for t in j["attribution"]["terms"]],
            # every group significant on the training blocks, whether or not the held-out test kept it
            "significant": [{"signal": t["signal"], "p_family": t["p_family"]}
                            for step in j["attribution"]["tests"] for t in step if t.get("p_family", 1.0) <= bar],
            # the candidates the naming test's first step finds significant (whatever the later checks)
            "step1_below_bar": [{"name": t["name"], "p_family": t["p_family"]}
                                for t in (j["selection_log"][0]["tests"] if j["selection_log"] else [])
                                if t.get("p_family", 1.0) <= bar]}


def main() -> None:
    a, res, out = R.study_cli(__doc__, ("--only", {"required": True, "help": "comma-separated keys"}))
    keys = a.only.split(",")
    lines = []
    for job in R.SETTINGS[a.study]():
        if job["key"] not in keys:
            continue
        g, _ = R.generated(job, Path(a.cache) if a.cache else res / "cache")
        rec = g.to_recording()
        exact = recording_from_arrays(g.time, np.asarray(g.true["theta"], float), np.asarray(g.true["omega"], float),
                                      g.torque, source=f"{job['key']} with the generator's exact kinematics")
        reps = {"fitted": lambda: diagnose(rec, progress=False, resolution=0.0),
                "generator": lambda: diagnose(rec, params=R.true_params(job) | {"offset": 0.0}, refit=True,
                                              progress=False, resolution=0.0),
                "true_kinematics": lambda: diagnose(exact, progress=False, resolution=0.0)}
        for way in WAYS:
            line = json.dumps(_row(job, way, reps[way]()))
            print(line, flush=True)
            lines.append(line)
    (out / f"eiv_terms_{a.study}.jsonl").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
