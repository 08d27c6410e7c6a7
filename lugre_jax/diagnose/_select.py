"""The diagnosis pipeline: condition -> fit baseline -> noise model -> locate -> select -> attribute
-> report (the joint model and friction are those of Li et al., Electronics 2020, 9, 284).

1. :func:`_prepare`: condition the kinematics from the data and fit the inverse LuGre joint model
   by Levenberg-Marquardt on the training blocks (:func:`_split`: every fifth time block held out);
2. :func:`_noise` and :func:`_floor`: the torque noise again through the fitted model, the noise floor
   and the null model (torque noise and the kinematics' errors, :mod:`._calibrate`);
3. :func:`~._locate.locate`: residual tests, Holm-controlled at a third of alpha;
4. :func:`_select`: greedy forward selection; at each step every candidate's first-order gain is
   tested against null draws simulated for this recording (min-P, a third of alpha); the most
   significant candidates are refitted jointly with the current model, and the first that is
   plausible and identifiable is named if it lowers the held-out error significantly (one held-out
   test per step, at ``DiagnoseConfig.alpha_confirm``);
5. :func:`_attribute`: what no candidate explains is attributed to a term library (the last third
   of alpha, :mod:`._attribute`);
6. :func:`_report`: the typed :class:`~._report.Diagnosis` (REPORT.json).
"""

from __future__ import annotations

import dataclasses
import time

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from . import _locate as L
from . import _model as M
from ..friction import LuGre
from ._attribute import Rivals, _rms, cancel_words, kinematic_lines, motion_lines, rivals
from ._calibrate import held_out_p, rejects
from ._config import DiagnoseConfig
from ._physics import CANDIDATES
from ._report import Baseline, Diagnosis, DiagnosisArrays, Finding, Improved, RecordingInfo, Region


def _friction(model, kin) -> np.ndarray:
    """The model's friction torque per sample (the friction-trend test's regressor)."""
    return np.asarray(M._parts(model, kin)[1])




def _mismatch(loc: dict, at_floor: bool) -> dict:
    """What counts as located. Whiteness alone locates nothing: at the floor, residual colour is
    the conditioning's (smoothed kinematics' noise, errors in variables), not missing physics, so it
    counts only when the baseline is also above its floor; structural tests always count."""
    if at_floor:
        loc = dict(loc, located=list(loc["structural"]))
    return loc


def _sse(r, w):
    return float(np.sum(w * r ** 2))


def _ms_bound(r, mask, blocks) -> float:
    """Upper bound (two standard errors) of the mean square of ``r`` over the samples ``mask``: the
    standard error from the variance of r^2 and r^2's own long-run factor over the time blocks (a
    residual whose size changes along the motion, as it does at rest, has r^2 far from the Gaussian
    2*sigma^4 variance, and r^2 is less correlated than r). A size that changes from block to block
    counts as spread, so the bound is then conservative (the test beside it)."""
    e2 = np.asarray(r, float)[mask] ** 2
    if e2.size < 2:
        return float(np.mean(e2)) if e2.size else 0.0
    b = np.asarray(blocks)[mask]
    if np.var(e2) <= 0:
        kappa = 1.0
    elif np.unique(b).size < 2:
        kappa = float(e2.size)  # one block: its samples count as one
    else:
        kappa = L.long_run_variance_factor(e2, b)
    return float(np.mean(e2) + 2.0 * np.sqrt(np.var(e2) * kappa / e2.size))


def _cross_validated(model, specs, kin, tau, keep, blocks, fixed_phase, folds, max_steps) -> np.ndarray:
    """Residual of ``model`` (fitted without the held-out phase ``fixed_phase``) on the resolved
    samples of the block phases ``folds``, each predicted by a fit that did not see it: the model
    is refitted (warm-started, by LM) without each other phase in turn, and each phase's samples
    take the residual of the fit that left them out; 0 elsewhere. Several phases, not
    one, because one phase is a fifth of the recording, and where the events are few it may hold
    few of them (a staircase's dwell middles, not its transitions); not a phase that holds most of
    some kind of event, whose refit would not see it (without the steps the inertia is free)."""
    out = np.zeros(keep.shape)
    phase = M.block_phase(blocks)
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


def _identifiability(model, space, kin, tau, w, kappa, cand, lines=None) -> float:
    """Largest |value - null| / standard error over the candidate's key parameters (joint fit);
    for a response linear in the motion, against the kinematic error's ``lines`` fitted alongside.
    A profiled parameter (``AbstractCandidate.profiled``) is held at its profile's value: its
    Jacobian column comes from the few samples where an event moves between samples, no local
    linearisation of a piecewise-flat objective, so the other parameters' errors are conditional
    on it, as the profile that set it (its own evidence is the linear parameter's)."""
    profiled = {path_p for path_p, _ in M.profiled_paths(model).values()}
    space = M.FitSpace([sp for sp in space.specs if sp.path not in profiled])
    try:
        se = M.standard_errors(model, space, kin, tau, w, kappa,
                               nuisance=lines if type(cand).linear_in_motion else None)
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


def _weighted_sse(model, kin, tau, w) -> tuple[float, np.ndarray]:
    """(training SSE with weights ``w``, residual); inf where the prediction is not finite."""
    e = tau - M.predict(model, kin)
    return (_sse(e, w) if np.all(np.isfinite(e)) else np.inf), e


def fit_baseline(rec, kins, weights, scales, friction="lugre", fit_offset=False, params=None, noise=0.0,
                 rough=None, screen_steps: int = 25, max_steps: int = 200, far_starts: int = 2, cfg=None):
    """Multi-start LM fit of the baseline; returns (model, info, index of the kinematics used).

    ``kins``: one or more candidate kinematics of the same recording (bristle paths); every start
    is screened on each. Starts from :func:`~._model.initial_baselines` (data-driven) plus the
    least-squares start, and on each kinematics the ``far_starts`` of the grid of further starts
    (``initial_baselines``' second list: sigma0 and the Stribeck hump decades away) whose training
    SSE is lowest before any step (a prediction each, no fit), from each Coulomb level's grid;
    each (start, kinematics) pair is run ``screen_steps`` LM steps, the best two by training SSE are
    run to convergence. ``cfg``: the settings of the starts (default :class:`DiagnoseConfig`).
    """
    w = np.asarray(weights)
    tau = np.asarray(rec.torque)

    def sse(m, kin):
        return _weighted_sse(m, kin, tau, w)[0]

    if params is not None:
        # given parameters: the bristle path is still chosen by the training SSE, as in a fit
        given = M.baseline_from_params(params)
        k = int(np.argmin([sse(given, kin) for kin in kins])) if len(kins) > 1 else 0
        return given, {"result": "given", "steps": 0, "starts": 0}, k
    m0 = rough if rough is not None else M.initial_baseline(rec, friction, fit_offset)
    starts, far = M.initial_baselines(rec, friction, fit_offset, noise, rough=m0, cfg=cfg)
    if isinstance(m0.friction, LuGre):
        starts.append(m0)
    else:
        far = []
    space = M.FitSpace(M.baseline_specs(starts[0], scales, fit_offset))
    far = [M.clip_into(space, s0) for s0 in far] if far_starts else []
    screened = []
    many = len(starts) * len(kins) > 1
    # the further starts by Coulomb level, the nearest of each level's grid taken: a static curve that
    # fits the resolved speeds with its Coulomb level near 0 is nearer before any step than the joint's
    # own level
    levels = [float(m.friction.Fc) for m in far]
    grids = [[i for i, c in enumerate(levels) if c == level] for level in dict.fromkeys(levels)]
    for k, kin in enumerate(kins):
        nearest = [i for grid in grids for i in sorted(grid, key=lambda i: sse(far[i], kin))[:far_starts]]
        for s0 in starts + [far[i] for i in nearest]:
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


