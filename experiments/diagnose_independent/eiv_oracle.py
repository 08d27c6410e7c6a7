"""What an oracle could name once the kinematics' errors are counted: per effect row of a study, the
part of the true effect that the diagnosis's own fitted baseline leaves (the noise-free torque less
that baseline's prediction along the true motion), over the training samples the diagnosis keeps
(resolved, outside the held-out phase), made orthogonal to the baseline's Jacobian on the
conditioned kinematics, as a one-column test along the effect's own direction ``x``:

* ``lam_kept_fitted``: its noncentrality against the torque noise alone (AR(1)-whitened where the
  noise is coloured). The naming test also takes the floor's nuisance shapes out, which this
  leaves in: an upper bound;
* ``kinematic_var``: the variance the kinematics' errors add along ``x``, over the torque noise's
  (the mean of ``(x . d)^2`` over the null's kinematic draws ``d``, ``DiagnosisArrays.kinematic_errors``:
  centred and scaled as the naming test uses them), so that the test's statistic has
  ``1 + kinematic_var`` times the torque noise's variance under the null;
* ``lam_eiv`` = ``lam_kept_fitted / (1 + kinematic_var)`` and its power at the naming test's level
  (``oracle_power.power_at``): the bound with the measurement chain's kinematic errors as noise;
* ``effect_z`` and ``kinematic_z``: on this recording, the effect's and the realised kinematic
  error's projections on ``x`` (the fitted baseline's prediction along the true motion less that
  along the conditioned kinematics), over the torque noise std.

Each row is diagnosed once (minutes). Writes <out>/eiv_oracle_<study>.jsonl and prints a line a row.

    python experiments/diagnose_independent/eiv_oracle.py --study fresh52 --only fresh52_effect13_stribeck_shape_d
"""

from __future__ import annotations

import numpy as np

import run as R
from lugre_jax.diagnose import diagnose
from oracle_power import PARAMS, _predict_along, _whiten, baseline_jacobian, column_basis, power_at


def evidence(job, cache) -> dict:
    g, _ = R.generated(job, cache)
    rep = diagnose(g.to_recording(), progress=False)
    A = rep.arrays
    rows = np.asarray(A.keep, bool) & ~np.asarray(A.val, bool)
    phi = float(job.get("torque_noise_ar") or 0.0)
    innovation = g.torque_noise_std ** 2 * (1.0 - phi ** 2)
    # the diagnosis fits no offset by default: the baseline's prediction without one is its own
    fitted = {k: float(rep.baseline.params[k]) for k in PARAMS} | {"delta": 2.0}
    kin_true, kin_c = R.true_kinematics(g), A.kin
    jac = _whiten(baseline_jacobian(kin_c, fitted), phi)[rows]
    p_true = _predict_along(kin_true, fitted)
    effect = _whiten(np.asarray(g.true["torque"], float) - p_true, phi)[rows]
    realised = _whiten(p_true - _predict_along(kin_c, fitted), phi)[rows]

    def perp(Q, x):
        return x - Q @ (Q.T @ x)

    Q = column_basis(jac)
    e = perp(Q, effect)
    lam = float(e @ e / innovation)
    x = e / max(np.linalg.norm(e), 1e-300)
    draws = np.zeros((0, rows.size)) if A.kinematic_errors is None else np.asarray(A.kinematic_errors, float)
    kv = 0.0
    if draws.size:
        proj = np.array([x @ perp(Q, _whiten(d, phi)[rows]) for d in draws])
        kv = float(np.mean(proj ** 2) / innovation)
    lam_eiv = lam / (1.0 + kv)
    return {"key": job["key"], "expected": job["expected"], "verdict": rep.verdict,
            "lam_kept_fitted": lam, "kinematic_var": kv, "lam_eiv": lam_eiv,
            "oracle_power_kept_fitted": float(power_at(lam)), "oracle_power_eiv": float(power_at(lam_eiv)),
            "effect_z": float(np.sqrt(lam)), "kinematic_z": float(x @ perp(Q, realised) / np.sqrt(innovation))}


def main() -> None:
    R.run_effect_rows(__doc__, "eiv_oracle", evidence, lambda row: (
        f"{row['key']}: {row['verdict']}; lam kept (fitted baseline) {row['lam_kept_fitted']:.1f}, kinematic "
        f"variance x{1 + row['kinematic_var']:.2f} -> {row['lam_eiv']:.1f} (power "
        f"{row['oracle_power_kept_fitted']:.2f} -> {row['oracle_power_eiv']:.2f}); on this row effect "
        f"{row['effect_z']:+.1f}, kinematic error {row['kinematic_z']:+.1f} noise std"))

if __name__ == "__main__":
    main()
