"""The null distribution of every candidate's gain, computed for the recording at hand.

Naming a candidate is a test of "the current model is complete" against "this candidate adds to
it". Its statistic is the drop of the training residual's sum of squares when the candidate's
torque shapes are added to the current model's, to first order: the squared norm of the residual
projected on the candidate's Jacobian columns made orthogonal to the current model's
(``||P_{C|B} r||^2``). Under the null the residual is the measurement chain's error, so the
statistic's distribution follows by simulating that chain (a parametric bootstrap):

* the torque channel's noise, an AR(1) of the estimated standard deviation and colour;
* the kinematics' errors, drawn as the conditioning made them
  (:func:`._condition.perturbed_kinematics`: fresh sensor errors on the measured signals, the same
  Savitzky-Golay window), carried through the current model: the scatter a correct model keeps
  because its inputs are estimated, which a candidate must not be named for absorbing.

Each draw is scored as the recording is: its columns (the current model's basis, the candidates'
Jacobians) are built through the kinematics its residual was made through (:class:`Views`: the
recording's columns share its kinematic errors with its residual, and so must a draw's), and for
candidates whose starting points are searched on the residual (a ripple's period, a resonance's
frequency) the search is repeated on the draw's own residual, so the null includes the
look-elsewhere effect.
Family-wise control over the candidates of a step is Westfall-Young's step-down min-P: each gain is
put on the scale of its own null's tail probability, and a candidate's adjusted p-value is the share
of draws whose smallest tail probability over it and the candidates less significant than it is at
most its own (:func:`min_p`).
"""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from scipy import stats
from scipy.signal import lfilter

from . import _model as M


@dataclasses.dataclass(frozen=True)
class NullModel:
    """What the residual of a complete model is made of, on this recording.

    ``torque_sd`` and ``torque_phi``: the torque channel's noise (AR(1) standard deviation and
    coefficient; ``torque_arma``, where set, the broader colour of :func:`._condition.torque_noise_std`,
    which then replaces the AR(1)); ``kinematic_draws``: pairs ``(synthetic, reference)`` of conditioned kinematics
    from :func:`._condition.perturbed_kinematics` (model-free; the current model turns each pair
    into a torque error), scaled by ``kinematic_scale`` (at most 1: see ``diagnose``'s floor);
    ``blocks``: the recording's time-block ids, over which :func:`null_draws` mixes the kinematic
    draws."""

    torque_sd: float
    torque_phi: float
    kinematic_draws: tuple
    blocks: np.ndarray = dataclasses.field(repr=False, compare=False)
    kinematic_scale: float = 1.0
    torque_arma: tuple = ()

    def torque_noise(self, rng: np.random.Generator, shape: tuple[int, int]) -> np.ndarray:
        if self.torque_arma:
            from ._condition import broader_colour_noise

            return self.torque_sd * broader_colour_noise(rng, shape, self.torque_arma)
        e = rng.standard_normal(shape)
        phi = float(np.clip(self.torque_phi, 0.0, 0.999))
        if phi > 0:
            e[:, 0] /= np.sqrt(1.0 - phi ** 2)  # stationary start
            e = lfilter([np.sqrt(1.0 - phi ** 2)], [1.0, -phi], e, axis=1)
        return self.torque_sd * e

    def kinematic_errors(self, model, kin, centred: bool = True) -> np.ndarray:
        """Torque error each kinematic draw brings through ``model`` (draws x n): prediction on the
        reference minus prediction on the synthetic kinematics (the sign of a residual); ``centred``:
        less their mean over the draws."""
        out = []
        for syn, ref in self.kinematic_draws:
            out.append(M.predict(model, _as_kin(kin, ref)) - M.predict(model, _as_kin(kin, syn)))
        if not out:
            return np.zeros((0, kin.v.shape[0]))
        # their spread only: the draws' mean (the systematic error of a smoothed reference against
        # its own re-quantisation) overstates what the recording's residual keeps, which locate
        # takes as a known shape instead
        d = np.asarray(out)
        return self.kinematic_scale * (centred_draws(d) if centred else d)


def centred_draws(d: np.ndarray) -> np.ndarray:
    """The draws (rows) less their mean, each rescaled to the spread of one realisation (centring on
    K draws leaves (K - 1)/K of the variance); a single draw unchanged."""
    k = d.shape[0]
    return (d - d.mean(axis=0)) * np.sqrt(k / (k - 1.0)) if k > 1 else d


