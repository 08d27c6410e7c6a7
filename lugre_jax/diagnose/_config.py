"""Every setting of the diagnosis in one place, each with the reason for its value."""

from __future__ import annotations

import dataclasses
import math


@dataclasses.dataclass(frozen=True)
class DiagnoseConfig:
    """Settings of :func:`~lugre_jax.diagnose.diagnose` (a frozen value; ``dataclasses.replace`` to vary).

    Error rates:

    - ``alpha`` (0.05): the family-wise false-alarm rate of a whole diagnosis on a recording the
      baseline model describes, split in three equal shares: locating residual structure (Holm
      over the residual tests), naming a candidate (each step's candidates against the simulated
      null, min-P) and attributing what remains to a term of the library (the same null, min-P);
      a recording is called ``none`` only if none of the three fires (Bonferroni over the three).
    - ``null_draws`` (None: ``ceil(6/alpha) - 1``, 119 at the default alpha): simulated recordings
      per test; p-values are multiples of 1/(null_draws + 1) and each test is held at a third of
      ``alpha``, so the default fits exactly two of those steps into ``alpha/3``: a test rejects at
      p <= ``alpha/3`` and its size is ``alpha/3`` itself (with 99 draws only 1/100 fits, a size of
      0.6 ``alpha/3``). A given number must keep 1/(null_draws + 1) below ``alpha/3`` (fewer draws
      could never name anything).
    - ``max_terms`` (2): terms the attribution adds at most.
    - ``kinematic_draws`` (8): draws of the kinematics' errors (each a fresh conditioning of the
      recording); the torque noise is drawn afresh for every null draw, these are cycled. Eight
      gives the systematic part of the errors (their mean, which does not average out through a
      nonlinear model) to a third of its spread.
    - ``seed`` (0): of the null draws; a diagnosis is reproducible.

    The selection:

    - ``max_effects`` (3): greedy steps; a fourth effect at the concealed level is beyond what the
      studies can show.
    - ``top_k`` (4): significant candidates refitted jointly per step (the refits dominate the cost),
      in order of gain beyond their null mean; the first that is plausible and identifiable takes
      the step's one held-out test, at ``alpha`` (``alpha_confirm``): cross-validated over the
      block phases, one-sided. The false-alarm bound of a step rests on the naming test (a third
      of ``alpha``); the held-out test only removes names, so that a finding improves held-out
      prediction, and where the simulated null misses structure the baseline leaves (a plant
      outside the baseline's model class) it alone bounds the chance that a step names a candidate
      adding nothing to held-out prediction, at ``alpha`` (one test per step needs no correction
      over tries). A held-out comparison has about half the z of the in-sample gain for the same
      effect, so a stricter share of ``alpha`` would cost most of the power at the concealed level.
    - The rival test (no number of its own): a candidate that passed the held-out test is not named
      when a term of the attribution library (with the model's linearised refit) predicts the same
      cross-validated phases better, one-sided, Bonferroni over the terms at ``alpha_name``. A
      physics outside the eight that a candidate partly absorbs is then left to the attribution; a
      correct candidate loses its name this way at most at ``alpha_name``.
    - ``start_correlation`` (0.8): a candidate's starts along a shape parameter (the backlash's
      width, tried from the smallest plausible gap to the bound; the compliance's natural frequency,
      0.5-20 Hz) are spaced on each recording so that
      neighbouring starts' torque shapes correlate at least this much there; a gap midway between
      two starts then correlates at least cos(arccos(0.8)/2) = 0.95 with the nearer one's, which keeps
      90 % of its one-column gain (the width's own derivative column recovers part of the rest). A
      closer spacing adds starts, and so cost and a slightly higher null maximum, for little gain.
    - ``max_steps`` (80): Levenberg-Marquardt steps of a refit, warm-started.
    - ``resolution`` (0.15): the smallest structure locate claims, in units of the noise floor: its
      binned means, its cross-correlations with the velocity and its sign and the friction trend must
      exceed it (their squared share, 0.0225, for the whiteness test). Below it sit the inverse
      model's own errors in variables at the slowest speeds, which leave means of that order even with
      the true parameters. 0 leaves the calibrated tests alone. (The attribution's terms are decided by
      their calibrated tests alone: what smoothing the true motion leaves is a nuisance column.)
    - ``shape_resolution`` (0.05): the friction-shape bands' margin beyond their errors-in-variables
      mean, in units of the noise floor (the bands average over many samples, so a smaller share of
      what the slowest speeds leave is enough).
    - ``identifiability_z`` (3.0): a named effect's key parameter must be this many standard errors
      from its no-effect value in the joint fit (a candidate the excitation cannot determine is not
      named even when its shapes reduce the residual).

    The baseline and its floor:

    - ``block_s`` (None: ~1 s, at least 25 blocks): length of the interleaved validation blocks;
      every fifth block is held out.
    - ``at_floor`` (1.1): validation RMSE over the estimated floor at or below which the baseline
      counts as at its floor (a 10 % excess is what the floor estimate resolves).
    - Dwells (with a velocity sensor: runs of at least one conditioning window, and 5 samples, whose
      conditioned velocity, and its mean over the run, are within ``norm.isf(alpha/2)`` noise std
      of zero) are left out of fit, floor and tests:
      there the bristle state is set by presliding motion below the sensors' resolution and by the
      history before the stop, so a correct inverse model misses the friction by up to the
      breakaway level (no number of its own: the rest test runs at ``alpha``, and a shorter run is
      a passage through zero the smoothed kinematics resolve).
    - ``min_resolved`` (100): resolved training samples a baseline fit needs (about ten parameters).
    - ``resolved_share`` (0.5): a sample's kinematics count as resolved where the smoothing-bias bound
      there (a third of the change of the acceleration, or of the whole model torque, from the window
      W to 2W-1; and the acceleration's change from each narrower window W/2, W/4, ... down to 5
      samples, where it is beyond that change's noise at ``alpha`` family-wise) is below this share
      of the torque noise; elsewhere (a sharp transient seen through a
      long window) the torque is not known from the samples, and the sample leaves the fit, the
      validation and the tests; so does a sample whose model torque the kinematics' noise alone
      (the kinematic draws through the fitted baseline, rms) moves by more than this share. The
      same share bounds a held-out sample's prediction error (its
      leverage under the training blocks) and the model torque's third differences kept out of the
      torque-noise estimate. A bias of half the noise adds at most a quarter of the noise variance
      where the bound is reached, and the bound is an upper one.
    - ``max_event_share`` (0.6) and ``event_alpha`` (1e-3): the held-out phase moves off the fixed one
      when that phase holds more than this share of a kind of event (reversals, bursts of
      acceleration; 0.2 is due) and more than chance alignment allows (binomial tail below
      ``event_alpha``): an excitation periodic in five blocks would otherwise keep every reversal
      from the fit. Six reversals with four in one phase (p 0.017) stay.
    - ``bristle_memory_share`` (0.1): after a transient the velocity-only path cannot follow, samples
      are left out until the wrong bristle state it leaves can bring at most this share of the
      torque noise (the bias then adds 1 % to the noise variance, a tenth of what the floor resolves).
    - ``outlier_std`` (4.0): in the torque-noise profile, a lag-k third difference further than this many
      robust stds from its lag's median is left out as signal (a fast but resolved change, as the
      friction's rise through a reversal; a Gaussian noise puts 6e-5 of its mass there).
    - ``colour_chi2`` (16.0): the torque noise is read as coloured (AR(1)) only when that profile
      fits the lags better than white noise by this chi-square (a four-standard-error improvement:
      a white noise read as coloured puts the floor too high); the broader colours (a white part plus
      an ARMA part) only when they fit better again by as much, and the profile rises over its first
      four lags by its square root in standard errors.
    - ``big_acceleration`` (0.2): accelerations above this share of the recording's acceleration
      scale identify the inertia (its start in the fit) and, as events, must stay in the fit (the
      held-out phase's event rule); below it the inertial torque is within a few noise std of the
      friction's and the least squares for J is dominated by the friction model's error.
    - ``far_presliding_over_p`` (1e-4 ... 3e-2), ``far_fs_over_fc`` (1.0001, 1.5, 2.5) and
      ``far_vs_over_v`` (0.003 ... 0.1): the grid of further fit starts, independent of the measured
      values. Where the data cannot give sigma0 or the Stribeck hump (a stiff position loop, a
      differentiated encoder, steps instead of reversals, no constant-speed stretch) the fit
      otherwise settles in a static-friction basin (sigma0 -> 1e5) or a humpless one; the grid spans
      pre-sliding lengths max(Fs, Fc)/sigma0 over four decades of the position span P, and Stribeck
      humps up to 2.5 Fc over 1.5 decades of the speed scale V. The same humps are searched again
      on the joint model after each accepted finding (``_select.hump_restart``).
    - ``shape_bands`` (10): at most this many log-speed bands of the friction-shape test, each at
      least a factor 1.5 wide (a Stribeck fall spans about a decade of speed; more bands cost each
      band's mean its samples).
    - ``gravity_min_variation`` (0.05): a fitted gravity must vary over the recording's positions by
      at least this share of its mean torque (a constant offset fitted as a gravity varies far less,
      a load far more); below it the angle dependence is not shown.
    - ``noise_free_share`` (1e-6): a torque noise below this share of the torque's scale is no
      measurement's (a 20-bit converter's step is 1e-6 of its range): the recording is taken as
      noise-free (a simulation's output), its derivatives are used as loaded (no smoothing is
      needed), and the report says that its tests, calibrated against measurement noise, then find
      the derivatives' numerical error significant.
    - ``rechoose_share`` (0.05): the conditioning window is chosen again for the fitted inertia
      when that lowers the kinematic torque error by more than this share of the torque noise
      variance (the floor would change by ~2.5 %). With the inertia unchanged, another window is
      taken where the fitted baseline's training residual is significantly lower on it (one-sided
      at ``alpha``, Bonferroni over the windows): the residual measures the kinematics' error the
      window rule only estimates.
    """

    alpha: float = 0.05
    null_draws: int | None = None
    kinematic_draws: int = 8
    seed: int = 0
    max_effects: int = 3
    max_terms: int = 2
    top_k: int = 4
    max_steps: int = 80
    resolution: float = 0.15
    shape_resolution: float = 0.05
    identifiability_z: float = 3.0
    block_s: float | None = None
    at_floor: float = 1.1
    min_resolved: int = 100
    resolved_share: float = 0.5
    max_event_share: float = 0.6
    event_alpha: float = 1e-3
    rechoose_share: float = 0.05
    noise_free_share: float = 1e-6
    outlier_std: float = 4.0
    colour_chi2: float = 16.0
    big_acceleration: float = 0.2
    far_presliding_over_p: tuple = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2)
    far_fs_over_fc: tuple = (1.0001, 1.5, 2.5)
    far_vs_over_v: tuple = (0.003, 0.01, 0.03, 0.1)
    shape_bands: int = 10
    gravity_min_variation: float = 0.05
    bristle_memory_share: float = 0.1
    start_correlation: float = 0.8

    def __post_init__(self):
        if not 0.0 < self.alpha < 1.0:
            raise ValueError(f"DiagnoseConfig.alpha: expected a number in (0, 1), got {self.alpha}")
        if self.null_draws is not None and not (self.null_draws + 1) * self.alpha > 3.0:
            raise ValueError(f"DiagnoseConfig.null_draws: expected at least {math.floor(3.0 / self.alpha)} at "
                             f"alpha {self.alpha:g} (p-values step by 1/(null_draws + 1), which must be below "
                             f"alpha/3), got {self.null_draws}")
        if self.top_k < 1:
            raise ValueError(f"DiagnoseConfig.top_k: expected at least 1, got {self.top_k}")
        if self.kinematic_draws < 1:
            raise ValueError(f"DiagnoseConfig.kinematic_draws: expected at least 1, got {self.kinematic_draws}")
        for name, lo, hi in (("resolved_share", 0.0, math.inf), ("max_event_share", 0.0, 1.0),
                             ("event_alpha", 0.0, 1.0), ("outlier_std", 0.0, math.inf),
                             ("colour_chi2", 0.0, math.inf), ("big_acceleration", 0.0, math.inf),
                             ("gravity_min_variation", 0.0, math.inf), ("noise_free_share", 0.0, 1.0),
                             ("start_correlation", 0.0, 1.0)):
            x = getattr(self, name)
            if not lo < x < hi:
                raise ValueError(f"DiagnoseConfig.{name}: expected a number in ({lo:g}, {hi:g}), got {x}")
        for name in ("resolution", "shape_resolution"):
            x = getattr(self, name)
            if not (math.isfinite(x) and x >= 0):
                raise ValueError(f"DiagnoseConfig.{name}: expected a share of the noise floor >= 0, got {x}")
        if self.shape_bands < 2:
            raise ValueError(f"DiagnoseConfig.shape_bands: expected at least 2, got {self.shape_bands}")
        for name in ("far_presliding_over_p", "far_fs_over_fc", "far_vs_over_v"):
            x = getattr(self, name)
            if not (isinstance(x, tuple) and all(math.isfinite(q) and q > 0 for q in x)):
                raise ValueError(f"DiagnoseConfig.{name}: expected a tuple of positive numbers, got {x!r}")
        if self.block_s is not None and not self.block_s > 0:
            raise ValueError(f"DiagnoseConfig.block_s: expected a positive time, got {self.block_s}")

    @property
    def draws(self) -> int:
        """The number of null draws used: ``null_draws``, or ``ceil(6/alpha) - 1``."""
        return self.null_draws if self.null_draws is not None else math.ceil(6.0 / self.alpha - 1e-9) - 1

    @property
    def alpha_locate(self) -> float:
        return self.alpha / 3.0

    @property
    def alpha_name(self) -> float:
        return self.alpha / 3.0

    @property
    def alpha_confirm(self) -> float:
        return self.alpha

    @property
    def alpha_attribute(self) -> float:
        return self.alpha / 3.0

    def to_json(self) -> dict:
        out = {k: list(v) if isinstance(v, tuple) else v for k, v in dataclasses.asdict(self).items()}
        return out | {"null_draws": self.draws}
