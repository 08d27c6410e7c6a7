"""How well the naming test's null holds the kinematics' errors: per recording of a study, the
error the conditioned kinematics actually bring through the generator's own plant (its prediction
on the true motion less that on the conditioned kinematics, over the resolved samples) against the
null's kinematic draws through the same model (``DiagnosisArrays.kinematic_errors``).

Also all the residual carries beyond the torque noise (the generator's noise-free torque less the
prediction), which the floor is about, and where the kinematics' error sits (its share in the
slowest fifth of the resolved samples) and what a check of the velocity column against its own
smoothing would find: where the column's departure from its Savitzky-Golay smoothing at the chosen
window has a mean square above the sensor noise's (chi-square over one window, Bonferroni over the
recording's windows at ``alpha``), the smoothing removed motion, not noise (a loop's transient or a
stick at a reversal faster than the window, and the velocity's kink at every reversal, which the
diagnosis's blur column holds); the table gives the share of the resolved samples so flagged
(widened by the window) and the share of the actual error they hold. The diagnosis does not leave
such samples out: on its own synthetic recording (make_recording) the check flags a third of the
samples, most at low speed around reversals, where a backlash's evidence lies.

The baseline is the generator's plant taken as given, with no candidates and 60 null draws (the
fewest the default alpha allows): only the conditioning, the floor and the null matter here. The
bristle path is the one the diagnosis chooses (the lowest training SSE under those parameters).
Writes <out>/kinematic_null_<study>.jsonl and prints a line a recording.

    python experiments/diagnose_independent/kinematic_null.py --study calib42
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from scipy.ndimage import maximum_filter1d, uniform_filter1d
from scipy.signal import savgol_coeffs, savgol_filter
from scipy.stats import chi2

import run as R
from lugre_jax.diagnose import diagnose, predict


def _rms(x) -> float:
    return float(np.sqrt(np.mean(np.square(x)))) if np.size(x) else 0.0


def motion_removed(velocity, noise_std: float, window: int, order: int, alpha: float) -> np.ndarray:
    """Samples where the velocity column's departure from its smoothing over ``window`` samples
    exceeds the sensor noise's by a chi-square test over one window (Bonferroni over the windows
    at ``alpha``), widened by the window on each side."""
    v = np.asarray(velocity, float)
    h = savgol_coeffs(window, order)
    gain = 1.0 - 2.0 * h[window // 2] + float(np.sum(h ** 2))  # var(n - H n) / var(n), white n
    ms = uniform_filter1d((v - savgol_filter(v, window, order)) ** 2, window)
    limit = chi2.isf(alpha / max(v.size / window, 1.0), window) / window
    return maximum_filter1d((ms > limit * gain * noise_std ** 2).astype(np.int8), 2 * window + 1) > 0


def row(job, cache: Path) -> dict:
    g, _ = R.generated(job, cache)
    rec = g.to_recording()
    rep = diagnose(rec, params=R.true_params(job) | {"offset": 0.0}, candidates=(), null_draws=60, progress=False)
    arr, cond = rep.arrays, rep.baseline.conditioning
    kin, model, keep = arr.kin, arr.baseline_model, np.asarray(arr.keep, bool)
    true = R.true_kinematics(g, kin.z0_sign)
    pred = np.asarray(predict(model, kin), float)
    e = np.asarray(predict(model, true), float) - pred
    # all the residual carries beyond the torque noise: the kinematics' error and what the model,
    # stepped on the sample grid, misses of the generator's continuous motion (a stick's breakaway
    # between two samples); the two can partly cancel
    beyond = np.asarray(g.true["torque"], float) - pred
    draws = np.asarray(arr.kinematic_errors, float)
    v = np.abs(np.asarray(kin.v, float))
    slow = keep & (v <= np.percentile(v[keep], 20))
    total = float(np.sum(e[keep] ** 2)) or 1.0
    out = {"key": job["key"], "fs": job["fs"], "position_column": job["position_column"],
           "velocity_column": job["velocity_column"], "torque_noise_nm": rep.baseline.torque_noise_nm,
           "kinematic_noise_nm": rep.baseline.kinematic_noise_nm, "source": cond["source"], "window": cond["window"],
           "actual_rms_nm": _rms(e[keep]), "null_rms_nm": _rms(draws[:, keep]) if draws.size else 0.0,
           "slowest_fifth_share": float(np.sum(e[slow] ** 2)) / total, "beyond_noise_rms_nm": _rms(beyond[keep])}
    # no ratio where the draws are nil (a noise-free velocity column: rounding only)
    nil = out["null_rms_nm"] <= 1e-6 * out["torque_noise_nm"]
    out["actual_over_null"] = None if nil else out["actual_rms_nm"] / out["null_rms_nm"]
    out["beyond_over_null"] = None if nil else out["beyond_noise_rms_nm"] / out["null_rms_nm"]
    if cond["velocity_measured"] and cond["source"] != "recording":
        flag = motion_removed(rec.velocity, cond["velocity_noise"], cond["window"], cond["order"], rep.alpha) & keep
        out |= {"flagged_share": float(flag.sum() / keep.sum()), "flagged_error_share": float(np.sum(e[flag] ** 2)) / total,
                "actual_rms_unflagged_nm": _rms(e[keep & ~flag])}
    return out


def main() -> None:
    a, res, out = R.study_cli(__doc__, ("--only", {"default": "", "help": "comma-separated keys (default: every effect-free row)"}))
    keys = [k for k in a.only.split(",") if k]
    lines = []
    for job in R.SETTINGS[a.study]():
        if (keys and job["key"] not in keys) or (not keys and job["expected"] != "none"):
            continue
        r = row(job, Path(a.cache) if a.cache else res / "cache")
        print(json.dumps(r), flush=True)
        lines.append(json.dumps(r))
    (out / f"kinematic_null_{a.study}.jsonl").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