def _as_kin(kin, x):
    v, a, th = (jnp.asarray(y, float) for y in x)
    return eqx.tree_at(lambda k: (k.v, k.a, k.theta, k.dpath), kin, (v, a, th, jnp.diff(th)))


def null_model(rec_in, cond, path: str, draws: int, blocks: np.ndarray) -> NullModel:
    from ._condition import perturbed_kinematics

    pairs = tuple(perturbed_kinematics(rec_in, cond, path, seed) for seed in range(draws))
    return NullModel(float(cond.torque_noise), float(cond.torque_noise_colour), pairs, blocks,
                     torque_arma=tuple(cond.torque_noise_arma))


def _orth(X: np.ndarray, rtol: float = 1e-8) -> np.ndarray:
    """Orthonormal basis of the column space of X (columns below ``rtol`` of the largest dropped)."""
    if X.shape[1] == 0:
        return X
    U, s, _ = np.linalg.svd(X, full_matrices=False)
    return U[:, s > rtol * max(float(s[0]), 1e-300)]


def jacobian(model, specs, kin, rows) -> np.ndarray:
    """d(prediction)/d(parameter) at ``model`` on the training ``rows`` (n_rows x k), in the fit's
    unbounded coordinates (the column space is what matters, and it is the same)."""
    if not specs:
        return np.zeros((int(rows.sum()), 0))
    space = M.FitSpace(specs)
    model = M.clip_into(space, model)
    n = kin.v.shape[0]
    Jm = np.asarray(M._jac_u(space.to_u(model), space.paths, space.bounds, model, M.pad_kinematics(kin),
                             M.pad(jnp.zeros(n)), M.pad(jnp.ones(n)), jnp.asarray(1.0)))
    return Jm[:n][rows]


JAC_BATCH = 32  # Jacobians per vectorised call: bounded memory, one compilation


def jacobians(trials: list, specs, kin, rows, out=None) -> np.ndarray:
    """:func:`jacobian` of several models that differ only in the parameters of ``specs``, in one
    vectorised call (trials x n_rows x k), written into ``out`` when given."""
    space = M.FitSpace(specs)
    us = [space.to_u(t) for t in trials]
    m = len(us)
    us = jnp.stack(us + [us[-1]] * (JAC_BATCH - m % JAC_BATCH if m % JAC_BATCH else 0))  # one compiled batch size
    n = kin.v.shape[0]
    J = np.asarray(_jac_many(us, space.paths, space.bounds, trials[0], M.pad_kinematics(kin), M.pad(jnp.zeros(n)),
                             M.pad(jnp.ones(n))))
    return np.take(J[:m, :n], np.flatnonzero(rows), axis=1, out=out)


@eqx.filter_jit
def _jac_many(us, paths, bounds, template, kin, tau, w):
    import jax

    return jax.vmap(lambda u: jax.jacfwd(M._residual_fn)(u, (paths, bounds, template, kin, tau, w, 1.0)))(us)


def block_pick(blocks: np.ndarray, k: int, n_draws: int, rng: np.random.Generator) -> np.ndarray:
    """For ``n_draws`` series, the realisation (of ``k``) each sample is taken from, block by block
    (draws x n): :func:`block_mixed`'s choice, kept so that everything a draw is seen through (its
    residual and its columns) comes from the same realisation."""
    _, b = np.unique(np.asarray(blocks), return_inverse=True)
    return rng.integers(0, k, size=(n_draws, int(b.max()) + 1))[:, b]


def block_mixed(d: np.ndarray, blocks: np.ndarray, n_draws: int, rng: np.random.Generator) -> np.ndarray:
    """``n_draws`` series (draws x n) made of the rows of ``d`` (K x n) block by block: each time
    block of each series taken from one of the K rows at random (a block bootstrap over the K
    realisations). The kinematics' errors are local in time (a smoothing window, the bristles'
    memory), so a block of one realisation is a realisation of that block; mixed, the K draws give
    ``n_draws`` nearly independent series instead of K repeated ones, whose few values would set
    the null's tail (a term that a fresh realisation happens to follow would beat all K of them
    with probability 1/(K + 1), whatever the draws)."""
    return d[block_pick(blocks, d.shape[0], n_draws, rng), np.arange(d.shape[1])[None, :]]


