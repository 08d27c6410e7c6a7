"""What :func:`~lugre_jax.diagnose.diagnose` returns: a :class:`Diagnosis` whose ``to_json()`` is the
REPORT.json content, with the arrays and models behind it in ``arrays`` (not written).

What has a fixed schema is typed; parameter sets, the conditioning, the fit's solver record and the
selection log stay plain dicts (their keys depend on the friction law, the candidates and the
solver). Every ``to_json()`` returns its keys in the order REPORT.json has them.
"""

from __future__ import annotations

import dataclasses
from typing import Any


@dataclasses.dataclass(frozen=True)
class RecordingInfo:
    """The diagnosed recording: ``source`` (file or description), ``n_samples``, ``units`` (quantity
    -> unit), ``duration`` and ``sample_rate_hz`` (in the recording's time unit), ``validation`` (which
    samples were held out, in words), ``held_out_phase`` (the fixed held-out block phase, 0-4) and
    ``cross_validated_phases`` (the phases the held-out tests cross)."""

    source: str
    n_samples: int
    units: dict
    duration: float
    sample_rate_hz: float
    validation: str
    held_out_phase: int | None = None
    cross_validated_phases: list = dataclasses.field(default_factory=list)

    def to_json(self) -> dict:
        return {"source": self.source, "n_samples": self.n_samples, "units": self.units,
                "duration": self.duration, "sample_rate_hz": self.sample_rate_hz, "validation": self.validation,
                "held_out_phase": self.held_out_phase, "cross_validated_phases": list(self.cross_validated_phases)}


@dataclasses.dataclass(frozen=True)
class Baseline:
    """The fitted (or given) baseline model, torques in the recording's torque unit.

    ``params``: joint-model parameters (``J``, friction law's, ``offset``...; the format ``--params``
    reads). ``rmse_nm``: residual RMS on the training samples. ``validation_rmse_nm``: the held-out
    RMSE, cross-validated over the block phases (each phase predicted by a refit that did not see
    it; the selection's held-out test compares these). ``fixed_phase_rmse_nm``: the RMSE on the
    fixed held-out phase alone (the model as fitted, without that phase).
    ``fit``: the solver's record (result, steps, starts, bristle_path). ``noise_floor_nm``: per-sample
    noise estimated from the data, ``torque_noise_nm`` and ``kinematic_noise_nm`` its two parts (the
    torque channel's, and what the conditioned velocity and acceleration carry through the model; both
    at most what the baseline's residual leaves, whose upper bound caps them, so the torque channel's
    own profile estimate stays in ``conditioning.torque_noise``);
    ``floor_ratio`` = fixed-phase RMSE / floor, ``at_floor`` when it is at most ``AT_FLOOR`` (1.1),
    else ``shortcoming`` says why located structure may be the baseline's own misfit.
    ``conditioning``: how the kinematics were conditioned (``Conditioning.to_json()``);
    ``unresolved_transient_fraction``: share of samples left out as unresolved (transients the
    sampling does not resolve, and the samples at rest counted in ``at_rest_fraction``);
    ``at_rest_fraction``: share left out because their velocity is not told from rest at ``alpha``
    (the bristle state there is below what the sensors resolve).
    """

    params: dict
    rmse_nm: float
    validation_rmse_nm: float
    fit: dict
    noise_floor_nm: float
    torque_noise_nm: float
    kinematic_noise_nm: float
    floor_ratio: float
    at_floor: bool
    shortcoming: str | None
    conditioning: dict
    unresolved_transient_fraction: float
    at_rest_fraction: float = 0.0
    fixed_phase_rmse_nm: float | None = None

    def to_json(self) -> dict:
        return {"params": self.params, "rmse_nm": self.rmse_nm, "validation_rmse_nm": self.validation_rmse_nm,
                "fit": self.fit, "noise_floor_nm": self.noise_floor_nm, "torque_noise_nm": self.torque_noise_nm,
                "kinematic_noise_nm": self.kinematic_noise_nm, "floor_ratio": self.floor_ratio,
                "at_floor": self.at_floor, "shortcoming": self.shortcoming, "conditioning": self.conditioning,
                "unresolved_transient_fraction": self.unresolved_transient_fraction,
                "at_rest_fraction": self.at_rest_fraction, "fixed_phase_rmse_nm": self.fixed_phase_rmse_nm}


