"""What an oracle could name: for each effect row of a study, the part of the true effect's torque
that the baseline's own parameters cannot absorb, over the torque noise, as the noncentrality of a
test that knows the effect's exact shape. It bounds what any calibrated test can do on that row.

The effect's torque is the recorded torque without noise less the generator's own plant along the
true motion (``predict`` of the true parameters on the true kinematics, so it holds every effect,
asymmetry included). The baseline's directions are the Jacobian of that prediction in its
log-parameters (central differences; no offset, which ``diagnose`` does not fit by default); the remainder is the effect's part
orthogonal to them, AR(1)-whitened where the noise is coloured. Its squared norm over the training
samples (four blocks in five) over the noise's innovation variance is the noncentrality ``lam`` of a
one-column chi-square test (each study row of ``run.py`` also holds it over the samples the
diagnosis kept for training, ``oracle_lam_kept``: a sharp transient's samples leave the fit); the oracle's power is at the naming test's level, ``alpha/3`` shared
over the eight candidates (Bonferroni; for an effect outside them, ``expected`` ``unexplained``, the
same level over the attribution's eight groups with the time line).

That linearisation at the true parameters understates what the baseline absorbs when an effect
moves its parameters far (a Stribeck exponent's change, taken up by ``Fs`` and ``vs``):
``lam_fitted`` and ``oracle_power_fitted`` are the same after the baseline's nonlinear fit to the
noise-free torque along the true motion (:func:`oracle_fitted`), the bound for a test on a fitted
baseline's residual. Writes <out>/oracle_<study>.jsonl and prints a line a row.

    python experiments/diagnose_independent/oracle_power.py --study fresh31

With ``--kept`` each row is diagnosed again (minutes a row) and ``lam_kept`` and ``oracle_power_kept``
hold the same over the training samples the diagnosis keeps (dwells, transients and samples the
kinematics do not resolve left out), ``lam_val`` over the fixed held-out phase's samples (which
confirm an attribution term), to <out>/oracle_kept_<study>.jsonl; ``--only`` takes
comma-separated keys. ``--tally S1,S2`` reads the written rows of studies instead: of the rows an
oracle finds with power 0.9 or more, how many the diagnosis got exactly right (``--fitted``: by
``oracle_power_fitted``; with ``--kept`` also by the run rows' ``oracle_lam_kept``).
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.stats import chi2, ncx2

import run as R
from plot import load
from lugre_jax.diagnose import CANDIDATES, DiagnoseConfig, baseline_from_params, diagnose, predict
from lugre_jax.friction import NonPassiveWarning

PARAMS = ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1")  # the baseline's directions (delta is fixed)


def _whiten(x: np.ndarray, phi: float) -> np.ndarray:
    """AR(1) prewhitening along the first axis (the first sample scaled to the stationary law)."""
    if phi <= 0:
        return x
    out = np.empty_like(x)
    out[0] = np.sqrt(1.0 - phi ** 2) * x[0]
    out[1:] = x[1:] - phi * x[:-1]
    return out


def power_at(lam):
    """The oracle's power at noncentrality ``lam``: a one-column chi-square test at the naming test's
    level, ``alpha/3`` shared over the eight candidates (Bonferroni)."""
    return ncx2.sf(chi2.isf(DiagnoseConfig().alpha_name / len(CANDIDATES), 1), 1, lam)


def _predict_along(kin, params: dict) -> np.ndarray:
    return np.asarray(predict(baseline_from_params(params | {"offset": 0.0}), kin), float)


def effect_torque(g, params: dict, kin=None) -> np.ndarray:
    """The effect's torque on a generated recording: its torque without noise less the generator's
    own plant (``params``) along the true motion (``kin``: its true kinematics, made when None)."""
    kin = R.true_kinematics(g) if kin is None else kin
    return np.asarray(g.true["torque"], float) - _predict_along(kin, params)


def baseline_jacobian(kin, params: dict, h: float = 1e-4) -> np.ndarray:
    """The baseline's prediction along ``kin`` differentiated in its log-parameters ``PARAMS`` at
    ``params`` (central differences of step ``h``; samples x parameters)."""
    cols = []
    for k in PARAMS:
        up, dn = dict(params), dict(params)
        up[k], dn[k] = params[k] * np.exp(h), params[k] * np.exp(-h)
        cols.append((_predict_along(kin, up) - _predict_along(kin, dn)) / (2.0 * h))
    return np.column_stack(cols)


def column_basis(J: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the columns of ``J`` (each scaled to unit norm; directions below 1e-8 of
    the largest dropped)."""
    U, s, _ = np.linalg.svd(J / np.maximum(np.linalg.norm(J, axis=0), 1e-300), full_matrices=False)
    return U[:, s > 1e-8 * s[0]]