@dataclasses.dataclass(frozen=True)
class Draws:
    """Null draws of a complete model's residual (``E``, draws x n, every sample) and the kinematic
    realisation behind each draw's sample (``pick``, draws x n, an index into
    ``null.kinematic_draws``; zeros without them)."""

    E: np.ndarray
    pick: np.ndarray


def sample(model, kin, null: NullModel, n_draws: int, seed: int) -> Draws:
    """``n_draws`` simulated residuals of ``model`` if it were complete: the torque noise plus the
    kinematics' errors carried through the model (the kinematic draws mixed block by block over
    ``null.blocks``, :func:`block_pick`); no refit is taken out, so a test referred to them is
    slightly conservative."""
    rng = np.random.default_rng(seed)
    n = kin.v.shape[0]
    E = null.torque_noise(rng, (n_draws, n))
    eiv = null.kinematic_errors(model, kin)
    if not eiv.shape[0]:
        return Draws(E, np.zeros((n_draws, n), int))
    pick = block_pick(null.blocks, eiv.shape[0], n_draws, rng)
    return Draws(E + eiv[pick, np.arange(n)[None, :]], pick)


def null_draws(model, kin, null: NullModel, n_draws: int, seed: int) -> np.ndarray:
    """:func:`sample`'s residuals alone (draws x n)."""
    return sample(model, kin, null, n_draws, seed).E


class Views:
    """Columns built from the kinematics as each null draw sees them (errors in variables).

    The recording's columns (a candidate's Jacobian, a term of the library) are built from the
    same estimated kinematics whose errors are in its residual, so the two are correlated: a column
    that follows the acceleration's error gains from a correct model's residual. A draw reproduces
    this only when its columns are built from the kinematics its residual was made through: the
    reference path moved by ``kinematic_scale`` times the synthetic one's error, realisation by
    realisation as the draw's blocks took them (``pick``)."""

    def __init__(self, null: NullModel, kin, pick: np.ndarray):
        pairs = null.kinematic_draws
        self.ref = _as_kin(kin, pairs[0][1]) if pairs else kin
        self.syn = [_as_kin(kin, syn) for syn, _ in pairs]
        self.scale = float(null.kinematic_scale) if pairs else 0.0
        self.pick = pick

    def build(self, f):
        """``f(kin)`` (m x k, or m) on the reference and on every synthetic path: ``(ref, syn)``,
        2-D; ``syn`` is K x m x k (empty without kinematic draws)."""
        def one(k):
            x = np.asarray(f(k), float)
            return x.reshape(x.shape[0], -1)
        ref = one(self.ref)
        syn = np.stack([one(k) for k in self.syn]) if self.syn and self.scale > 0 else np.zeros((0,) + ref.shape)
        return ref, syn

    def at(self, built, d: int, rows=None) -> np.ndarray:
        """Draw ``d``'s columns from :meth:`build`'s output (on ``rows`` when it was built on them)."""
        ref, syn = built
        if not syn.shape[0]:
            return ref
        p = self.pick[d] if rows is None else self.pick[d][rows]
        return (1.0 - self.scale) * ref + self.scale * syn[p, np.arange(ref.shape[0])]


class NullBasis:
    """The current model's Jacobian with the ``nuisance`` columns, on every sample of the recording
    (``JB``) and of each draw's kinematics (:meth:`JB_at`); their orthonormal bases on the training
    ``rows`` (``QB``, :meth:`Q`); and every draw's residual there with its own basis projected out
    (``R``, rows x draws: what a refit leaves)."""

    def __init__(self, current, base_specs, kin, rows, null: NullModel, n_draws: int, seed: int, nuisance=None):
        n = kin.v.shape[0]
        self.rows = rows
        self.draws = sample(current, kin, null, n_draws, seed)
        self.views = Views(null, kin, self.draws.pick)
        everywhere = np.ones(n, bool)
        self.nuisance = None if nuisance is None else np.asarray(nuisance, float).reshape(n, -1)
        self.JB = self._with_nuisance(jacobian(current, base_specs, kin, everywhere))
        self.QB = _orth(self.JB[rows])
        self._JB_views = self.views.build(lambda k: jacobian(current, base_specs, k, everywhere))
        self._Q = [_orth(self.JB_at(d)[rows]).astype(np.float32) for d in range(n_draws)]
        Er = self.draws.E[:, rows]
        self.R = np.column_stack([Er[d] - self._Q[d] @ (self._Q[d].T @ Er[d]) if self._Q[d].shape[1] else Er[d]
                                  for d in range(n_draws)])

    def _with_nuisance(self, JB):
        return JB if self.nuisance is None else np.column_stack([JB, self.nuisance])

    def Q(self, d: int) -> np.ndarray:
        return self._Q[d]

    def JB_at(self, d: int) -> np.ndarray:
        """Draw ``d``'s baseline Jacobian (and nuisance) on every sample."""
        return self._with_nuisance(self.views.at(self._JB_views, d))


