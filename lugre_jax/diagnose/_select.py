"""Name the missing physics: score candidates on the located residual, refit jointly, select greedily.

Pipeline (the joint model and friction are those of Li et al., Electronics 2020, 9, 284):

1. fit the baseline (inverse LuGre joint model) by Levenberg-Marquardt on the training blocks;
2. :func:`~lugre_jax.diagnose._locate.locate` the residual (Holm-controlled family of tests);
   if nothing is located the verdict is ``none`` and no physics is claimed;
3. otherwise score every applicable candidate on the located residual: of its multi-start guesses
   (e.g. the position-periodogram peaks for a ripple), keep the one whose torque projects best
   onto the residual; that projected drop of the residual sum of squares is its score;
4. refit the best ``top_k`` (default 4) JOINTLY with the baseline by LM -- jointly, because
   friction parameters trade off against the new physics (e.g. Fs, vs against the Stribeck
   exponent); accept the candidate with the largest BIC drop
   BIC if (a) BIC decreases, computed with the effective sample size N/kappa (kappa: long-run
   variance factor of the candidate model's residual) so that autocorrelated noise does not
   inflate the evidence, and (b) the held-out error decreases significantly, cross-validated
   over the five phases of the interleaved time blocks (each phase's samples predicted by refits
   of the candidate model and of the current one that left that phase out; one-sided test of the
   squared-error drop, noise variance estimated cluster-robustly over the blocks, p < alpha);
5. repeat from 2 on the new residual (greedy forward selection) until nothing is located or no
   candidate is accepted; structure that remains located is reported as ``unexplained``.
"""

from __future__ import annotations

import dataclasses
import time

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from scipy import stats

from . import _locate as L
from . import _model as M
from ..friction import LuGre
from ._physics import CANDIDATES
from ._report import Baseline, Diagnosis, DiagnosisArrays, Finding, Improved, RecordingInfo, Region


def _friction(model, kin) -> np.ndarray:
    """The model's friction torque per sample (the friction-trend test's regressor)."""
    return np.asarray(M._parts(model, kin)[1])


def _ctx(rec, model, kin, r, loc, scales, n_rev, extra=None):
    inertial, F, _ = (np.asarray(x) for x in M._parts(model, kin))
    return {**(extra or {}),"rec": rec, "kin": kin, "baseline": model, "residual": r, "scales": scales, "units": rec.units,
            "position_peaks": loc["position_periodogram"]["peaks"],
            "time_peak_hz": loc["time_periodogram"]["frequency"], "friction_torque": F,
            "inertial_torque": inertial, "n_reversals": n_rev,
            "to_rad": np.pi / 180 if rec.units.get("position") == "deg" else 1.0}


MIN_RESOLVED = 100  # resolved training samples a baseline fit needs (about ten parameters)
AT_FLOOR = 1.1  # validation RMSE / estimated floor at or below which the baseline counts as at its floor


def _mismatch(loc: dict, at_floor: bool) -> dict:
    """What counts as located. Whiteness alone locates nothing: at the floor, residual colour is
    the conditioning's (smoothed kinematics' noise, errors in variables), not missing physics, so it
    counts only when the baseline is also above its floor; structural tests always count."""
    if at_floor:
        loc = dict(loc, located=list(loc["structural"]))
    return loc


