"""Why the concealed load-dependent friction of the proof study is reported ``none`` (measured).

For each strength (and seed) of ``run.py``'s ``CONCEALED['load_dependent']`` on the proof study's
recording kind (issue plant, 144-s staircase, 200 Hz, torque noise 0.08 N*m):

1. definitions: least squares of the candidate's form ``mu*|J*a|*tanh(v/v_eps)`` (its fixed
   ``v_eps = 0.01*V``, and the generator's 0.02) on the generator's true effect torque, true
   kinematics: the share of the effect's sum of squares it expresses;
2. absorption: the baseline fitted to the recording with the effect and to the same recording
   without it (same noise draw): the share of the effect's sum of squares left in the residual
   on the resolved samples, and the share carried by unresolved transients (left out);
3. detection: the candidate's projected SSE drop on the baseline residual (as in the selection's
   scoring) in units of the noise floor (z), the acceleration x direction bins' t without the
   resolution margin, the verdict; then the selection forced to run (the first locate call made
   to return its smallest-p test as located): what it would name, with which evidence;
4. a prototype test, not in the library: cross-correlation of the residual with ``|J*a|*sign(v)``
   (:func:`lugre_jax.diagnose._locate.xcorr_test`, Bonferroni over +-0.5 s of lags).

    python experiments/diagnose_independent/load_dependent_probe.py 1:11 0:11 0.5:11 2:11
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run as R  # noqa: E402  (calls lugre_jax.configure())

from lugre_jax import testing as T  # noqa: E402
from lugre_jax.diagnose import _locate as L, _model as M, _select as S, diagnose  # noqa: E402


def generate(strength, seed):
    sens = T.Sensors(fs=200.0, torque_noise=0.08, velocity_noise=0.003, quantisation=0.0005)
    effs = R.CONCEALED["load_dependent"](strength) if strength > 0 else []
    return T.generate(R.excitation_of("staircase_short", 200.0, seed), effs, T.Plant(), T.VelocityPIController(), sens,
                      seed=seed)


def forced_diagnose(rec):
    orig, calls = L.locate, []

    def first_located(*a, **k):
        out = orig(*a, **k)
        calls.append(1)
        if len(calls) == 1 and not out["located"]:
            best = min(out["tests"], key=lambda x: x["p_value"])
            out = dict(out, located=[best], structural=[best])
        return out

    S.L.locate = first_located
    try:
        return diagnose(rec, progress=False)
    finally:
        S.L.locate = orig


def probe(strength, seed):
    g, g0 = generate(strength, seed), generate(0.0, seed)
    e, v, a = g.true["effect_torque"], g.true["omega"], g.true["acceleration"]
    J = T.Plant().J
    out = {"strength": strength, "seed": seed, "peak_over_noise": float(np.abs(e).max() / 0.08)}
    rep = diagnose(g.to_recording(), progress=False)
    A = rep.arrays
    r = np.asarray(A.r0)
    keep = r != 0
    w = ((~np.asarray(A.val)) & keep).astype(float)
    V = M.data_scales(A.rec)["V"]
    if strength > 0:
        expr = {}
        for ve in (0.02, 0.01 * V):
            x = np.abs(J * a) * np.tanh(v / ve)
            mu = float(x @ e / (x @ x))
            expr[f"v_eps={ve:.3g}"] = {"mu": mu, "share_expressed": float(1 - np.sum((e - mu * x) ** 2) / np.sum(e ** 2))}
        out["definition_fit"] = expr
        r_null = np.asarray(diagnose(g0.to_recording(), progress=False).arrays.r0)
        left = r - r_null
        out["absorption"] = {"effect_sse_share_unresolved": float(np.sum(e[~keep] ** 2) / np.sum(e ** 2)),
                             "effect_sse_share_left_resolved": float(np.sum(left ** 2) / np.sum(e[keep] ** 2)),
                             "oracle_z_training": float(np.sqrt(np.sum(w * e ** 2)) / rep.baseline.noise_floor_nm)}
    inertial = np.asarray(M._parts(A.baseline_model, A.kin)[0])
    x = np.abs(inertial) * np.tanh(np.asarray(A.kin.v) / (0.01 * V))
    er, ee = float(np.sum(w * x * r)), float(np.sum(w * x * x))
    out["candidate_projection_z"] = float(np.sign(er) * np.sqrt(er ** 2 / ee) / rep.baseline.noise_floor_nm)
    out["verdict"] = rep.verdict
    tests = A.loc0["tests"]
    best = min(tests, key=lambda q: q["p_value"])
    out["best_locate_test"] = {"test": best["test"], "region": best["region"], "p": best["p_value"],
                               "p_holm": best["p_holm"], "n_tests": len(tests)}
    a_c, v_c, blocks = np.asarray(A.kin.a), np.asarray(A.kin.v), np.asarray(A.blocks)
    big = np.abs(a_c) > 0.2 * M.data_scales(A.rec)["A"]
    bins = []
    for sv in (1, -1):
        for sa in (1, -1):
            m = big & keep & (np.sign(v_c) == sv) & (np.sign(a_c) == sa)
            res = L.cluster_mean_test(r, m, blocks)
            if res is not None:
                bins.append({"dir": sv, "acc": sa, "mean": res["mean_residual"], "t_no_margin": res["statistic"],
                             "clusters": res["df"] + 1})
    out["acceleration_bins"] = bins
    xx = np.where(keep, x, x[keep].mean())
    xc = L.xcorr_test(r, xx, 100, min(r.size // 4, 1000))
    out["prototype_xcorr_absJa_signv"] = {"z": xc["statistic"], "lag": xc["lag_samples"], "p_bonferroni": xc["p_value"]}
    if strength > 0 and rep.verdict == "none":
        f = forced_diagnose(g.to_recording())
        out["forced_selection"] = {"verdict": f.verdict, "refits": f.selection_log[0]["joint_refits"],
                                   "named": {m.name: m.params for m in f.missing_physics}}
    return out


if __name__ == "__main__":
    for spec in sys.argv[1:] or ["1:11"]:
        st, sd = spec.split(":")
        print(json.dumps(probe(float(st), int(sd)), default=float), flush=True)