def chi2_log_sf(x: np.ndarray, T: np.ndarray) -> np.ndarray:
    """``log P(G >= x)`` per column, ``G`` the scaled chi-square ``c*chi2(nu)`` whose mean and
    variance are those of the column's null draws ``T`` (draws x tests; Satterthwaite's match).

    A gain is ``||P r||^2``: for Gaussian noise a weighted sum of chi-square(1) terms, which the
    matched law follows closely in the tail. Its role is to put tests of different size and
    degrees of freedom on one scale (a tail probability), not to be exact: the family's reference
    stays the draws themselves. A column whose draws are all equal gets ``log 1 = 0``."""
    m = np.mean(T, axis=0)
    var = np.var(T, axis=0, ddof=1) if T.shape[0] > 1 else np.zeros_like(m)
    ok = (m > 0) & (var > 0)
    c = np.where(ok, var / np.maximum(2.0 * m, 1e-300), 1.0)
    nu = np.where(ok, np.clip(2.0 * m ** 2 / np.where(ok, var, 1.0), 1e-3, 1e8), 1.0)
    out = stats.chi2.logsf(np.maximum(x, 0.0) / c, nu)
    return np.where(ok, out, 0.0)


def rejects(p, alpha: float):
    """A permutation-style p-value ``(1 + count)/(draws + 1)`` rejects at ``p <= alpha``: its size is
    then at most ``alpha`` (exactly ``alpha`` when ``alpha * (draws + 1)`` is a whole number, which
    the default draws make of ``alpha/3``). The tolerance absorbs the rounding of ``2/120`` against
    ``0.05/3``."""
    return np.asarray(p) <= alpha * (1.0 + 1e-9)


def normal_log_sf(x: np.ndarray, T: np.ndarray) -> np.ndarray:
    """``log P(G >= x)`` per column, ``G`` normal with the mean and standard deviation of the
    column's null draws ``T`` (draws x tests): the scale of :func:`min_p` for statistics that can
    be negative (a held-out gain). A column whose draws are all equal gets ``log 1 = 0``."""
    m = np.mean(T, axis=0)
    sd = np.std(T, axis=0, ddof=1) if T.shape[0] > 1 else np.zeros_like(m)
    ok = sd > 0
    return np.where(ok, stats.norm.logsf((x - m) / np.where(ok, sd, 1.0)), 0.0)


def min_p(obs: np.ndarray, T: np.ndarray, tail=chi2_log_sf):
    """Raw and family-wise p-values of the observed statistics ``obs`` against null draws ``T``
    (draws x tests), and each statistic over its null mean (``standardised``, for the report).

    Family-wise control is Westfall-Young's step-down min-P (Westfall and Young 1993, algorithm
    2.8): every statistic, observed and drawn, is turned into its tail probability under its own
    null (``tail``: :func:`chi2_log_sf` for gains, which are never negative; :func:`normal_log_sf`
    for held-out gains); the tests are ordered from the most significant, and the k-th one's
    adjusted p-value is the share of draws whose smallest tail probability over the k-th and every
    less significant test is at most its own, made non-decreasing along that order. The most
    significant test's p-value is single-step min-P's, so the chance that any test rejects when no
    test has an effect is unchanged; a test behind others whose effects are real is no longer held
    to their minimum (strong family-wise control either way). Tail probabilities, unlike gains over
    their null mean, weigh tests of different degrees of freedom alike: a one-column candidate's
    heavy relative tail does not set the bar for a six-column one. Never below the raw p-value;
    resolution ``1/(draws + 1)``."""
    B = T.shape[0]
    p_raw = (1.0 + np.sum(T >= obs[None, :], axis=0)) / (B + 1.0)
    scale = np.maximum(np.mean(T, axis=0), 1e-300)
    lp_obs, lp_null = tail(obs, T), tail(T, T)
    order = np.argsort(lp_obs, kind="stable")
    # per draw, the smallest tail probability over each test and those after it in the order
    tail_min = np.minimum.accumulate(lp_null[:, order[::-1]], axis=1)[:, ::-1]
    p_step = (1.0 + np.sum(tail_min <= lp_obs[order][None, :], axis=0)) / (B + 1.0)
    p_adj = np.empty_like(p_step)
    p_adj[order] = np.maximum.accumulate(np.maximum(p_step, p_raw[order]))
    return p_raw, p_adj, obs / scale