def _eiv_noise(rec_in, cond, model, kin, path, keep, draws: int = 3) -> tuple[float, np.ndarray]:
    """Per-sample torque error that the kinematics' errors carry into the inverse model (errors in
    variables), rms over the resolved samples and ``draws`` draws of
    :func:`._condition.perturbed_kinematics`: J*a, the friction's slope, the bristles' rate
    dependence and their path, all through the fitted model.

    Also returns the per-sample mean of those errors over the draws (0 where not resolved): the
    model is nonlinear (the friction's fall at low speed), so the errors do not average out, and
    the residual of a correct model keeps about minus this mean wherever its regions average."""
    from ._condition import perturbed_kinematics

    def as_kin(x):
        v, a, th = (jnp.asarray(y, float) for y in x)
        return eqx.tree_at(lambda k: (k.v, k.a, k.theta, k.dpath), kin, (v, a, th, jnp.diff(th)))

    ms, mean = [], np.zeros(keep.shape)
    for seed in range(draws):
        syn, ref = perturbed_kinematics(rec_in, cond, path, seed)
        d = np.asarray(M.predict(model, as_kin(syn)) - M.predict(model, as_kin(ref)))
        ms.append(float(np.mean(d[keep] ** 2)) if np.any(keep) else 0.0)
        mean += np.where(keep, d, 0.0) / draws
    return float(np.sqrt(np.mean(ms))), mean


def _sse(r, w):
    return float(np.sum(w * r ** 2))


def _val_rmse(r, val):
    return float(np.sqrt(np.mean(r[val] ** 2)))


def _paired_block_test(r0, r1, blocks, val):
    """One-sided p-value that the new model lowers the held-out squared error.

    ``d = sum_val(r0^2 - r1^2)`` with ``r0 - r1 = Delta`` (the change of prediction, fixed by the
    training data). If the new physics is not real, ``r1 = noise - Delta`` and ``d = sum(2*noise*Delta
    - Delta^2)``: mean <= 0, variance ``4*var(sum noise*Delta)``, estimated cluster-robustly over the
    validation time blocks (so autocorrelated noise is allowed) and never below the iid value. z = d/sd is referred to N(0, 1).
    This is far more powerful than a t-test on block totals when the effect lives in few blocks.
    """
    delta = (r0 - r1)[val]
    d = float(np.sum(r0[val] ** 2 - r1[val] ** 2))
    _, inv = np.unique(blocks[val], return_inverse=True)
    sb = np.bincount(inv, weights=r1[val] * delta)
    # cluster-robust (autocorrelation) or iid, whichever is larger: with the effect in few blocks the
    # cluster estimate alone is biased low (few effective clusters)
    sd_iid = 2.0 * float(np.std(r1[val]) * np.sqrt(np.sum(delta ** 2)))
    sd = max(2.0 * float(np.sqrt(np.sum(sb ** 2))), sd_iid)
    if sd == 0:
        return 1.0 if d <= 0 else 0.0
    return float(stats.norm.sf(d / sd))


def _cross_validated(model, specs, kin, tau, keep, blocks, fixed_phase, folds, max_steps) -> np.ndarray:
    """Residual of ``model`` (fitted without the held-out phase ``fixed_phase``) on the resolved
    samples of the block phases ``folds``, each predicted by a fit that did not see it: the model
    is refitted (warm-started, by LM) without each other phase in turn, and each phase's samples
    take the residual of the fit that left them out; 0 elsewhere. Several phases, not
    one, because an excitation whose period is a multiple of five blocks shows one phase only the
    same part of every period (a staircase's dwell middles, never its transitions); not a phase
    that holds most of some kind of event, whose refit would not see it (a 10-s staircase's steps
    all start a block of phase 0: without them the inertia is free)."""
    out = np.zeros(keep.shape)
    phase = blocks % M.VALIDATION_EVERY
    for j in folds:
        fold = keep & (phase == j)
        fitted = model
        if j != fixed_phase and specs:
            space = M.FitSpace(specs)
            fitted, _ = M.fit(M.clip_into(space, model), space, kin, tau, (keep & ~fold).astype(float),
                              max_steps=max_steps)
        e = np.asarray(tau - M.predict(fitted, kin))
        if not np.all(np.isfinite(e[fold])):  # a failed refit is infinitely bad, never a silent NaN
            e = np.full(e.shape, np.inf)
        out[fold] = e[fold]
    return out