def hump_restart(model, space, kin, tau, weights, V: float, cfg, screen_steps: int = 25,
                 n: int = 2) -> tuple[object, np.ndarray | None]:
    """``model`` (a least-squares fit of its structure on ``weights``) with its Stribeck hump searched
    again: the humps ``cfg.far_fs_over_fc`` x ``cfg.far_vs_over_v`` (of the speed scale ``V``) on the
    fitted inertia, Coulomb level, viscous, bristle and candidate parameters, ranked by training SSE
    (a prediction each), the ``n`` nearest run ``screen_steps`` LM steps and the best to convergence.
    Returns (the model, its residual ``tau - prediction`` where it changed, else None): the new fit
    only where its training SSE is lower.

    Where few resolved samples are slow (moves between dwells) a fit that settled humpless while
    an effect was missing stays so when the effect joins it, though the joint optimum has the
    joint's hump; its misfit at low speed is structure the null, simulated from that fit, does not
    hold, and the next candidate that takes part of it is named."""
    if not isinstance(model.friction, LuGre):
        return model, None
    tau = np.asarray(tau)
    w = np.asarray(weights, float)

    def sse(m):
        return _weighted_sse(m, kin, tau, w)[0]

    e0, Fc = sse(model), float(model.friction.Fc)
    grid = [M.clip_into(space, eqx.tree_at(lambda m: (m.friction.Fs, m.friction.vs), model,
                                           (jnp.asarray(max(ratio, 1.0001) * Fc), jnp.asarray(q * V))))
            for ratio in cfg.far_fs_over_fc for q in cfg.far_vs_over_v]
    near = sorted(grid, key=sse)[:n]
    screened = sorted(((sse(m), m) for m in (M.fit(s0, space, kin, tau, weights, max_steps=screen_steps)[0]
                                             for s0 in near)), key=lambda x: x[0])
    if not screened or not screened[0][0] < e0:
        return model, None
    fitted, _ = M.fit(screened[0][1], space, kin, tau, weights, max_steps=cfg.max_steps)
    e, r = _weighted_sse(fitted, kin, tau, w)
    return (fitted, r) if e < e0 else (model, None)


@dataclasses.dataclass(frozen=True)
class Prepared:
    """Stage 1: the conditioned recording and the fitted (or given) baseline.

    ``rec_in``: as loaded; ``rec``: conditioned; ``cond``: how; ``unresolved``: samples inside
    transients the sampling does not resolve; ``kin``: kinematics along the chosen bristle ``path``;
    ``base``: the baseline; ``info``: its fit record; ``k``: its free-parameter count; ``at_rest``:
    the dwells left out (part of ``unresolved``); ``lines``: frequencies of the motion's spectral
    lines (:func:`._attribute.motion_lines`), where a time-periodic term is not told from a kinematic
    error."""

    rec_in: object
    rec: object
    cond: object
    unresolved: np.ndarray
    kin: object
    path: str
    base: object
    info: dict
    k: int
    at_rest: np.ndarray
    lines: np.ndarray


@dataclasses.dataclass(frozen=True)
class Split:
    """Stage 2: which samples fit, which validate. ``blocks``: time-block ids; ``keep``: resolved
    samples; ``val``: the held-out phase ``phase``; ``folds``: the phases a candidate's
    cross-validated test crosses (``cv_mask``); ``w``: training weights."""

    blocks: np.ndarray
    keep: np.ndarray
    val: np.ndarray
    phase: int
    folds: tuple
    cv_mask: np.ndarray
    w: np.ndarray
    n_reversals: int
    unpredicted: int = 0

    @property
    def rows(self) -> np.ndarray:
        return self.w > 0


@dataclasses.dataclass(frozen=True)
class Floor:
    """Stage 3: the noise model. ``torque_nm`` and ``kinematic_nm``: per-sample noise of the torque
    channel and what the kinematics' errors bring through the baseline, each capped by the upper bound
    of the baseline's residual mean square (:func:`_floor`); ``floor_nm``: both;
    ``ratio``: the baseline's validation RMSE over it; ``known``: what a correct model's residual
    keeps in expectation (shapes :func:`~._locate.locate` does not claim); ``null``: the
    measurement chain the candidates' test simulates; ``scales``: data scales with ``noise`` set;
    ``kinematic_errors``: the null's kinematic draws through the baseline, centred and scaled as
    ``null.kinematic_errors`` gives them (``kinematic_nm`` is their rms over the training samples)."""

    torque_nm: float
    kinematic_nm: float
    floor_nm: float
    ratio: float
    attenuation: float
    known: dict
    null: object
    scales: dict
    kinematic_errors: np.ndarray = dataclasses.field(repr=False, compare=False, default=None)