# Keys a located region may carry, in REPORT.json's order; the last four come from the binned
# (cluster-mean) tests only and are left out of the JSON for the others.
_REGION_OPTIONAL = ("mean_residual", "ci95", "df", "n")


@dataclasses.dataclass(frozen=True)
class Region:
    """One located mismatch: a residual test that is significant after Holm's correction.

    ``test``: ``velocity_band``, ``position_periodic``, ``time_periodic``, ``cross_correlation``,
    ``whiteness_ljung_box``, ...; ``region``: where (free-form: velocity band and direction, period,
    frequency, input and lag...); ``statistic``, ``p_value`` and the Holm-adjusted ``p_holm``. The
    binned tests add ``mean_residual``, its ``ci95``, the cluster ``df`` and the sample count ``n``
    (``None`` for the other tests).
    """

    test: str
    region: dict
    statistic: float
    p_value: float
    p_holm: float
    mean_residual: float | None = None
    ci95: list | None = None
    df: int | None = None
    n: int | None = None

    @classmethod
    def from_test(cls, x: dict) -> "Region":
        """From one entry of :func:`~lugre_jax.diagnose.locate`'s ``located`` list."""
        return cls(x["test"], x["region"], x["statistic"], x["p_value"], x["p_holm"],
                   **{k: x[k] for k in _REGION_OPTIONAL if k in x})

    def to_json(self) -> dict:
        out = {"test": self.test, "region": self.region, "statistic": self.statistic, "p_value": self.p_value,
               "p_holm": self.p_holm}
        out.update({k: getattr(self, k) for k in _REGION_OPTIONAL if getattr(self, k) is not None})
        return out


@dataclasses.dataclass(frozen=True)
class Finding:
    """One entry of the missing physics: a candidate accepted by the selection, or ``unexplained``.

    ``name``: candidate id (``position_ripple``, ``gravity``...) or ``unexplained``;
    ``explanation``: what it is, in words; ``params``: the fitted effect's parameters in the FINAL
    joint model, with every accepted effect and the baseline refitted together (free-form, the
    candidate's ``describe()``, the same as in ``Diagnosis.improved.params``; for ``unexplained``:
    ``{"regions": [...], "attribution": {...}}``, the located regions left, as
    :meth:`Region.to_json`, at most 10, and what the residual follows, ``Diagnosis.attribution``);
    ``validation_rmse_nm``: held-out RMSE of the model at the step that accepted it (it and the
    findings before it; cross-validated over the block phases, as ``Baseline.validation_rmse_nm``;
    for ``unexplained``, the final model's). The evidence it was accepted on at that step
    (``None`` for ``unexplained``, which is not a fit): ``p_family``, its gain against the null
    simulated for the recording, family-wise over the step's candidates (below a third of alpha);
    ``p_validation``, the held-out test cross-validated over the block phases (below alpha,
    ``alpha_confirm``); ``delta_bic``, for information. ``alternatives``: the step's other
    candidate that passed every check in this one's place when the held-out blocks cannot tell the
    two apart (``name``, its cross-validated ``cv_rmse_nm``, ``p_named_better``: the one-sided
    p-value that this one predicts those blocks better, above alpha); empty when the recording
    tells them apart or no other candidate passed. ``alternative_terms``: the attribution
    library's terms that, with the model before this finding refitted, lower the held-out error
    significantly beyond that refit alone and that this one does not predict significantly better
    (``term``, its ``reading``, ``cv_rmse_nm``, ``p_named_better`` above alpha): physics outside
    the eight the excitation cannot tell from this one; empty when it can.
    """

    name: str
    explanation: str
    params: dict
    validation_rmse_nm: float
    delta_bic: float | None = None
    p_validation: float | None = None
    p_family: float | None = None
    alternatives: tuple[dict, ...] = ()
    alternative_terms: tuple[dict, ...] = ()

    @property
    def unexplained(self) -> bool:
        return self.name == "unexplained"

    def to_json(self) -> dict:
        out = {"name": self.name, "explanation": self.explanation, "params": self.params,
               "validation_rmse_nm": self.validation_rmse_nm}
        out.update({k: getattr(self, k) for k in ("delta_bic", "p_validation", "p_family")
                    if getattr(self, k) is not None})
        if not self.unexplained:
            out["alternatives"] = [dict(a) for a in self.alternatives]
            out["alternative_terms"] = [dict(a) for a in self.alternative_terms]
        return out