def _identifiability(model, space, kin, tau, w, kappa, cand) -> float:
    """Largest |value - null| / standard error over the candidate's key parameters (joint fit)."""
    try:
        se = M.standard_errors(model, space, kin, tau, w, kappa)
    except Exception:  # noqa: BLE001 - a failed Jacobian means "not shown identifiable"
        return 0.0
    z = 0.0
    for name, null in type(cand).key_params.items():
        key = f"{cand.id}.{name}"
        if key in se:
            v, e = se[key]
            if np.isfinite(e) and e > 0:
                z = max(z, abs(v - null) / e)
    return z


def _bic(sse, n_eff_factor, n, k):
    ne = n / n_eff_factor
    return ne * np.log(sse / n) + k * np.log(ne)


def _all_specs(model, scales, fit_offset, freeze_baseline=False):
    specs = [] if freeze_baseline else M.baseline_specs(model, scales, fit_offset)
    for k in range(len(model.candidates)):
        specs += M.candidate_specs(model, k, scales)
    return specs


# the window is chosen again for the fitted inertia, and the baseline refitted, when the first
# window's estimated kinematic torque error exceeds the new one's by this share of the torque noise
# variance (the floor would rise by ~2.5 %)
RECHOOSE_SHARE = 0.05


def fit_baseline(rec, kins, weights, scales, friction="lugre", fit_offset=False, params=None, noise=0.0,
                 rough=None, screen_steps: int = 25, max_steps: int = 200):
    """Multi-start LM fit of the baseline; returns (model, info, index of the kinematics used).

    ``kins``: one or more candidate kinematics of the same recording (bristle paths); every start
    is screened on each. Starts from :func:`~._model.initial_baselines` (data-driven) plus the
    least-squares start; each (start, kinematics) pair is run ``screen_steps`` LM steps, the best
    two by training SSE are run to convergence.
    """
    if params is not None:
        return M.baseline_from_params(params), {"result": "given", "steps": 0, "starts": 0}, 0
    m0 = rough if rough is not None else M.initial_baseline(rec, friction, fit_offset)
    starts = M.initial_baselines(rec, friction, fit_offset, noise, rough=m0)
    if isinstance(m0.friction, LuGre):
        starts.append(m0)
    space = M.FitSpace(M.baseline_specs(starts[0], scales, fit_offset))
    w = np.asarray(weights)
    tau = np.asarray(rec.torque)

    def sse(m, kin):
        e = tau - M.predict(m, kin)
        return float(np.sum(w * e * e)) if np.all(np.isfinite(e)) else np.inf

    screened = []
    many = len(starts) * len(kins) > 1
    for k, kin in enumerate(kins):
        for s0 in starts:
            s0 = M.clip_into(space, s0)
            fitted, _ = M.fit(s0, space, kin, tau, weights, max_steps=screen_steps) if many else (s0, {})
            screened.append((sse(fitted, kin), k, fitted))
    screened.sort(key=lambda x: x[0])
    best = None
    for _, k, s0 in screened[:2]:
        fitted, info = M.fit(s0, space, kins[k], tau, weights, max_steps=max_steps)
        e = sse(fitted, kins[k])
        if best is None or e < best[0]:
            best = (e, fitted, info, k)
    info = dict(best[2])
    info["starts"] = len(starts)
    return best[1], info, best[3]