@dataclasses.dataclass(frozen=True)
class CandidateTest:
    """The calibrated test of one step: per candidate its statistic on the recording, its raw and
    family-wise adjusted p-values against ``n_draws`` null draws (min-P over the candidates; each
    gain over its null mean is ``standardised``), and the null's 1 - alpha quantile
    of the statistic (what the recording's gain had to exceed, for the report)."""

    names: tuple
    statistic: np.ndarray
    standardised: np.ndarray
    p_raw: np.ndarray
    p_adjusted: np.ndarray
    null_quantile: np.ndarray
    best_guess: tuple
    n_draws: int

    def to_json(self) -> list:
        return [{"name": n, "gain_nm2": float(s), "gain_over_null_mean": float(z),
                 "null_quantile_nm2": float(q), "p_raw": float(p), "p_family": float(pa)}
                for n, s, z, q, p, pa in zip(self.names, self.statistic, self.standardised, self.null_quantile,
                                             self.p_raw, self.p_adjusted)]


def _key(guess) -> tuple:
    """A candidate instance's identity by value (equal guesses share a Jacobian)."""
    return (type(guess).__name__,) + tuple(np.asarray(getattr(guess, f.name), float).tobytes()
                                          for f in dataclasses.fields(guess))


def _trial(current, guess):
    return M.JointModel(current.J, current.friction, current.offset, current.candidates + (guess,))


def _complement(QB, XC):
    """Orthonormal basis of the columns of XC made orthogonal to the orthonormal QB."""
    return _orth(XC - QB @ (QB.T @ XC) if QB.shape[1] else XC, 1e-6)


def _project(Qc, R):
    """||Qc^T r||^2 for every column r of R."""
    return np.sum((Qc.T @ R) ** 2, axis=0) if Qc.shape[1] else np.zeros(R.shape[1])


def _gains(QB, XC, R):
    """||P_{C|B} r||^2 for every column r of R, C made orthogonal to B first."""
    return _project(_complement(QB, XC), R)


def best_start(g_obs, per: np.ndarray):
    """Of a candidate's fixed starting points, the one whose gain (``g_obs``, one per start) is
    largest over its own null mean (``per``: starts x draws, each start's gain on every draw), that
    mean (``unit``) and the null of the statistic: per draw, the largest gain over its start's null
    mean, times ``unit`` (so the recording's gain at the chosen start is compared in its own units).

    The starts' columns need not see the null alike (a slow column takes more of a coloured noise);
    a raw maximum would let the start with the largest null set the bar for every other, so that an
    effect along a quieter start's column counts for less. Scaled, each start weighs alike, and the
    same maximum on the recording and on every draw keeps the test exact."""
    per = np.asarray(per, float)
    m = np.maximum(per.mean(axis=1), 1e-300)
    k = int(np.argmax(np.asarray(g_obs, float) / m))
    return k, float(m[k]), np.max(per / m[:, None], axis=0) * float(m[k])