@dataclasses.dataclass(frozen=True)
class Improved:
    """The baseline with every accepted finding, refitted jointly: ``params`` (the joint model's,
    plus one entry per candidate id with its ``describe()``), ``rmse_nm`` on the training samples,
    ``validation_rmse_nm`` and ``fixed_phase_rmse_nm`` as the baseline's. Equal to the baseline's
    when nothing was accepted."""

    params: dict
    rmse_nm: float
    validation_rmse_nm: float
    fixed_phase_rmse_nm: float | None = None

    def to_json(self) -> dict:
        return {"params": self.params, "rmse_nm": self.rmse_nm, "validation_rmse_nm": self.validation_rmse_nm,
                "fixed_phase_rmse_nm": self.fixed_phase_rmse_nm}


@dataclasses.dataclass(frozen=True)
class DiagnosisArrays:
    """In-memory results behind a :class:`Diagnosis` (for figures and experiments; not in REPORT.json).

    ``rec``: the conditioned recording the residuals belong to; ``kin``: its kinematics (bristle
    path chosen); ``baseline_model`` / ``improved_model``: ``JointModel``; ``r0`` / ``r1``: their
    residuals (0 at unresolved samples); ``val``: held-out mask; ``blocks``: time-block ids;
    ``loc0`` / ``loc1``: :func:`~lugre_jax.diagnose.locate`'s full output on ``r0`` / ``r1``
    (periodograms, every test); ``kinematic_errors``: the null's kinematic draws through the
    baseline (draws x samples, centred and scaled as the naming test's null uses them; none where
    the floor leaves them no room); ``keep``: the resolved samples.
    """

    rec: Any
    kin: Any
    baseline_model: Any
    improved_model: Any
    r0: Any
    r1: Any
    val: Any
    blocks: Any
    loc0: dict
    loc1: dict
    attribution: Any = None  # the attribution with its arrays (regressors, fits, partial residuals)
    kinematic_errors: Any = None
    keep: Any = None


@dataclasses.dataclass(frozen=True)
class Diagnosis:
    """Result of :func:`~lugre_jax.diagnose.diagnose`; ``to_json()`` is REPORT.json (what
    ``lugre-jax diagnose`` writes).

    ``verdict``: ``none`` (nothing located), the accepted names joined by ``+``, ``unexplained``,
    or the names ``+unexplained``. ``mismatch``: the regions located on the baseline's residual;
    ``n_tests``: the size of the Holm family; ``missing_physics``: accepted findings in order of
    acceptance, then ``unexplained`` if structure remains; ``selection_log``: per greedy step, each
    candidate's projected score and each joint refit's evidence and reason for rejection (plain
    dicts); ``alpha``: the family-wise false-alarm rate; ``kappa_long_run_variance``: the baseline
    residual's long-run variance factor; ``seconds``: wall time. ``arrays``: see
    :class:`DiagnosisArrays` (not in ``to_json()``).
    """

    recording: RecordingInfo
    baseline: Baseline
    alpha: float
    kappa_long_run_variance: float
    verdict: str
    mismatch: tuple[Region, ...]
    n_tests: int
    missing_physics: tuple[Finding, ...]
    improved: Improved
    selection_log: list
    seconds: float
    arrays: DiagnosisArrays | None = dataclasses.field(default=None, repr=False, compare=False)
    config: dict | None = None
    attribution: dict | None = None

    @property
    def named(self) -> list[str]:
        """Names in ``missing_physics`` (``unexplained`` included when present)."""
        return [f.name for f in self.missing_physics]

    def to_json(self) -> dict:
        """JSON-ready dict, keys: recording, baseline, alpha, kappa_long_run_variance, verdict,
        mismatch, n_tests, missing_physics, improved, selection_log, seconds. Write it with
        :func:`lugre_jax.io.write_json`; a previous report is accepted by ``--params``."""
        return {"recording": self.recording.to_json(), "baseline": self.baseline.to_json(), "alpha": self.alpha,
                "kappa_long_run_variance": self.kappa_long_run_variance, "verdict": self.verdict,
                "mismatch": [r.to_json() for r in self.mismatch], "n_tests": self.n_tests,
                "missing_physics": [f.to_json() for f in self.missing_physics],
                "improved": self.improved.to_json(), "selection_log": self.selection_log,
                "seconds": self.seconds, **({"config": self.config} if self.config is not None else {}),
                **({"attribution": self.attribution} if self.attribution is not None else {})}