def diagnose(rec, params: dict | None = None, friction: str = "lugre", fit_offset: bool = False,
             alpha: float = 0.05, top_k: int | None = 4, max_effects: int = 3, candidates=None,
             progress: bool = True, block_s: float | None = None, max_steps: int = 80) -> Diagnosis:
    """Diagnose a :class:`~lugre_jax.io.Recording`; returns a :class:`~._report.Diagnosis`
    (``to_json()``: the REPORT.json content; ``arrays``: residuals, models and tests behind it).

    ``params``: baseline parameters to use instead of fitting (REPORT ``baseline.params`` format).
    ``friction``: baseline friction law, ``lugre`` (default), ``stribeck`` or ``coulomb_viscous``.
    ``fit_offset``: include a constant torque offset in the baseline (the EMPS benchmark does).

    Before fitting, the kinematics are conditioned from the data (:func:`._condition.condition`:
    velocity column or position, Savitzky-Golay window from the estimated noise and bias; bristles
    driven along the position path) and samples inside unresolved sharp transients are left out.
    The result's ``baseline`` (:class:`~._report.Baseline`) has ``noise_floor_nm`` (per-sample
    noise estimated from the data), ``floor_ratio`` (validation RMSE / floor), ``at_floor`` (ratio
    <= 1.1), ``shortcoming``, ``torque_noise_nm`` and ``kinematic_noise_nm`` (its two parts: the
    floor of an inverse model includes the noise the conditioned velocity and acceleration carry),
    ``conditioning`` and ``unresolved_transient_fraction``; each joint refit in ``selection_log``
    adds ``identifiability_z`` and ``rejected_because`` (a candidate is named only if plausible and
    identifiable on the recording, see docs/diagnosis.md).
    """
    from tqdm.auto import tqdm

    from ._condition import condition

    t_start = time.time()
    rough = M.initial_baseline(rec, friction, fit_offset)
    crec, cond, unresolved = condition(rec, float(rough.J), float(getattr(rough.friction, "sigma2", 0.0)))
    # the first least-squares inertia comes from the loader's raw derivatives; where they are noisy
    # (a differentiated encoder) errors in variables shrink it toward zero, and the window chosen
    # for that inertia is too long: estimate it again on the conditioned kinematics and re-choose
    rough2 = M.initial_baseline(crec, friction, fit_offset)
    if not 0.8 <= float(rough2.J) / max(float(rough.J), 1e-300) <= 1.25:
        rough = rough2
        crec, cond, unresolved = condition(rec, float(rough.J), float(getattr(rough.friction, "sigma2", 0.0)))
    rec_in = rec
    rechosen = None
    # the window is chosen for an inertia; the first comes from a linear fit, which friction with
    # bristle dynamics can throw far off (a multisine through zero speed: J < 0, clipped), so the
    # fitted inertia chooses again, and a different window is fitted again (once)
    for second in (False, True):
        if not cond.position_measured:
            # the path is the integral of the velocity: across a transient the sampling does not
            # resolve, that integral is wrong by an unknown step, which the bristles keep until they
            # have travelled a few relaxation lengths (pre-sliding travel, from the data)
            from ._condition import forget_after

            unresolved = forget_after(unresolved, crec.position,
                                      3.0 * M.presliding_displacement(crec, float(rough.friction.Fs))
                                      if hasattr(rough.friction, "Fs") else 0.0)
        rec = crec
        kin = M.kinematics_of(rec)
        # memory of the conditioning: a Savitzky-Golay window W, then a central difference for the jerk.
        # A quantised position's error is correlated for as long as the joint takes to cross a step,
        # seconds at slow speed, and the bristles carry it further: with derivatives of a quantised
        # position the cross-correlations with acceleration and jerk have no null distribution we can
        # bound from the data, so they are not run (flags past their largest lag, 0.5 s)
        flags = cond.window + 2 if cond.source != "recording" else 0
        if cond.source == "position" and cond.quantisation > 0:
            flags = int(round(0.5 / rec.dt)) + 1
        scales = M.data_scales(rec)
        blocks = M.block_ids(rec.time, block_s)
        # unresolved transients take no part: not in the fit, the validation or the tests
        keep = ~unresolved
        since, direction, n_rev = L.reversal_info(rec.time, rec.velocity, scales["V"])
        # the held-out phase: the fixed one unless it would take most of the reversals or of the bursts
        # of acceleration (an excitation periodic in five blocks) away from the fit
        events = [keep & (since == 0),
                  M.event_starts(keep & (np.abs(np.asarray(rec.acceleration)) > M.BIG_ACCELERATION * scales["A"]))]
        phase = M.validation_phase(blocks, events)
        val = M.validation_mask(blocks, phase=phase) & keep
        # the phases a candidate's cross-validated test uses: those whose refit still sees every kind of event
        folds = [j for j, h in enumerate(M.phases_holding_events(blocks, events)[1]) if not h or j == phase]
        cv_mask = keep & np.isin(blocks % M.VALIDATION_EVERY, folds)
        w = ((~val) & keep).astype(float)
        tau = np.asarray(rec.torque)
        n_train = int(w.sum())
        if n_train < MIN_RESOLVED or int(val.sum()) < MIN_RESOLVED // 4:
            raise ValueError(
                f"{rec.source}: only {int(keep.sum())} of {rec.n} samples have kinematics resolved at this "
                f"sampling and noise ({cond.source}, window {cond.window}); expected at least {MIN_RESOLVED} "
                "for the fit and a quarter of that held out: a slower or smoother excitation, or a velocity "
                "sensor, is needed")

        # bristle path: the complementary one (conditioned velocity pulled to the position) or, where
        # the position was measured and smoothed, the measured position itself; which is better depends
        # on the encoder step against the bristle stiffness, so the data decide (training SSE)
        paths = {"complementary" if cond.source != "recording" else "measured": kin}
        if cond.source != "recording" and cond.position_measured:
            paths["measured"] = M.kinematics_of(eqx.tree_at(lambda r: r.position, rec, np.asarray(rec_in.position)))
        base, info, k_path = fit_baseline(rec, list(paths.values()), w, scales, friction, fit_offset, params,
                                          noise=cond.torque_noise)
        path = list(paths)[k_path]
        kin = paths[path]
        info["bristle_path"] = path
        if second or params is not None:
            break
        J_fit, s2_fit = float(base.J), float(getattr(base.friction, "sigma2", 0.0))
        if cond.source == "recording" or 0.8 <= J_fit / max(float(rough.J), 1e-300) <= 1.25:
            break
        crec2, cond2, unresolved2 = condition(rec_in, J_fit, s2_fit)
        if (cond2.source, cond2.window, cond2.order) == (cond.source, cond.window, cond.order):
            break
        # refitted only if the fitted inertia's window is better by a share of the torque noise
        # variance that matters, not for the small shifts of window a small change of J brings
        mse_old = condition(rec_in, J_fit, s2_fit, choices=[(cond.source, cond.window, cond.order)], error_only=True)
        mse_new = condition(rec_in, J_fit, s2_fit, choices=[(cond2.source, cond2.window, cond2.order)], error_only=True)
        if mse_old - mse_new <= RECHOOSE_SHARE * cond.torque_noise ** 2:
            break
        rechosen = {"source": cond.source, "window": cond.window, "order": cond.order, "inertia": float(rough.J),
                    "excess_error_nm": float(np.sqrt(mse_old - mse_new))}
        crec, cond, unresolved = crec2, cond2, unresolved2
    if rechosen is not None:
        info["window_rechosen_from"] = rechosen
    tau_base = M.predict(base, kin)
    r0 = (tau - tau_base) * keep
    # the floor of an inverse model: the torque noise and what the kinematics' noise brings through
    # the fitted model (errors in variables), both estimated from the data
    kin_noise, eiv_bias = _eiv_noise(rec_in, cond, base, kin, path, keep)
    rec = eqx.tree_at(lambda r: r.extra, rec, {
        **rec.extra, "eiv_bias_nm": eiv_bias,
        "static_basis": M.static_curve_basis(base, M.baseline_specs(base, scales, fit_offset),
                                             np.asarray(rec.velocity))})
    # least squares on a noisy acceleration attenuates J by lam = var(a_true)/var(a_measured); the
    # best predictor then also misses (1 - lam)*J*a_true, so its errors-in-variables variance is
    # that of J_fit*noise over lam, and its residual keeps a share of the acceleration beyond the
    # filter's memory, which the cross-correlation tests must expect (rec.extra, see locate)
    a_m = np.asarray(rec.acceleration)
    lam = 1.0
    if cond.source != "recording" and np.any(w > 0):
        va = float(np.var(a_m[w > 0]))
        lam = float(np.clip(1.0 - cond.accel_noise ** 2 / va, 0.2, 1.0)) if va > 0 else 1.0
    if lam < 1.0:
        kin_noise = float(np.hypot(kin_noise, float(base.J) * cond.accel_noise * np.sqrt(1.0 / lam - 1.0)))
        rec = eqx.tree_at(lambda r: r.extra, rec, {**rec.extra,
                                                 "eiv_inertial_nm": (1.0 / lam - 1.0) * float(base.J) * a_m})
    info["acceleration_attenuation"] = lam
    scales["acceleration_attenuation"] = lam
    floor = float(np.hypot(cond.torque_noise, kin_noise))
    ratio = _val_rmse(r0, val) / floor if floor > 0 else float("inf")
    scales["noise"] = floor  # the tests' resolution margins are shares of the per-sample floor
    loc0 = _mismatch(L.locate(rec, r0, blocks, scales, alpha, flags, keep, _friction(base, kin)), ratio <= AT_FLOOR)
    kappa = loc0["kappa"]
    k0 = len(M.baseline_specs(base, scales, fit_offset)) if params is None else 0
    recording = RecordingInfo(
        source=rec.source, n_samples=rec.n, units=rec.units, duration=scales["D"], sample_rate_hz=scales["fs"],
        validation="every 5th time block of ~%.3g %s held out, phase %d (%d of %d samples); a candidate's "
                   "held-out test crosses phases %s"
                   % (float(np.diff(rec.time[blocks == 1][[0, -1]])[0]) if np.any(blocks == 1) else 0,
                      rec.units["time"], phase, int(val.sum()), rec.n, ", ".join(map(str, folds))))
    baseline = Baseline(
        params=M.model_params(base), rmse_nm=float(np.sqrt(np.mean(r0[w > 0] ** 2))),
        validation_rmse_nm=_val_rmse(r0, val), fit=info, noise_floor_nm=floor, torque_noise_nm=cond.torque_noise,
        kinematic_noise_nm=kin_noise, floor_ratio=ratio, at_floor=bool(ratio <= AT_FLOOR),
        shortcoming=None if ratio <= AT_FLOOR else (
            f"the baseline's validation RMSE is {ratio:.3g}x the estimated noise floor: located "
            "structure may be the baseline's own misfit, not missing physics"
            + ("; the torque noise's profile still rises at its longest lag (colour longer than it "
               "reaches, or the signal), so the floor may be only a lower bound"
               if cond.torque_noise_open else "")),
        conditioning=cond.to_json(), unresolved_transient_fraction=float(unresolved.mean()))
    cext = {"position_resolution": max(cond.quantisation, cond.position_noise),
            "accel_bandwidth_hz": _sg_bandwidth(cond.window, scales["fs"], cond.order) if cond.source != "recording"
            else 0.25 * scales["fs"]}
    current, r_cur, loc_cur, k_cur = base, r0, loc0, k0
    accepted, steps_log = [], []
    sse_cur = _sse(r_cur, w)
    pool = dict(CANDIDATES) if candidates is None else {c: CANDIDATES[c] for c in candidates}
    while loc_cur["located"] and len(accepted) < max_effects:
        ctx = _ctx(rec, current, kin, r_cur, loc_cur, scales, n_rev, cext)
        r_cur_cv = None  # the current model's cross-validated residual, made once a trial needs it
        scored = []
        names = [n for n in pool if n not in [a.name for a in accepted]]
        it = tqdm(names, desc=f"score candidates (step {len(accepted) + 1})", disable=not progress, leave=False)
        for name in it:
            proto = pool[name]
            inst = _Proto.get(proto)
            guesses = inst.initial_guesses(ctx) if inst.applicable(ctx) else []
            if not guesses:
                continue
            best = None
            for g in guesses:
                trial = M.JointModel(current.J, current.friction, current.offset, current.candidates + (g,))
                e = M.predict(trial, kin) - (tau - r_cur)
                if not np.all(np.isfinite(e)):
                    continue
                ee = float(np.sum(w * e * e))
                er = float(np.sum(w * e * r_cur))
                # signed: a guess anti-aligned with the residual is a bad start, not a good one
                proj = np.sign(er) * er ** 2 / ee if ee > 0 else 0.0
                if best is None or proj > best[0]:
                    best = (proj, trial)
            if best is None:
                continue
            scored.append({"name": name, "model": best[1], "score": best[0]})
        scored.sort(key=lambda s: -s["score"])
        trials = []
        for s in tqdm(scored[:top_k], desc=f"joint refits (step {len(accepted) + 1})", disable=not progress,
                      leave=False):
            space = M.FitSpace(_all_specs(s["model"], scales, fit_offset, freeze_baseline=params is not None))
            model = M.clip_into(space, s["model"])
            fitted, finfo = M.fit(model, space, kin, tau, w, max_steps=max_steps)
            r1 = (tau - M.predict(fitted, kin)) * keep
            r_start = (tau - M.predict(model, kin)) * keep
            if not np.all(np.isfinite(r1)) or _sse(r1, w) > _sse(r_start, w):
                fitted, r1 = model, r_start
            k1 = len(space.specs) if params is None else k_cur + len(M.candidate_specs(fitted, len(fitted.candidates) - 1, scales))
            sse1 = _sse(r1, w)
            # the effective sample size uses the NEW residual's autocorrelation: the old residual
            # still contains the effect, whose structure is not noise
            kap1 = L.long_run_variance_factor(r1, blocks)
            bic1 = _bic(sse1, kap1, n_train, k1)
            dbic = bic1 - _bic(sse_cur, kap1, n_train, k_cur)
            cand = fitted.candidates[-1]
            why = cand.implausible(ctx | {"baseline": fitted})
            zmax = _identifiability(fitted, space, kin, tau, w, kap1, cand)
            if why is None and not zmax >= 3.0:
                why = (f"not identifiable on this excitation: its parameters are within "
                       f"{zmax:.2g} standard errors of no effect")
            # the held-out test, cross-validated over the five block phases; only for a trial that
            # passed everything else (four refits each, of the trial and once per step of the model)
            p_val = cv_cur = cv1 = None
            if dbic < 0 and why is None:
                if r_cur_cv is None:
                    r_cur_cv = _cross_validated(current, _all_specs(current, scales, fit_offset, params is not None),
                                                kin, tau, keep, blocks, phase, folds, max_steps)
                r1_cv = _cross_validated(fitted, space.specs, kin, tau, keep, blocks, phase, folds, max_steps)
                p_val = _paired_block_test(r_cur_cv, r1_cv, blocks, cv_mask) if np.all(np.isfinite(r1_cv)) else 1.0
                cv_cur, cv1 = _val_rmse(r_cur_cv, cv_mask), _val_rmse(r1_cv, cv_mask)
            trials.append({"name": s["name"], "model": fitted, "r": r1, "k": k1, "sse": sse1, "bic": bic1,
                           "delta_bic": dbic, "kappa": kap1, "p_validation": p_val,
                           "p_fixed_phase": _paired_block_test(r_cur, r1, blocks, val),
                           "validation_rmse_nm": _val_rmse(r1, val), "cv_rmse_nm": cv1, "cv_rmse_before_nm": cv_cur,
                           "fit": finfo, "identifiability_z": zmax, "rejected_because": why})
        steps_log.append({
            "step": len(accepted) + 1,
            "scores": [{"name": s["name"], "projected_sse_reduction": s["score"]} for s in scored],
            "joint_refits": [{k: t[k] for k in ("name", "delta_bic", "p_validation", "p_fixed_phase",
                                                 "validation_rmse_nm", "cv_rmse_nm", "cv_rmse_before_nm",
                                                 "identifiability_z", "rejected_because")}
                             for t in trials]})
        ok = [t for t in trials if t["p_validation"] is not None and t["p_validation"] < alpha
              and t["cv_rmse_nm"] < t["cv_rmse_before_nm"]]
        if not ok:
            break
        best = min(ok, key=lambda t: t["delta_bic"])
        cand = best["model"].candidates[-1]
        accepted.append(Finding(name=best["name"], explanation=type(cand).explanation,
                                params=cand.describe(ctx | {"baseline": best["model"]}),
                                validation_rmse_nm=best["validation_rmse_nm"],
                                delta_bic=best["delta_bic"], p_validation=best["p_validation"]))
        current, r_cur, k_cur = best["model"], best["r"], best["k"]
        sse_cur = best["sse"]
        loc_cur = _mismatch(L.locate(rec, r_cur, blocks, scales, alpha, flags, keep,
                                     _friction(current, kin)),
                            _val_rmse(r_cur, val) <= AT_FLOOR * floor)

    located = tuple(Region.from_test(x) for x in loc0["located"])
    remaining = tuple(Region.from_test(x) for x in loc_cur["located"]) if accepted else located
    # every later step refits the earlier findings jointly with the new one: a finding's parameters
    # are those of the final joint model (the values at its own step carry what it absorbed of the
    # effects not yet in the model, e.g. a ripple taking part of a torque offset where the joint
    # dwells); its evidence (delta_bic, p_validation, validation RMSE) stays that of its step
    ctx_final = _ctx(rec, current, kin, r_cur, loc_cur, scales, n_rev)
    missing = [dataclasses.replace(a, params=c.describe(ctx_final))
               for a, c in zip(accepted, current.candidates, strict=True)]
    if remaining:
        missing.append(Finding(name="unexplained",
                               explanation="Residual structure remains where listed, and no candidate in the "
                                           "library explains it with a validated improvement.",
                               params={"regions": [x.to_json() for x in remaining[:10]]},
                               validation_rmse_nm=_val_rmse(r_cur, val)))
    verdict = "none" if not located else ("+".join(a.name for a in accepted) if accepted else "unexplained")
    if accepted and remaining:
        verdict += "+unexplained"
    improved = Improved(
        params={**M.model_params(current),
                **{c.id: c.describe(ctx_final) for c in current.candidates}},
        rmse_nm=float(np.sqrt(np.mean(r_cur[~val] ** 2))), validation_rmse_nm=_val_rmse(r_cur, val))
    arrays = DiagnosisArrays(rec=rec, kin=kin, baseline_model=base, improved_model=current, r0=r0, r1=r_cur,
                             val=val, blocks=blocks, loc0=loc0, loc1=loc_cur)
    return Diagnosis(recording=recording, baseline=baseline, alpha=alpha, kappa_long_run_variance=kappa,
                     verdict=verdict, mismatch=located, n_tests=loc0["n_tests"], missing_physics=tuple(missing),
                     improved=improved, selection_log=steps_log, seconds=time.time() - t_start, arrays=arrays)


def _sg_bandwidth(W: int, fs: float, order: int = 3) -> float:
    """-3 dB frequency [Hz] of the Savitzky-Golay derivative of window W (Schafer 2011:
    f_c ~ (order + 1)/(3.2 W - 4.6) * fs/2 for the smoother; used as the bandwidth of the acceleration)."""
    return float((order + 1) / (3.2 * W - 4.6) * fs / 2)


class _Proto:
    """Prototype instances (default parameters) for calling the candidates' guess methods."""

    _cache: dict = {}

    @classmethod
    def get(cls, klass):
        if klass not in cls._cache:
            kw = {}
            for f in dataclasses.fields(klass):
                if "rel_bounds" in f.metadata:
                    kw[f.name] = 1.0
            cls._cache[klass] = klass(**kw)
        return cls._cache[klass]