def oracle(g, params: dict, phi: float, rows=None, train_share: float = 0.8) -> dict:
    """``lam`` and the effect's rms before and after the baseline's directions (over the noise std).
    ``rows``: the training samples (a mask; the diagnosis's kept training samples, as ``run.py``
    passes them); None counts ``train_share`` of every sample."""
    kin = R.true_kinematics(g)
    e = effect_torque(g, params, kin)
    Jb = _whiten(baseline_jacobian(kin, params), phi)
    ew = _whiten(e, phi)
    share = train_share
    if rows is not None:
        Jb, ew, share = Jb[rows], ew[rows], 1.0
    Q = column_basis(Jb)
    left = ew - Q @ (Q.T @ ew)
    sd = g.torque_noise_std
    innovation = sd ** 2 * (1.0 - phi ** 2)
    return {"effect_rms_over_noise": float(np.sqrt(np.mean(e ** 2)) / sd),
            "left_rms_over_noise": float(np.sqrt(np.mean(left ** 2) / innovation)),
            "lam": float(share * np.sum(left ** 2) / innovation)}


def oracle_fitted(g, params: dict, phi: float, train_share: float = 0.8) -> dict:
    """The same noncentrality after the baseline's nonlinear least-squares fit to the noise-free
    torque along the true motion (its seven parameters in log space, from the generator's own, with
    scipy's trust-region solver): what the baseline's family absorbs with exact kinematics and no
    noise, which its Jacobian at the true parameters understates (a Stribeck exponent's change,
    taken up by a moved ``Fs`` and ``vs``). ``lam_fitted`` bounds any test on a fitted baseline's
    residual from above; the fitted parameters go with it."""
    from scipy.optimize import least_squares

    kin = R.true_kinematics(g)
    tau = np.asarray(g.true["torque"], float)
    x0 = np.log([params[k] for k in PARAMS])

    def model(x):
        return params | dict(zip(PARAMS, np.exp(x).tolist())) | {"offset": 0.0}

    def res(x):
        return _whiten(tau - np.asarray(predict(baseline_from_params(model(x)), kin), float), phi)

    with warnings.catch_warnings():
        # the fit's path may cross non-passive parameter sets: a least-squares bound, not a plant
        warnings.simplefilter("ignore", NonPassiveWarning)
        fit = least_squares(res, x0, method="trf", diff_step=1e-4, xtol=1e-10, ftol=1e-12, max_nfev=200)
    left = fit.fun
    innovation = g.torque_noise_std ** 2 * (1.0 - phi ** 2)
    return {"lam_fitted": float(train_share * np.sum(left ** 2) / innovation),
            "fitted_params": {k: float(v) for k, v in zip(PARAMS, np.exp(fit.x))}}


def tally(studies: list[str], power: float = 0.9, key: str = "oracle_power", kept: bool = False) -> None:
    """Over the studies' written oracle rows with ``key`` (``oracle_power``, or
    ``oracle_power_fitted`` where the rows have it) at least ``power``: how many the diagnosis got
    exactly right (their ``runs_<study>.jsonl``), and the misses. ``kept``: the power is also held
    to the run row's ``oracle_lam_kept`` (the smaller of the two): what a test could see on the
    samples whose kinematics the recording resolves. Prints the summed power too (the oracle's
    expected number of rows found)."""
    res = Path(__file__).resolve().with_name("results")
    hit = n = 0
    expected = 0.0
    for study in studies:
        runs = {d["key"]: d for d in load(res / study / f"runs_{study}.jsonl")}
        for o in map(json.loads, (res / study / f"oracle_{study}.jsonl").read_text().splitlines()):
            run = runs.get(o["key"])
            if key not in o or run is None:
                continue
            p = o[key]
            if kept and run.get("oracle_lam_kept") is not None:
                p = min(p, float(power_at(run["oracle_lam_kept"])))
            expected += p
            if p >= power:
                n += 1
                hit += bool(run["correct"])
                if not run["correct"]:
                    print(f"missed: {o['key']} (power {p:.2f}, verdict {run['verdict']})")
    what = key + (" and oracle_lam_kept" if kept else "")
    print(f"rows an oracle finds with power >= {power} ({what}): {hit} of {n} exactly right; "
          f"the oracle's expected count {expected:.1f}")