def test_candidates(current, base_specs, candidates: dict, ctx_obs, kin, rows, null: NullModel, n_draws: int,
                    alpha: float, seed: int = 0, nuisance=None) -> CandidateTest:
    """Test every candidate against the null simulated for this recording (module docstring).

    ``candidates``: name -> prototype instance; ``ctx_obs``: the candidates' context
    (:class:`~._model.Context`) on the current model's residual; ``rows``: training samples."""
    from ._locate import position_peaks_many, time_peaks_many

    residual = np.asarray(ctx_obs.residual, float)
    scales = ctx_obs.scales
    n = residual.size
    nb = NullBasis(current, base_specs, kin, rows, null, n_draws, seed, nuisance)
    QB, Rn, views = nb.QB, nb.R, nb.views
    r_obs = residual[rows][:, None]

    # each start's Jacobian made orthogonal to B, once: grid starts recur in every null draw
    cache: dict = {}

    def trial_specs(guess):
        trial = _trial(current, guess)
        return trial, M.candidate_specs(trial, len(trial.candidates) - 1, scales)

    def basis(guess):
        key = _key(guess)
        if key not in cache:
            trial, specs = trial_specs(guess)
            cache[key] = _complement(QB, jacobian(trial, specs, kin, rows))
        return cache[key]

    def draw_gain(d, X):
        return float(_gains(nb.Q(d), X, Rn[:, d:d + 1])[0])

    names, obs, null_stats, best, units = [], [], [], [], []
    ctx_draws = None
    for name, inst in candidates.items():
        if not inst.applicable(ctx_obs):
            continue
        guesses = inst.initial_guesses(ctx_obs)
        if not guesses:
            continue
        g_obs = [float(_project(basis(g), r_obs)[0]) for g in guesses]
        k = int(np.argmax(g_obs))
        if getattr(type(inst), "searches_residual", False):
            # the search repeated on every draw's own residual: the look-elsewhere effect
            if ctx_draws is None:
                full = np.zeros((n_draws, n))
                full[:, rows] = Rn.T
                peaks = position_peaks_many(ctx_obs.rec.position, full)
                lines = time_peaks_many(ctx_obs.rec.time, full)
                ctx_draws = [ctx_obs.replace(residual=full[b], position_peaks=peaks[b], time_peak_hz=float(lines[b]))
                             for b in range(n_draws)]
            guesses_b = [inst.initial_guesses(c) if inst.applicable(c) else [] for c in ctx_draws]
            todo = {}
            for gs in guesses_b:
                for g in gs:
                    todo.setdefault(_key(g), g)
            keys = list(todo)
            g_null = np.zeros(n_draws)
            trials = [_trial(current, g) for g in todo.values()]
            specs = M.candidate_specs(trials[0], len(trials[0].candidates) - 1, scales) if trials else []
            for i0 in range(0, len(trials), JAC_BATCH):
                chunk = trials[i0:i0 + JAC_BATCH]
                index = {key: i for i, key in enumerate(keys[i0:i0 + JAC_BATCH])}
                ref = jacobians(chunk, specs, views.ref, rows)
                paths = views.syn if views.scale > 0 else []
                syn = np.empty((len(paths),) + ref.shape, ref.dtype)  # K x chunk x rows x k
                for j, kj in enumerate(paths):
                    jacobians(chunk, specs, kj, rows, out=syn[j])
                for b, gs in enumerate(guesses_b):
                    for g in gs:
                        i = index.get(_key(g))
                        if i is not None:
                            g_null[b] = max(g_null[b], draw_gain(b, views.at((ref[i], syn[:, i]), b, rows)))
            unit = max(float(np.mean(g_null)), 1e-300)  # the searched statistic's own null mean
        else:
            # fixed starts: each start's gain over its own null mean, the largest over the starts
            # (on the recording and on every draw alike). A raw maximum lets the start whose column
            # the null's colour or kinematic errors load most set the bar for the others
            per = np.zeros((len(guesses), n_draws))
            for i, g in enumerate(guesses):
                trial, specs = trial_specs(g)
                built = views.build(lambda kk: jacobian(trial, specs, kk, rows))
                per[i] = [draw_gain(b, views.at(built, b, rows)) for b in range(n_draws)]
            k, unit, g_null = best_start(g_obs, per)
        names.append(name)
        obs.append(g_obs[k])
        null_stats.append(g_null)
        units.append(unit)
        best.append(guesses[k])
    if not names:
        z = np.zeros(0)
        return CandidateTest((), z, z, z, z, z, (), n_draws)
    obs = np.asarray(obs)
    T = np.stack(null_stats, axis=1)  # draws x candidates
    # min-P over candidates (min_p): its resolution is 1/(n_draws + 1) whatever their number
    p_raw, p_adj, _ = min_p(obs, T)
    std_obs = obs / np.asarray(units)  # each gain over the null mean of its own start (searched: statistic)
    q = np.quantile(T, 1.0 - alpha, axis=0)
    return CandidateTest(tuple(names), obs, std_obs, p_raw, p_adj, q, tuple(best), n_draws)


def held_out_p(r0, r1, blocks, val) -> float:
    """One-sided p-value that the new model (residual ``r1``) lowers the held-out squared error of
    the current one (``r0``) on the samples ``val``.

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