def _prepare(rec, cfg, params, friction, fit_offset, refit: bool = False) -> tuple[Prepared, "Split"]:
    """Condition the kinematics for a first inertia, fit the baseline, and condition again for the
    fitted inertia when that changes the window enough to matter (``cfg.rechoose_share``), or, with
    the inertia unchanged, on the window where the baseline's training residual is significantly
    lower (:func:`_residual_window`)."""
    from ._condition import (blended, condition, conditioned_kinematics, forget_after, model_bias_unresolved,
                             smoothing_blend)

    def conditioned(J0, s2_0, **kw):
        return condition(rec, J0, s2_0, cfg=cfg, **kw)

    rough = M.initial_baseline(rec, friction, fit_offset)
    crec, cond, unresolved = conditioned(float(rough.J), float(getattr(rough.friction, "sigma2", 0.0)))
    # the first least-squares inertia comes from the loader's raw derivatives; where they are noisy
    # (a differentiated encoder) errors in variables shrink it, and the window chosen for it is too
    # long: estimate it again on the conditioned kinematics
    rough2 = M.initial_baseline(crec, friction, fit_offset)
    if not 0.8 <= float(rough2.J) / max(float(rough.J), 1e-300) <= 1.25:
        rough = rough2
        crec, cond, unresolved = conditioned(float(rough.J), float(getattr(rough.friction, "sigma2", 0.0)))
    rest = _dwells(crec, cond, cfg)
    unresolved = unresolved | rest
    rechosen, offered, first, first_state = None, None, None, None
    for second in (False, True):
        forget = None
        # the bristle state is unknown after a dwell (whatever the sensors), and with a velocity-only
        # path after any unresolved transient too (the path is off by an unknown step there): the
        # bristles remember either over the travel bristle_memory gives (pre-sliding length
        # measured at the reversals)
        events = rest if cond.position_measured else unresolved
        if np.any(events) and hasattr(rough.friction, "Fs"):
            forget = bristle_memory(M.presliding_displacement(crec, float(rough.friction.Fs)),
                                    max(float(rough.friction.Fs), float(rough.friction.Fc)), cond.torque_noise, cfg)
            unresolved_in = unresolved
            unresolved = unresolved | forget_after(events, crec.position, forget)
        split = _split(crec, cond, unresolved, cfg)
        w = split.w
        paths = _paths(rec, crec, cond)
        base, info, k_path = fit_baseline(crec, list(paths.values()), w, M.data_scales(crec), friction,
                                          fit_offset, params, noise=cond.torque_noise, cfg=cfg)
        if forget is not None and isinstance(base.friction, LuGre):
            # the measured pre-sliding length can be short of the bristles' (a fast reversal moves the
            # torque by inertia and by the controller too): with the fitted Fs/sigma0 the memory can
            # be longer, and then the fit is repeated without the samples it adds
            fmax = max(float(base.friction.Fs), float(base.friction.Fc))
            forget_fit = bristle_memory(M.presliding_length(base.friction), fmax, cond.torque_noise, cfg)
            wider = (unresolved_in | forget_after(events, crec.position, forget_fit)) if forget_fit > forget \
                else unresolved
            if np.any(wider & ~unresolved):
                unresolved = wider
                split = _split(crec, cond, unresolved, cfg)
                w = split.w
                base, info, k_path = fit_baseline(crec, list(paths.values()), w, M.data_scales(crec), friction,
                                                  fit_offset, params, noise=cond.torque_noise, cfg=cfg)
                info["bristle_memory_refit"] = float(forget_fit)
        path = list(paths)[k_path]
        kin = paths[path]
        info["bristle_path"] = path
        if second:
            # the window is a nuisance choice kept, as the blend below, only where the refitted
            # baseline predicts the held-out samples both windows keep better than the first did:
            # the training residual compares one baseline on two windows, and the refit can move
            if not _predicts_better(first, (crec, base, kin, split), cfg.min_resolved // 4):
                (crec, base, kin, split), (cond, unresolved, rest, info, path, paths) = first, first_state
                info = {**info, "window_refused": dict(zip(("source", "window", "order"), offered))}
                rechosen = None
            break
        first, first_state = (crec, base, kin, split), (cond, unresolved, rest, info, path, paths)
        J_fit, s2_fit = float(base.J), float(getattr(base.friction, "sigma2", 0.0))
        if cond.source == "recording":  # no window error to compare for data used as loaded
            break
        # another window is taken where it fits significantly better (_residual_window)
        needed = 0.0
        if not 0.8 <= J_fit / max(float(rough.J), 1e-300) <= 1.25:
            # the window rule's estimate for the fitted inertia, when it changes the floor noticeably
            needed = cfg.rechoose_share * cond.torque_noise ** 2
            cond2 = conditioned(J_fit, s2_fit)[1]
            choice = None if cond2.source == "recording" else (cond2.source, cond2.window, cond2.order)
            excess = 0.0
            if choice is not None and choice != (cond.source, cond.window, cond.order):
                excess = conditioned(J_fit, s2_fit, choices=[(cond.source, cond.window, cond.order)],
                                     error_only=True) - conditioned(J_fit, s2_fit, choices=[choice], error_only=True)
        else:
            choice, excess = _residual_window(rec, crec, cond, base, kin, path, split, cfg.alpha)
        if choice is None or excess <= needed:
            break
        rechosen = {"source": cond.source, "window": cond.window, "order": cond.order, "inertia": float(rough.J),
                    "excess_error_nm": float(np.sqrt(excess))}
        offered = choice
        crec, cond, unresolved = conditioned(J_fit, s2_fit, choices=[choice])
        rest = _dwells(crec, cond, cfg)
        unresolved = unresolved | rest
    if rechosen is not None:
        info["window_rechosen_from"] = rechosen
    # the smoothing bias the chosen window leaves, extrapolated from the next window where the
    # held-out blocks confirm it (_condition.smoothing_blend); the baseline is then fitted again
    r = (np.asarray(crec.torque) - M.predict(base, kin)) * split.keep
    blend = smoothing_blend(rec, crec, cond, float(base.J), r, split.w > 0, split.val)
    if blend:
        a = conditioned_kinematics(rec.time, rec.position, rec.velocity, cond.source, cond.window, cond.order,
                                   blend)[1]
        crec = eqx.tree_at(lambda r_: r_.acceleration, crec, a)
        cond = blended(cond, blend, rec.dt)
        paths = _paths(rec, crec, cond)
        base, info_b, k_path = fit_baseline(crec, list(paths.values()), split.w, M.data_scales(crec), friction,
                                            fit_offset, params, noise=cond.torque_noise, cfg=cfg)
        info = {**info, **info_b}
        path = list(paths)[k_path]
        kin = paths[path]
        info["bristle_path"] = path
    # samples that leave the fit after it, each rule read through the baseline fitted before it and
    # the fit repeated without them (too few left to fit: the fit stands, and its floor carries what
    # they hold, which shows as excess over it, not as a refusal): the smoothing-bias rule again,
    # through the fitted model's whole torque (near slow reversals the friction's, not the
    # inertia's); then the sensors' noise through the fitted model, where it alone moves the model
    # torque by more than the share the smoothing's bias may take
    rules = (("model_bias_unresolved",
              lambda: model_bias_unresolved(rec, cond, kin, lambda k_: M.predict(base, k_), cfg.resolved_share)),
             ("kinematic_noise_unresolved",
              lambda: _kinematic_noise_unresolved(rec, cond, path, base, kin, split.blocks, cfg)))
    for key, rule in rules:
        extra = rule() & ~unresolved
        if not np.any(extra):
            continue
        try:
            split_new = _split(crec, cond, unresolved | extra, cfg)
        except ValueError:
            continue
        unresolved, split = unresolved | extra, split_new
        base, info_b, k_path = fit_baseline(crec, list(paths.values()), split.w, M.data_scales(crec), friction,
                                            fit_offset, params, noise=cond.torque_noise, cfg=cfg)
        info = {**info, **info_b, key: int(extra.sum())}
        path = list(paths)[k_path]
        kin = paths[path]
        info["bristle_path"] = path
    k = len(M.baseline_specs(base, M.data_scales(crec), fit_offset)) if params is None or refit else 0
    lines = motion_lines(np.asarray(rec.time, float), np.asarray(kin.v, float), cfg.alpha_attribute)
    return Prepared(rec, crec, cond, unresolved, kin, path, base, info, k, rest, lines), split


def _kinematic_noise_unresolved(rec, cond, path, base, kin, blocks, cfg) -> np.ndarray:
    """Samples whose model torque the kinematics' noise moves by more than ``cfg.resolved_share`` of
    the torque noise: the rms over the kinematic draws (fresh sensor noise, a quantised position
    re-quantised on a shifted grid, each conditioned as the recording) of the fitted ``base``'s
    torque on them less its torque on the recording's kinematics. There the sensors do not determine
    the torque (creep within a few encoder steps of the bristles' pre-sliding length, say), and a
    least-squares fit over those samples is biased by errors in variables, as it is where the
    smoothing's bias is that large; the share is the smoothing rule's."""
    from ._calibrate import null_model

    # DiagnoseConfig holds kinematic_draws >= 1, so there is always a draw
    d = null_model(rec, cond, path, cfg.kinematic_draws, blocks).kinematic_errors(base, kin)
    return np.sqrt(np.mean(d ** 2, axis=0)) > cfg.resolved_share * float(cond.torque_noise)


def _predicts_better(old, new, fewest: int) -> bool:
    """Whether the baseline ``new`` (conditioned recording, baseline, kinematics, split) has a lower
    mean square residual than ``old`` on the held-out samples both keep; False with fewer than
    ``fewest`` of them (the held-out count a split needs)."""
    both = np.asarray(old[3].val, bool) & np.asarray(new[3].val, bool)
    if np.count_nonzero(both) < fewest:
        return False
    ms = [np.mean((np.asarray(c.torque) - np.asarray(M.predict(b, k)))[both] ** 2) for c, b, k, _ in (old, new)]
    return bool(np.isfinite(ms[1]) and ms[1] < ms[0])


def _residual_window(rec, crec, cond, base, kin, path: str, split, alpha: float) -> tuple:
    """The window (:func:`~._condition.window_options`) on whose kinematics the fitted baseline's
    training mean square residual is significantly lower than on ``kin``, and by how much ((None, 0)
    without one). The residual holds what the kinematics' smoothing bias and noise bring together,
    with the torque noise common to every window; the window rule only estimates them (its bias from
    the change from W to 2W-1, which misses motion both windows remove and counts transients the fit
    leaves out). The test is one-sided on the paired difference, its standard error from the
    training time blocks' sums, at ``alpha`` (Bonferroni over the windows compared); the baseline was
    fitted on ``kin``, so it leans towards keeping the window."""
    from scipy.stats import norm

    from ._condition import conditioned_kinematics, window_options

    tau, w = np.asarray(crec.torque), np.asarray(split.w)
    _, blk = np.unique(split.blocks, return_inverse=True)
    wb = np.bincount(blk, weights=w)

    def sq(k):
        e = tau - np.asarray(M.predict(base, k))
        return e * e if np.all(np.isfinite(e[w > 0])) else None

    own = sq(kin)
    options = window_options(rec, cond, float(base.J))
    nb = np.count_nonzero(wb)
    if own is None or not options or nb < 5:
        return None, 0.0
    z = float(norm.isf(alpha / len(options)))
    best, gain = None, 0.0
    for choice in options:
        v, a, th = conditioned_kinematics(rec.time, rec.position, rec.velocity, *choice)
        theta = _path_position(rec, th, path)
        e2 = sq(M.kinematics_of(eqx.tree_at(lambda r: (r.position, r.velocity, r.acceleration), crec, (theta, v, a))))
        if e2 is None:
            continue
        # off the training samples a non-finite residual times its zero weight would make every sum NaN
        db = np.bincount(blk, weights=np.where(w > 0, w * (own - e2), 0.0))
        mean = float(db.sum() / wb.sum())
        se = float(np.sqrt(np.sum((db - mean * wb) ** 2) * nb / (nb - 1)) / wb.sum())
        if mean > z * se and mean > gain:
            best, gain = choice, mean
    return best, gain


def _dwells(crec, cond, cfg) -> np.ndarray:
    """The dwells left out (:func:`~._condition.at_rest`), with a velocity sensor: its white noise
    through the window is what the rest test's level assumes. Derivatives of a quantised position
    read zero between encoder steps at a slow creep, which the test cannot tell from a stop."""
    from ._condition import at_rest

    if not cond.velocity_measured:
        return np.zeros(np.shape(crec.velocity), bool)
    return at_rest(crec.velocity, cond.velocity_noise_after, cfg.alpha, max(cond.window, 5))


def _paths(rec, crec, cond) -> dict:
    """The bristle paths a baseline fit chooses between: the conditioned recording's own
    (complementary, or as measured when used as loaded) and, with conditioned derivatives, the
    measured position where there is one and the measured velocity's own integral where there is
    one (:func:`~._condition.velocity_path`)."""
    paths = {"complementary" if cond.source != "recording" else "measured": M.kinematics_of(crec)}
    if cond.source != "recording":
        for kind, present in (("measured", cond.position_measured), ("velocity", cond.velocity_measured)):
            if present:
                theta = _path_position(rec, np.asarray(crec.position), kind)
                paths[kind] = M.kinematics_of(eqx.tree_at(lambda r: r.position, crec, theta))
    return paths


def _path_position(rec, conditioned_position, kind: str) -> np.ndarray:
    """A bristle path's positions: the conditioned ones (``complementary``), the recording's own
    (``measured``) or the measured velocity's integral held to them (``velocity``)."""
    if kind == "measured":
        return np.asarray(rec.position)
    if kind == "velocity":
        from ._condition import velocity_path

        return velocity_path(rec.time, conditioned_position, rec.velocity)
    return conditioned_position


def bristle_memory(x_pre: float, f_max: float, torque_noise: float, cfg) -> float:
    """Travel after which a wrong bristle state no longer shows in the torque.

    LuGre's z error contracts along the path at least as exp(-s/x_pre), x_pre = max(Fs, Fc)/sigma0
    (g <= max(Fs, Fc)), from at most 2*max(Fs, Fc) of torque (z between -g/sigma0 and g/sigma0);
    the travel that brings that bound down to ``cfg.bristle_memory_share`` of the torque noise."""
    share = cfg.bristle_memory_share * max(float(torque_noise), 1e-12)
    return float(x_pre) * max(np.log(2.0 * float(f_max) / share), 1.0)


def _split(rec, cond, unresolved, cfg) -> Split:
    scales = M.data_scales(rec)
    blocks = M.block_ids(rec.time, cfg.block_s)
    keep = ~unresolved
    since, _, n_rev = L.reversal_info(rec.time, rec.velocity, scales["V"])
    # the held-out phase: the fixed one unless it would take most of the reversals or of the bursts
    # of acceleration (an excitation periodic in five blocks) away from the fit
    events = [keep & (since == 0),
              M.event_starts(keep & (np.abs(np.asarray(rec.acceleration)) > cfg.big_acceleration * scales["A"]))]
    worst, held = M.phases_holding_events(blocks, events, max_share=cfg.max_event_share, alpha=cfg.event_alpha)
    phase = M.phase_off_events(worst, held)
    val = M.validation_mask(blocks, phase=phase) & keep
    folds = tuple(j for j, h in enumerate(held) if not h or j == phase)
    cv_mask = keep & np.isin(M.block_phase(blocks), folds)
    w = ((~val) & keep).astype(float)
    if int(w.sum()) < cfg.min_resolved or int(val.sum()) < cfg.min_resolved // 4:
        raise ValueError(
            f"{rec.source}: only {int(keep.sum())} of {rec.n} samples have kinematics resolved at this "
            f"sampling and noise and the joint moving ({cond.source}, window {cond.window}); expected at least "
            f"{cfg.min_resolved} for the fit and a quarter of that held out: a slower or smoother "
            f"excitation, or {'a higher sampling rate' if cond.velocity_measured else 'a velocity sensor'}, "
            "is needed")
    return Split(blocks, keep, val, phase, folds, cv_mask, w, n_rev)


def _predicted(prep: Prepared, split: Split, fit_offset, share: float) -> Split:
    """``split`` without the held-out samples whose model torque the training blocks do not
    determine: where a held-out sample's leverage ``h = j (J'J)^-1 j'`` (``j`` its row of the
    baseline's Jacobian, ``J`` the training rows') puts the fitted prediction's standard error
    ``sqrt(h)`` times the noise above ``share`` of it (``resolved_share``), the criterion a sample's
    kinematics must meet. Such samples are extrapolation (a reversal only a held-out block
    resolves, the bristle parameters then set by nothing the fit saw): their error is the fit's, not
    missing physics, and they leave the validation and the tests."""
    from ._calibrate import jacobian

    if prep.k == 0 or not np.any(split.val):
        return split
    specs = M.baseline_specs(prep.base, M.data_scales(prep.rec), fit_offset)
    J = jacobian(prep.base, specs, prep.kin, split.keep)
    # columns to unit norm over the kept samples (a parameter near its bound has a small column
    # in the fit's unbounded coordinates; leverage does not depend on the columns' scales) and a
    # ridge at rounding level, so that a direction no training row moves counts as undetermined
    norm = np.sqrt(np.sum(J ** 2, axis=0))
    J = J / np.where(norm > 0, norm, 1.0)
    rows, held = split.rows[split.keep], split.val[split.keep]
    G = J[rows].T @ J[rows]
    G += 1e-10 * max(float(np.trace(G)) / G.shape[0], 1e-300) * np.eye(G.shape[0])
    h = np.einsum("ij,ji->i", J[held], np.linalg.solve(G, J[held].T))
    bad = np.zeros_like(split.val)
    bad[np.flatnonzero(split.keep)[held]] = h > share ** 2
    if not np.any(bad) or not np.any(split.val & ~bad):
        return split
    return dataclasses.replace(split, keep=split.keep & ~bad, val=split.val & ~bad, cv_mask=split.cv_mask & ~bad,
                               unpredicted=int(bad.sum()))


def _noise(prep: Prepared, prediction: np.ndarray, cfg) -> Prepared:
    """``prep`` with the torque noise estimated again through the fitted model
    (:func:`~._condition.refined_torque_noise`): the differences the model's torque sets are left out
    of the noise profile, so the motion's fast changes no longer read as colour. The estimate made
    before the fit (which chose the window and the bristle memory) is kept in ``info``."""
    from ._condition import refined_torque_noise

    c = prep.cond
    noise = refined_torque_noise(np.asarray(prep.rec.torque, float), prediction, c.torque_noise,
                                 cfg.resolved_share, colour_chi2=cfg.colour_chi2, outlier_std=cfg.outlier_std)
    cond = dataclasses.replace(c, torque_noise=noise.std, torque_noise_colour=noise.phi,
                               torque_noise_open=noise.open, torque_noise_arma=noise.arma)
    info = {**prep.info, "torque_noise_before_fit": {"std_nm": c.torque_noise, "colour": c.torque_noise_colour}}
    return dataclasses.replace(prep, cond=cond, info=info)


def _floor(prep: Prepared, split: Split, cfg, fit_offset, r0: np.ndarray) -> Floor:
    """The floor of an inverse model: the torque noise and what the kinematics' noise brings through
    the fitted model (errors in variables), both from the data; and the null model that simulates
    them. ``r0``: the baseline's residual on the kept samples."""
    from ._calibrate import centred_draws, null_model

    rec, cond, base, kin = prep.rec, prep.cond, prep.base, prep.kin
    scales = M.data_scales(rec)
    null = null_model(prep.rec_in, cond, prep.path, cfg.kinematic_draws, split.blocks)
    d = null.kinematic_errors(base, kin, centred=False)
    # the systematic part (the draws' mean) is what a correct model's residual keeps in expectation
    eiv_bias = np.where(split.keep, -d.mean(axis=0), 0.0)
    known = {"conditioning_bias_nm": cond.bias_nm, "eiv_bias_nm": eiv_bias,
             "static_basis": M.static_curve_basis(base, M.baseline_specs(base, scales, fit_offset),
                                                  np.asarray(rec.velocity))}
    # least squares on a noisy acceleration attenuates J by lam = var(a_true)/var(a_measured); the
    # best predictor then misses (1 - lam)*J*a_true, which the cross-correlations must expect
    a_m = np.asarray(rec.acceleration)
    lam = 1.0
    if cond.source != "recording" and np.any(split.rows):
        va = float(np.var(a_m[split.rows]))
        lam = float(np.clip(1.0 - cond.accel_noise ** 2 / va, 0.2, 1.0)) if va > 0 else 1.0
    if lam < 1.0:
        known["eiv_inertial_nm"] = (1.0 / lam - 1.0) * float(base.J) * a_m
    # the floor is the null model's per-sample residual: the torque noise and the scatter the
    # kinematics' errors bring through the fitted model (the same draws the candidates' test uses)
    kin_noise = 0.0
    draws = centred_draws(d)
    if d.shape[0] > 1 and np.any(split.rows):
        kin_noise = float(np.sqrt(np.mean(draws[:, split.rows] ** 2)))
    # a complete model cannot beat the floor: the baseline's mean square over the kept samples (its
    # upper bound; the fit's few parameters take a negligible share of the training samples' noise)
    # bounds the floor from above. Where it is below the torque noise itself, the noise's profile
    # read high (a strong colour at a low rate, whose plateau lies where the motion's differences
    # are large too), and the torque noise is that bound, in the floor and in the null draws
    bound = _ms_bound(r0, split.keep, split.blocks)
    torque_nm = float(cond.torque_noise)
    if 0.0 < bound < torque_nm ** 2:
        torque_nm = float(np.sqrt(bound))
        null = dataclasses.replace(null, torque_sd=torque_nm)
    # the simulated kinematic errors can be larger than the recording's (a velocity column whose
    # high-frequency content is motion, not noise): where the bound leaves less room above the
    # torque noise, the kinematic part is scaled down to that room, in the floor and in the draws
    room = max(bound - torque_nm ** 2, 0.0)
    if kin_noise > 0 and kin_noise ** 2 > room:
        scale = float(np.sqrt(room) / kin_noise)
        null = dataclasses.replace(null, kinematic_scale=scale)
        kin_noise *= scale
    floor = float(np.hypot(torque_nm, kin_noise))
    # the shapes a correct model's residual keeps in expectation, which no test may claim: the
    # kinematics' systematic error (above), the smoothing's bias, J times the change of the
    # acceleration from the window W to 2W-1 (signed; the same estimate the conditioning chose by),
    # and the smoothing's blur of the acceleration where the friction changes fast (the motor's
    # torque is smooth, so the true acceleration carries the friction's switches; the kinematic
    # draws, smoothed alike, do not hold it)
    nuisance = [eiv_bias]
    if cond.source != "recording" and 2 * cond.window - 1 < rec.n // 2:
        from ._condition import friction_smoothing_error, wider_acceleration

        rin = prep.rec_in
        a2 = wider_acceleration(rin.time, rin.position, rin.velocity, cond.source, cond.window, cond.order)
        nuisance.append(np.where(split.keep, float(base.J) * (a_m - a2), 0.0))
        blur = friction_smoothing_error(rec.time, _friction(base, kin), cond)
        nuisance.append(np.where(split.keep, blur, 0.0))
    known["nuisance"] = np.column_stack(nuisance)
    ratio = _rms(r0, split.val) / floor if floor > 0 else float("inf")
    scales = {**scales, "noise": floor, "acceleration_attenuation": lam}
    return Floor(torque_nm, kin_noise, floor, ratio, lam, known, null, scales,
                 kinematic_errors=null.kinematic_scale * draws)


def _quantised_derivatives(cond) -> bool:
    """The kinematics are derivatives of a quantised position (errors correlated over an encoder step)."""
    return cond.source == "position" and cond.quantisation > 0


def _filter_lags(prep: Prepared) -> int:
    """Memory of the conditioning: a Savitzky-Golay window W (2W-1 when blended), then a central
    difference for the jerk.
    A quantised position's error is correlated for as long as the joint takes to cross a step, and
    the bristles carry it further: with derivatives of a quantised position the cross-correlations
    with acceleration and jerk have no null distribution bounded from the data, so they are not run
    (flags past their largest lag, 0.5 s)."""
    cond = prep.cond
    if _quantised_derivatives(cond):
        return int(round(0.5 / prep.rec.dt)) + 1
    from ._condition import memory

    return memory(cond) + 2 if cond.source != "recording" else 0


def _locate(prep, split, floor, cfg, model, r, filter_lags, at_floor: bool):
    from ._calibrate import null_draws

    draws = null_draws(model, prep.kin, floor.null, cfg.draws, cfg.seed + 2000)
    loc = L.locate(prep.rec, r, split.blocks, floor.scales, cfg.alpha_locate, filter_lags, split.keep,
                   _friction(model, prep.kin), known=floor.known, null=draws, resolution=cfg.resolution,
                   shape_resolution=cfg.shape_resolution, shape_bands=cfg.shape_bands)
    return _mismatch(loc, at_floor)


def _context(prep, split, floor, model, r, cfg, loc=None) -> M.Context:
    """The candidates' view of the current model and residual (periodogram peaks of ``r``)."""
    from ._condition import accel_bandwidth

    rec = prep.rec
    inertial, F, _ = (np.asarray(x) for x in M._parts(model, prep.kin))
    if loc is not None:
        peaks, f_t = loc["position_periodogram"]["peaks"], loc["time_periodogram"]["frequency"]
    else:
        # as the calibration's null draws find them (:mod:`._calibrate`)
        peaks = L.position_peaks_many(rec.position, r)[0]
        f_t = float(L.time_peaks_many(rec.time, r)[0])
    cond = prep.cond
    return M.Context(rec=rec, kin=prep.kin, baseline=model, residual=np.asarray(r), scales=floor.scales,
                     position_peaks=peaks, time_peak_hz=f_t, friction_torque=F, inertial_torque=inertial,
                     n_reversals=split.n_reversals,
                     to_rad=np.pi / 180 if rec.units.get("position") == "deg" else 1.0,
                     position_resolution=max(cond.quantisation, cond.position_noise),
                     accel_bandwidth_hz=accel_bandwidth(cond, prep.rec.dt), config=cfg)


@dataclasses.dataclass
class _Reference:
    """What a step's held-out test compares a candidate with: the current model, or the current model
    with a candidate refused as fitting beyond the kinematics' resolution (``refused``: its id; that
    structure is the smoothing's, so a later candidate is credited only with what it adds to it).
    Its cross-validated residual and the library's rival terms are computed once, when first needed."""

    model: object
    specs: list
    r: np.ndarray
    refused: str | None = None
    _cv: np.ndarray | None = None
    _rivals: Rivals | None = None

    def cross_validated(self, kin, tau, split, cfg) -> np.ndarray:
        if self._cv is None:
            self._cv = _cross_validated(self.model, self.specs, kin, tau, split.keep, split.blocks, split.phase,
                                        split.folds, cfg.max_steps)
        return self._cv

    def library_rivals(self, ctx, kin, split, prep, floor) -> Rivals:
        if self._rivals is None:
            ctx_ref = ctx if self.refused is None else ctx.replace(baseline=self.model, residual=self.r)
            self._rivals = rivals(self.model, self.specs, ctx_ref, kin, split.keep, split.blocks, split.folds,
                                  _window(prep), _quantised_derivatives(prep.cond), floor.known["nuisance"],
                                  motion=prep.lines, cond=prep.cond)
        return self._rivals


def _alternatives(best, others, kin, tau, split, cfg) -> list[dict]:
    """Of the step's other accepted candidates (``others``: each refitted in the named one's place,
    plausible, identifiable, lowering the held-out error), those the held-out blocks cannot tell
    from the named one: it does not predict them significantly better (one-sided, at
    ``alpha_confirm``). The verdict keeps one name; the report says which other physics the
    excitation leaves as likely (a gravity torque nearly constant over the angles moved through is a
    constant torque, which while sliding is a direction asymmetry)."""
    r_best = best["ref"].cross_validated(kin, tau, split, cfg)
    out = []
    for t in others:
        p = held_out_p(t["ref"].cross_validated(kin, tau, split, cfg), r_best, split.blocks, split.cv_mask)
        if not rejects(p, cfg.alpha_confirm):
            out.append({"name": t["name"], "cv_rmse_nm": t["cv_rmse_nm"], "p_named_better": p})
    return out


def _term_alternatives(r_named, cv_before, rivals_step: Rivals, split, cfg) -> list[dict]:
    """The library terms (each with the current model's linearised refit, cross-validated on the
    named candidate's phases) that lower the held-out error too, significantly beyond that refit
    alone (one-sided, at ``alpha_confirm``), and that the named candidate does not predict
    significantly better (one-sided, at ``alpha_confirm``): physics outside the eight
    that the excitation ties to the candidate's shape (on a staircase, whose speeds rise with time,
    a drag ``v*|v|`` and a friction drifting in time). The name stays; the report lists these."""
    out = []
    for g, r_g, reading in rivals_step.terms:
        cv_g = _rms(r_g, split.cv_mask)
        # the term's own share: it lowers the held-out error beyond the model's linearised refit
        # alone (which, cross-validated, can lower it by itself and so carry every term along)
        if not (cv_g < cv_before and rejects(held_out_p(rivals_step.refit, r_g, split.blocks, split.cv_mask),
                                             cfg.alpha_confirm)):
            continue
        p = held_out_p(r_g, r_named, split.blocks, split.cv_mask)
        if not rejects(p, cfg.alpha_confirm):
            out.append({"term": g.name, "reading": reading, "cv_rmse_nm": cv_g, "p_named_better": p})
    return sorted(out, key=lambda a: a["cv_rmse_nm"])


def _select(prep, split, floor, cfg, pool, fit_offset, frozen, progress, start: _Reference):
    """Greedy forward selection: at each step every candidate is tested against the null simulated
    for this recording (:mod:`._calibrate`); the significant ones (family-wise, ``cfg.alpha_name``)
    are refitted jointly with the current model, and the first that is plausible and identifiable is
    held out: accepted when it lowers the held-out error (cross-validated over the block phases,
    significantly at ``cfg.alpha_confirm``; the model carried forward lowers it too) and no term of
    the attribution library predicts those phases significantly better (:func:`~._attribute.rivals`).
    When it is, the next significant candidate is judged alike, and of the two accepted the one with
    the lower cross-validated error is named (the other is reported as an alternative when the
    held-out blocks cannot tell them apart). Stops when no candidate is significant, none is
    plausible and identifiable, or the held-out test fails. After a finding the Stribeck hump is
    searched again (:func:`hump_restart`); where that moves the fit, the selection goes on from both
    fits and keeps the path whose final model has the lower cross-validated error (the log's
    ``hump_restart_paths``). ``start``: the baseline as the first step's reference. Returns the final
    model's reference (its cross-validated residual is the report's held-out error) with the log."""
    from tqdm.auto import tqdm

    from ._calibrate import test_candidates

    tau = np.asarray(prep.rec.torque)
    kin, w, keep, val = prep.kin, split.w, split.keep, split.val
    scales = floor.scales
    bar = tqdm(total=cfg.max_effects, desc="select", disable=not progress, leave=False)

    def steps(cur_ref, accepted, log, may_branch):
        while len(accepted) < cfg.max_effects:
            current, r_cur = cur_ref.model, cur_ref.r
            names = {n: _Proto.get(k) for n, k in pool.items() if n not in [a[0] for a in accepted]}
            ctx = _context(prep, split, floor, current, r_cur, cfg)
            specs_cur = _all_specs(current, scales, fit_offset, freeze_baseline=frozen)
            test = test_candidates(current, specs_cur, names, ctx, kin, split.rows,
                                   floor.null, cfg.draws, cfg.alpha_name, seed=cfg.seed + len(accepted),
                                   nuisance=floor.known["nuisance"])
            # significance is family-wise (min-P); among the significant, the candidate that explains the
            # most beyond what noise alone gives it (gain less its null mean) is refitted first: the
            # standardised gain would favour a one-shape candidate that takes a sliver of a larger effect
            excess = test.statistic - test.statistic / np.maximum(test.standardised, 1e-300)
            order = np.argsort(-excess)
            significant = [int(i) for i in order if rejects(test.p_adjusted[i], cfg.alpha_name)][: cfg.top_k]
            # the model the held-out test compares against: the current one, or the current one with a
            # candidate refused as fitting beyond the kinematics' resolution (that structure is the
            # smoothing's; a later candidate of the step is credited only with what it adds to it)
            ref = cur_ref
            trials = []
            # the motion's lines a kinematic error explains: for a candidate linear in the motion, once a step
            kin_lines, lines_known = None, False

            def _fit_from(model, guess):
                start = M.JointModel(model.J, model.friction, model.offset, model.candidates + (guess,))
                space = M.FitSpace(_all_specs(start, scales, fit_offset, freeze_baseline=frozen))
                start = M.clip_into(space, start)
                fitted, finfo = M.fit(start, space, kin, tau, w, max_steps=cfg.max_steps)
                r1 = (tau - M.predict(fitted, kin)) * keep
                r_start = (tau - M.predict(start, kin)) * keep
                if not np.all(np.isfinite(r1)) or _sse(r1, w) > _sse(r_start, w):
                    fitted, r1 = start, r_start
                return fitted, finfo, space, r1

            def evaluate(i, ref):
                """Refit candidate ``i`` with the current model, judge it (plausible, identifiable,
                lowering the held-out error against ``ref``, no library term predicting better)."""
                nonlocal kin_lines, lines_known
                name = test.names[i]
                fitted, finfo, space, r1 = _fit_from(current, test.best_guess[i])
                cand = fitted.candidates[-1]
                ctx_fit = ctx.replace(baseline=fitted)
                why = cand.implausible(ctx_fit)
                beyond = why is not None and cand.beyond_resolution(ctx_fit)
                kap1 = L.long_run_variance_factor(r1, split.blocks)
                if not lines_known and type(cand).linear_in_motion:
                    kin_lines, lines_known = kinematic_lines(current, kin, np.asarray(prep.rec.time, float), r_cur,
                                                             w > 0, prep.lines, prep.cond), True
                zmax = _identifiability(fitted, space, kin, tau, w, kap1, cand, kin_lines)
                if why is None and not zmax >= cfg.identifiability_z:
                    why = (f"not identifiable on this excitation: its parameters are within "
                           f"{zmax:.2g} standard errors of no effect")
                cv_cur = cv1 = p_val = None
                # the model carried forward; its cross-validated residual is the test's own when it is
                # judged against the current model itself
                fwd = _Reference(fitted, space.specs, r1)
                riv = {"rival": None, "cv_rmse_rival_nm": None, "p_rival": None}
                term_alts = []
                judged_with = ref.refused
                v_cur, v1 = _rms(r_cur, val), _rms(r1, val)
                if why is None:
                    if judged_with is None:
                        m_test, specs_test, r_test = fitted, space.specs, r1
                    else:
                        m_test, _, space_n, r_test = _fit_from(ref.model, test.best_guess[i])
                        specs_test = space_n.specs
                    r_cur_cv = ref.cross_validated(kin, tau, split, cfg)
                    r1_cv = _cross_validated(m_test, specs_test, kin, tau, keep, split.blocks, split.phase,
                                             split.folds, cfg.max_steps)
                    cv_cur, cv1 = _rms(r_cur_cv, split.cv_mask), _rms(r1_cv, split.cv_mask)
                    p_val = (held_out_p(r_cur_cv, r1_cv, split.blocks, split.cv_mask)
                             if np.all(np.isfinite(r1_cv)) else 1.0)
                    if not (cv1 < cv_cur and rejects(p_val, cfg.alpha_confirm)):
                        why = (f"does not lower the held-out error significantly (cross-validated {cv_cur:.4g} -> "
                               f"{cv1:.4g}, p {p_val:.3g})")
                    else:
                        # the report's held-out error is the model carried forward's, cross-validated
                        # alike: judged against a refused structure, it must still be below the current one's
                        if judged_with is None:
                            fwd = _Reference(fitted, space.specs, r1, _cv=r1_cv)
                        cv_fwd, cv_fwd_before = (_rms(fwd.cross_validated(kin, tau, split, cfg), split.cv_mask),
                                                 _rms(cur_ref.cross_validated(kin, tau, split, cfg), split.cv_mask))
                        if not cv_fwd < cv_fwd_before:
                            why = (f"lowers the held-out error only with {judged_with}'s structure (cross-validated "
                                   f"{cv_fwd_before:.4g} -> {cv_fwd:.4g} without it)")
                if why is None:
                    # physics outside the eight that the candidate partly absorbs: a library term
                    # predicts the held-out blocks significantly better than the candidate (one-sided,
                    # Bonferroni over the terms at the naming test's share of alpha)
                    rivals_step = ref.library_rivals(ctx, kin, split, prep, floor)
                    if rivals_step.terms:
                        p_under = [held_out_p(r1_cv, r_g, split.blocks, split.cv_mask)
                                   for _, r_g, _ in rivals_step.terms]
                        top = int(np.argmin(p_under))
                        g_riv, r_riv, _ = rivals_step.terms[top]
                        riv = {"rival": g_riv.name, "cv_rmse_rival_nm": _rms(r_riv, split.cv_mask),
                               "p_rival": min(1.0, len(p_under) * float(p_under[top]))}
                        if rejects(riv["p_rival"], cfg.alpha_name):
                            why = (f"the library's {g_riv.name} term predicts the held-out blocks better (cross-validated "
                                   f"{cv1:.4g} -> {riv['cv_rmse_rival_nm']:.4g}, p {riv['p_rival']:.3g})")
                        else:
                            term_alts = _term_alternatives(r1_cv, cv_cur, rivals_step, split, cfg)
                k1 = len(space.specs) if not frozen else prep.k + sum(
                    len(M.candidate_specs(fitted, j, scales)) for j in range(len(fitted.candidates)))
                sse1 = _sse(r1, w)
                n_train = int(w.sum())
                dbic = _bic(sse1, kap1, n_train, k1) - _bic(_sse(r_cur, w), kap1, n_train, k1 - len(
                    M.candidate_specs(fitted, len(fitted.candidates) - 1, scales)))
                trial = {"name": name, "ref": fwd, "delta_bic": dbic,
                         "p_family": float(test.p_adjusted[i]), "p_validation": p_val,
                         "validation_rmse_nm": v1, "validation_rmse_before_nm": v_cur,
                         "cv_rmse_nm": cv1, "cv_rmse_before_nm": cv_cur, "fit": finfo,
                         "identifiability_z": zmax, "rejected_because": why,
                         "held_out_with": judged_with, "alternative_terms": term_alts} | riv
                return trial, beyond, fitted, space, r1

            for i in significant:
                t, beyond, fitted, space, r1 = evaluate(i, ref)
                trials.append(t)
                if beyond and ref.refused is None:
                    ref = _Reference(fitted, space.specs, r1, refused=t["name"])
                if t["rejected_because"] is None or t["p_validation"] is not None:
                    # one held-out test per step (p_validation is set once a candidate is held out): the
                    # first plausible, identifiable candidate's result decides whether the step names
                    # anything, so the test's alpha bounds the step without a correction over tries
                    break
            if trials and trials[-1]["rejected_because"] is None:
                # the step names physics; which physics: the next significant candidate is held out
                # too, and the one that predicts the held-out blocks better is named (a tie in the
                # linearised gains is not a tie in the refitted models, and the gain's order can
                # be wrong where two shapes share most of the residual)
                k = significant.index(test.names.index(trials[-1]["name"]))
                if k + 1 < len(significant):
                    trials.append(evaluate(significant[k + 1], ref)[0])
            log.append({"step": len(accepted) + 1, "null_draws": test.n_draws, "alpha": cfg.alpha_name,
                        "alpha_held_out": cfg.alpha_confirm,
                        "tests": test.to_json(),
                        "joint_refits": [{k: t[k] for k in ("name", "p_family", "delta_bic", "p_validation",
                                                             "validation_rmse_nm", "validation_rmse_before_nm",
                                                             "cv_rmse_nm", "cv_rmse_before_nm", "identifiability_z",
                                                             "rival", "cv_rmse_rival_nm", "p_rival",
                                                             "rejected_because", "held_out_with", "alternative_terms")}
                                       for t in trials]})
            ok = [t for t in trials if t["rejected_because"] is None]
            if not ok:
                break
            best = min(ok, key=lambda t: t["cv_rmse_nm"])
            best["alternatives"] = _alternatives(best, [t for t in ok if t is not best], kin, tau, split, cfg)
            accepted.append((best["name"], best))
            cur_ref = best["ref"]
            if not frozen:
                # the structure changed: the model carried forward is the least squares of it, its
                # Stribeck hump searched again (a baseline fitted humpless with the effect missing
                # stays so in the joint refit)
                moved, r = hump_restart(cur_ref.model, M.FitSpace(cur_ref.specs), kin, tau, w, scales["V"], cfg)
                log[-1]["hump_restarted"] = r is not None
                if r is not None:
                    restarted = dataclasses.replace(cur_ref, model=moved, r=r * keep, _cv=None, _rivals=None)
                    if not may_branch:
                        cur_ref = restarted
                    else:
                        # a lower training SSE need not lead to the better model: the selection goes
                        # on from both fits (restarts inside them kept on training SSE), and the final
                        # model that predicts the held-out blocks better is kept (a restarted hump can
                        # take a share of a later finding)
                        bar.update(1)
                        paths = [steps(ref_i, list(accepted), [dict(e) for e in log], False)
                                 for ref_i in (restarted, cur_ref)]
                        cvs = [_rms(p[0].cross_validated(kin, tau, split, cfg), split.cv_mask) for p in paths]
                        kept = int(np.argmin(cvs))
                        step = paths[kept][2][len(log) - 1]
                        step["hump_restarted"] = kept == 0
                        step["hump_restart_paths"] = {
                            "cv_rmse_restarted_nm": cvs[0], "cv_rmse_not_restarted_nm": cvs[1],
                            "named_restarted": [a[0] for a in paths[0][1]],
                            "named_not_restarted": [a[0] for a in paths[1][1]]}
                        return paths[kept]
            if may_branch:
                bar.update(1)
        return cur_ref, accepted, log

    out = steps(start, [], [], True)
    bar.close()
    return out


def diagnose(rec, *, params: dict | None = None, refit: bool = False, friction: str = "lugre",
             fit_offset: bool = False, candidates=None, config: DiagnoseConfig | None = None, progress: bool = True,
             **settings) -> Diagnosis:
    """Diagnose a :class:`~lugre_jax.io.Recording`; returns a :class:`~._report.Diagnosis`
    (``to_json()``: the REPORT.json content; ``arrays``: residuals, models and tests behind it).

    The pipeline (docs/diagnosis.md): condition the kinematics and fit the baseline
    (:func:`_prepare`), split training and held-out blocks (:func:`_split`), estimate the torque noise
    again through the fitted model (:func:`_noise`), the noise floor and the null model (:func:`_floor`), locate residual structure (:func:`~._locate.locate`),
    select candidates by the calibrated test (:func:`_select`), report.

    ``params``: baseline parameters to use instead of fitting (REPORT ``baseline.params`` format),
    held fixed in every test; with ``refit`` they are taken as an estimate, as a fitted baseline's
    are: the tests keep the baseline's linearised refit and its parameter count.
    ``friction``: ``lugre`` (default), ``stribeck`` or ``coulomb_viscous``. ``fit_offset``: a
    constant torque offset in the baseline. ``candidates``: a subset of candidate ids.
    ``config``: a :class:`DiagnoseConfig`; keyword ``settings`` override its fields (``alpha=``,
    ``block_s=``, ``top_k=``, ``max_effects=``, ``null_draws=``...).
    """
    t_start = time.time()
    if refit and params is None:
        raise ValueError("diagnose: refit=True takes the given params as an estimate; pass params")
    cfg = dataclasses.replace(config or DiagnoseConfig(), **settings)
    pool = dict(CANDIDATES) if candidates is None else {c: CANDIDATES[c] for c in candidates}
    frozen = params is not None and not refit
    prep, split = _prepare(rec, cfg, params, friction, fit_offset, refit)
    split = _predicted(prep, split, fit_offset, cfg.resolved_share)
    prediction = np.asarray(M.predict(prep.base, prep.kin), float)
    r0 = (np.asarray(prep.rec.torque) - prediction) * split.keep
    prep = _noise(prep, prediction, cfg)
    floor = _floor(prep, split, cfg, fit_offset, r0)
    flags = _filter_lags(prep)
    loc0 = _locate(prep, split, floor, cfg, prep.base, r0, flags, floor.ratio <= cfg.at_floor)
    start = _Reference(prep.base, _all_specs(prep.base, floor.scales, fit_offset, freeze_baseline=frozen), r0)
    final, accepted, log = _select(prep, split, floor, cfg, pool, fit_offset, frozen, progress, start)
    current, r_cur = final.model, final.r
    loc_cur = (_locate(prep, split, floor, cfg, current, r_cur, flags,
                       _rms(r_cur, split.val) <= cfg.at_floor * floor.floor_nm) if accepted else loc0)
    attribution = _attribute(prep, split, floor, cfg, current, r_cur, fit_offset, frozen)
    # the held-out error reported: cross-validated over the block phases, as the selection's test
    tau = np.asarray(prep.rec.torque)
    cv = (_rms(start.cross_validated(prep.kin, tau, split, cfg), split.cv_mask),
          _rms(final.cross_validated(prep.kin, tau, split, cfg), split.cv_mask))
    return _report(prep, split, floor, cfg, r0, loc0, current, r_cur, loc_cur, accepted, log, attribution,
                   cv, t_start)


def _window(prep) -> int:
    """The smoothing window of the attribution's derivatives: the conditioning's."""
    return prep.cond.window if prep.cond.source != "recording" else 5


def _attribute(prep, split, floor, cfg, model, r, fit_offset, frozen):
    """What the residual left by the selection follows, from the term library (:mod:`._attribute`)."""
    from ._attribute import attribute

    ctx = _context(prep, split, floor, model, r, cfg)
    window = _window(prep)
    return attribute(model, _all_specs(model, floor.scales, fit_offset, freeze_baseline=frozen), ctx, prep.kin, split.rows,
                     split.val, split.blocks, floor.null, cfg.draws, cfg.alpha_attribute, window, cfg.max_terms,
                     seed=cfg.seed + 1000, nuisance=floor.known["nuisance"],
                     quantised_derivatives=_quantised_derivatives(prep.cond),
                     at_floor_nm=cfg.at_floor * floor.floor_nm, motion=prep.lines, cond=prep.cond,
                     keep=split.keep, folds=split.folds)


def _report(prep, split, floor, cfg, r0, loc0, current, r_cur, loc_cur, accepted, log, attribution,
            cv, t_start) -> Diagnosis:
    rec, base, kin, val, w = prep.rec, prep.base, prep.kin, split.val, split.w
    scales = floor.scales
    ratio = floor.ratio
    cond = prep.cond
    blocks = split.blocks
    recording = RecordingInfo(
        source=rec.source, n_samples=rec.n, units=rec.units, duration=scales["D"], sample_rate_hz=scales["fs"],
        validation="one time block of ~%.3g %s in five held out (phases drawn per run of five blocks), phase %d (%d of %d samples); a candidate's "
                   "held-out test crosses phases %s%s"
                   % (M.block_length(np.asarray(rec.time), cfg.block_s), rec.units["time"], split.phase, int(val.sum()), rec.n, ", ".join(map(str, split.folds)),
                      "; %d held-out samples left out: the training blocks do not determine their model torque"
                      % split.unpredicted if split.unpredicted else ""),
        held_out_phase=int(split.phase), cross_validated_phases=[int(f) for f in split.folds])
    baseline = Baseline(
        params=M.model_params(base), rmse_nm=float(np.sqrt(np.mean(r0[w > 0] ** 2))),
        validation_rmse_nm=cv[0], fixed_phase_rmse_nm=_rms(r0, val),
        fit={**prep.info, "acceleration_attenuation": floor.attenuation, "held_out_unpredicted": split.unpredicted},
        noise_floor_nm=floor.floor_nm, torque_noise_nm=floor.torque_nm, kinematic_noise_nm=floor.kinematic_nm,
        floor_ratio=ratio, at_floor=bool(ratio <= cfg.at_floor),
        shortcoming=None if ratio <= cfg.at_floor else (
            f"the baseline's RMSE on the fixed held-out phase is {ratio:.3g}x the estimated noise floor: located "
            "structure may be the baseline's own misfit, not missing physics"
            + ("; the torque noise's profile still rises at its longest lag (colour longer than it "
               "reaches, or the signal), so the floor may be only a lower bound"
               if cond.torque_noise_open else "")
            + (f"; the torque carries no measurable noise ({floor.torque_nm:.2g} {rec.units['torque']}, "
               f"{floor.torque_nm / scales['T']:.1g} of its scale): the tests are calibrated against measurement "
               "noise, so the derivatives' numerical error and the samples' transients are significant here; "
               "a simulated recording needs measurement noise added to be diagnosed"
               if floor.torque_nm < cfg.noise_free_share * scales["T"] else "")),
        conditioning=cond.to_json(), unresolved_transient_fraction=float(prep.unresolved.mean()),
        at_rest_fraction=float(prep.at_rest.mean()))
    located = tuple(Region.from_test(x) for x in loc0["located"])
    remaining = tuple(Region.from_test(x) for x in loc_cur["located"])
    # a finding's parameters are those of the final joint model; its evidence stays that of its step
    ctx_final = _context(prep, split, floor, current, r_cur, cfg, loc_cur)
    named = {name for name, _ in accepted}  # a runner-up named at a later step is not an alternative
    missing = [Finding(name=name, explanation=type(c).explanation, params=c.describe(ctx_final),
                       validation_rmse_nm=_rms(t["ref"].cross_validated(kin, np.asarray(rec.torque), split, cfg),
                                                    split.cv_mask), delta_bic=t["delta_bic"],
                       p_validation=t["p_validation"], p_family=t["p_family"],
                       alternatives=tuple(a for a in t.get("alternatives", ()) if a["name"] not in named),
                       alternative_terms=tuple(t.get("alternative_terms", ())))
               for (name, t), c in zip(accepted, current.candidates, strict=True)]
    if remaining or attribution.found:
        words = ("Residual structure remains" + (" where listed" if remaining else "")
                 + ", and no candidate in the library explains it with a validated improvement."
                 + (" It follows: " + "; ".join(f"{t['signal']} ({t['reading']})" for t in attribution.terms)
                    + f"; with the term{'s' if len(attribution.terms) > 1 else ''} the held-out RMSE, "
                    f"cross-validated, goes from {attribution.cv_rmse_before_nm:.4g} to "
                    f"{attribution.cv_rmse_after_nm:.4g} {rec.units['torque']}."
                    + (" In this fit " + cancel_words(attribution.fit_rms_nm, attribution.sum_rms_nm,
                                                      rec.units["torque"]) + "."
                       if attribution.nearly_cancel else "")
                    if attribution.found else ""))
        missing.append(Finding(name="unexplained", explanation=words,
                               params={"regions": [x.to_json() for x in remaining[:10]],
                                       "attribution": attribution.to_json()},
                               validation_rmse_nm=cv[1]))
    names = [a[0] for a in accepted]
    verdict = "+".join(names + (["unexplained"] if (remaining or attribution.found) else [])) or "none"
    improved = Improved(
        params={**M.model_params(current), **{c.id: c.describe(ctx_final) for c in current.candidates}},
        rmse_nm=float(np.sqrt(np.mean(r_cur[w > 0] ** 2))), validation_rmse_nm=cv[1],
        fixed_phase_rmse_nm=_rms(r_cur, val))
    arrays = DiagnosisArrays(rec=rec, kin=kin, baseline_model=base, improved_model=current, r0=r0, r1=r_cur,
                             val=val, blocks=blocks, loc0=loc0, loc1=loc_cur,
                             attribution=attribution, kinematic_errors=floor.kinematic_errors,
                             keep=split.keep)
    return Diagnosis(recording=recording, baseline=baseline, alpha=cfg.alpha, kappa_long_run_variance=loc0["kappa"],
                     verdict=verdict, mismatch=located, n_tests=loc0["n_tests"], missing_physics=tuple(missing),
                     improved=improved, selection_log=log, seconds=time.time() - t_start, arrays=arrays,
                     config=cfg.to_json(), attribution=attribution.to_json())


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