def main() -> None:
    if "--tally" in sys.argv:  # python oracle_power.py --tally outside10,outside11 [--fitted] [--kept]
        return tally(sys.argv[sys.argv.index("--tally") + 1].split(","),
                     key="oracle_power_fitted" if "--fitted" in sys.argv else "oracle_power",
                     kept="--kept" in sys.argv)
    a, res, out = R.study_cli(__doc__,
                              ("--kept", {"action": "store_true", "help": "also over the samples the diagnosis keeps"}),
                              ("--only", {"default": "", "help": "comma-separated keys (default: every effect row)"}))
    runs = {}
    if (res / f"runs_{a.study}.jsonl").exists():
        runs = {d["key"]: d for d in map(json.loads, (res / f"runs_{a.study}.jsonl").read_text().splitlines())}
    lines, total, total_fitted, rows = [], 0.0, 0.0, 0
    for job in R.SETTINGS[a.study]():
        if job.get("expected", "none") == "none" or (a.only and job["key"] not in a.only.split(",")):
            continue
        g, _ = R.generated(job, Path(a.cache) if a.cache else res / "cache")
        row = {"key": job["key"], "expected": job["expected"], "torque_noise_ar": job["torque_noise_ar"]}
        params, phi = R.true_params(job), float(job["torque_noise_ar"])
        row |= oracle(g, params, phi)
        row["oracle_power"] = float(power_at(row["lam"]))
        row |= oracle_fitted(g, params, phi)
        row["oracle_power_fitted"] = float(power_at(row["lam_fitted"]))
        row["verdict"] = runs.get(job["key"], {}).get("verdict")
        if a.kept:
            rep = diagnose(g.to_recording(), progress=False)
            r0, val = np.asarray(rep.arrays.r0), np.asarray(rep.arrays.val)
            kept = (r0 != 0) & ~val  # the training samples the fit kept (left-out samples carry r0 = 0)
            row["n_kept"], row["lam_kept"] = int(kept.sum()), oracle(g, params, phi, rows=kept)["lam"]
            row["oracle_power_kept"] = float(power_at(row["lam_kept"]))
            # the fixed held-out phase, which confirms an attribution term: a fifth of the information
            row["n_val"], row["lam_val"] = int(val.sum()), oracle(g, params, phi, rows=val)["lam"]
            row["verdict_now"] = rep.verdict
        total += row["oracle_power"]
        total_fitted += row["oracle_power_fitted"]
        rows += 1
        lines.append(json.dumps(row))
        more = (f" kept: lam {row['lam_kept']:.1f} power {row['oracle_power_kept']:.2f}, held-out phase lam "
                f"{row['lam_val']:.1f}, verdict now {row['verdict_now']}" if a.kept else "")
        print(f"{job['key']:48s} effect {row['effect_rms_over_noise']:.3f} left {row['left_rms_over_noise']:.3f} "
              f"lam {row['lam']:8.1f} oracle power {row['oracle_power']:.2f} fitted: lam {row['lam_fitted']:8.1f} power "
              f"{row['oracle_power_fitted']:.2f} verdict {row['verdict']}{more}",
              flush=True)
    (out / f"oracle_{'kept_' if a.kept else ''}{a.study}.jsonl").write_text("\n".join(lines) + "\n")
    print(f"oracle: {total:.1f} of {rows} expected named (after the baseline's nonlinear fit: {total_fitted:.1f})")


if __name__ == "__main__":
    main()
