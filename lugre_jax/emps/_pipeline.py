"""The EMPS study: IDIM-LS reproduction, output-error fits per model, scores per run, outputs.

Split: every model is fitted on the first ``train_fraction`` (default 70 %) of the estimation run;
scores are reported on the whole estimation run (which contains the training part, as the
published closed-loop errors do), on the held-out last 30 %, and on the validation run when one is
given. The best model of each protocol is chosen on the held-out part by the one-standard-error
rule (:func:`one_se_choice`): the fewest parameters among the models within one standard error of
the lowest held-out error.

The headline is the benchmark's protocol: input ``vir`` alone, output ``qm``, 20 samples to set the
state, RMSE (with R² and fit index) over the rest. Everything else on a validation run is a
labelled variant. A validation run's ``pulses_N`` column enters the closed loop only as
:func:`estimate_pulse_entry` establishes it (location, gain, delay); when it cannot be
established it is left out and the summary says why. Closed-loop errors are reported with the
pulses as estimated and as ignored, for the fitted models and for the published model simulated
the same way.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Callable

import numpy as np

from ..io import EMPS_REFERENCE, EmpsRun
from ._fit import FIT_MAX_STEPS, FitResult, RunArrays, fit_closed_loop, fit_open_loop
from ._idim import IdimResult, idim_ls
from ._models import DEFAULT_MODELS, MODELS, AbstractEmpsModel, AsymmetricCoulombViscous, EmpsCoulombViscous
from ._pulses import PLANT, UNIT_GAIN, PulseEstimate, estimate_pulse_entry, newey_west_cov
from ._score import N_INIT, BenchmarkScore, ClosedLoopScore, benchmark_score, closed_loop_score

#: Published anchors (Janot, Gautier, Brunot 2019; Forgione & Piga 2021).
PUBLISHED = {
    "idim_symmetric": dict(EMPS_REFERENCE["symmetric"]),
    "idim_asymmetric": dict(EMPS_REFERENCE["asymmetric"]),
    "closed_loop_estimation": {"position_pct": 0.0138, "velocity_pct": 0.229, "force_pct": 5.85},
    "closed_loop_validation": {"force_pct": 8.94},
    "benchmark_neural_ss_validation": {"rmse_mm_about": 8.0, "r2_above": 0.99},
}

PROTOCOL = (f"nonlinear-benchmark protocol: u = vir only, y = qm, state set from the first {N_INIT} "
            f"samples, free simulation, RMSE [mm], R^2 and fit index over the remaining samples")

# closed-loop keys on a validation run with pulses
VAL_ESTIMATED, VAL_IGNORED, VAL_UNIT = ("validation_pulses_estimated", "validation_pulses_ignored",
                                        "variant_validation_pulses_unit_gain")
# benchmark-protocol variant on a validation run with pulses established at the plant
VAL_BENCH_VARIANT = "variant_validation_pulses_estimated_as_input"


@dataclasses.dataclass(frozen=True)
class ModelReport:
    label: str
    closed_loop_fit: FitResult
    benchmark_fit: FitResult
    closed_loop: dict  # run key -> ClosedLoopScore
    benchmark: dict  # run key -> BenchmarkScore

    @property
    def n_params(self) -> int:
        return len(type(self.closed_loop_fit.model).names())

    def to_json(self) -> dict:
        m = self.closed_loop_fit.model
        units = type(m).units()
        jn = type(m).json_names
        return {"params": m.to_dict(), "units": {jn.get(k, k): u for k, u in units.items()},
                "n_physical_parameters": self.n_params,
                "closed_loop_fit": self.closed_loop_fit.to_json(),
                "benchmark_fit": self.benchmark_fit.to_json(),
                "runs": {run: {"closed_loop": self.closed_loop[run].to_json() if run in self.closed_loop else None,
                               "benchmark": self.benchmark[run].to_json() if run in self.benchmark else None}
                         for run in dict.fromkeys([*self.closed_loop, *self.benchmark])}}


def _bjson(b: BenchmarkScore | None) -> dict | None:
    return None if b is None else {"rmse_mm": b.rmse_mm, "r2": b.r2, "fit_index": b.fit_index}


def _cjson(c: ClosedLoopScore | None) -> dict | None:
    return None if c is None else {"force_pct": c.force_pct, "position_pct": c.position_pct,
                                   "velocity_pct": c.velocity_pct}


@dataclasses.dataclass(frozen=True)
class EmpsReport:
    source: str
    validation_source: str | None
    train_samples: int
    n_samples: int
    idim: dict  # 'symmetric'/'asymmetric' -> IdimResult
    reference: dict  # 'symmetric'/'asymmetric' -> {'model', 'closed_loop': {...}, 'benchmark': {...}}
    models: dict  # label -> ModelReport
    best_closed_loop: str
    best_benchmark: str
    total_time_s: float
    validation_has_pulses: bool = False
    pulses: PulseEstimate | None = None

    @property
    def fits(self) -> list[tuple[str, FitResult]]:
        return [(k, f) for k, m in self.models.items() for f in (m.closed_loop_fit, m.benchmark_fit)]

    @property
    def not_converged(self) -> list[str]:
        """One line per fit that did not converge (empty when all did)."""
        return [f"{k}: {f.protocol} fit did not converge ({f.status}: {f.n_steps} of {f.max_steps} steps)"
                for k, f in self.fits if not f.converged]

    @property
    def protocol_run(self) -> str:
        return "validation" if self.validation_source else "held_out"

    def summary(self) -> dict:
        """The headline figures: the protocol's score of the best model and of the published model,
        closed-loop errors (with the pulses as estimated and as ignored on a validation run with
        pulses), the pulses' estimate and every fit's convergence."""
        best_b, best_c = self.models[self.best_benchmark], self.models[self.best_closed_loop]
        pub = self.reference["symmetric"]
        runs = ["held_out"] + (["validation"] if self.validation_source else [])
        protocol = {"definition": PROTOCOL, "best_model": self.best_benchmark,
                    "best_model_n_physical_parameters": best_b.n_params,
                    "chosen_on": "held_out, one-standard-error rule"}
        protocol["held_out_rmse_mm_and_se"] = {
            k: [1e3 * x for x in rms_and_se(m.benchmark["held_out"].y - m.benchmark["held_out"].y_sim)]
            for k, m in self.models.items()}
        for r in runs:
            protocol[r] = {"best_model": _bjson(best_b.benchmark.get(r)),
                           "published_idim_model": _bjson(pub["benchmark"].get(r))}
        closed = {"best_model": self.best_closed_loop,
                  "best_model_n_physical_parameters": best_c.n_params,
                  "chosen_on": "held_out, one-standard-error rule",
                  "held_out": {"best_model": _cjson(best_c.closed_loop["held_out"]),
                               "published_idim_model": _cjson(pub["closed_loop"]["held_out"])},
                  "published_anchor_estimation_force_pct": PUBLISHED["closed_loop_estimation"]["force_pct"]}
        if self.validation_source:
            keys = [VAL_ESTIMATED, VAL_IGNORED] if self.validation_has_pulses else ["validation"]
            closed["validation"] = {k: {"best_model": _cjson(best_c.closed_loop.get(k)),
                                        "published_idim_model": _cjson(pub["closed_loop"].get(k))}
                                    for k in keys}
            closed["published_anchor_validation_force_pct"] = PUBLISHED["closed_loop_validation"]["force_pct"]
        variants = {}
        if self.validation_has_pulses:
            variants[VAL_UNIT] = {"what": "closed loop with pulses_N at unit gain, no delay, at the plant "
                                          "(the column at face value; not the estimate)",
                                  "best_model": _cjson(best_c.closed_loop.get(VAL_UNIT)),
                                  "published_idim_model": _cjson(pub["closed_loop"].get(VAL_UNIT))}
            if VAL_BENCH_VARIANT in best_b.benchmark:
                variants[VAL_BENCH_VARIANT] = {
                    "what": "protocol simulation with the estimated plant force added to vir (not the protocol)",
                    "best_model": _bjson(best_b.benchmark.get(VAL_BENCH_VARIANT)),
                    "published_idim_model": _bjson(pub["benchmark"].get(VAL_BENCH_VARIANT))}
        nc = self.not_converged
        return {
            "protocol": protocol, "closed_loop": closed,
            "pulses": self.pulses.to_json() if self.pulses is not None else None,
            "variants": variants,
            "convergence": {"all_converged": not nc, "n_fits": len(self.fits), "not_converged": nc,
                            "fits": [{"model": k, "protocol": f.protocol, "status": f.status,
                                      "steps": f.n_steps, "max_steps": f.max_steps, "result": f.to_json()["result"],
                                      "fit_time_s": f.time_s} for k, f in self.fits]},
        }

    def to_json(self) -> dict:
        def idim_json(key, r: IdimResult):
            pub = PUBLISHED[f"idim_{key}"]
            j = r.to_json()
            j["published"] = pub
            j["rel_diff_pct"] = {k: 100 * (r.params[k] - pub[k]) / abs(pub[k]) for k in r.params if k in pub}
            j["rel_diff_pct"]["rel_err_pct"] = 100 * (r.rel_err_pct - pub["rel_err_pct"]) / pub["rel_err_pct"]
            return j

        ref = {k: {"params": v["model"].to_dict(),
                   "closed_loop": {r: s.to_json() for r, s in v["closed_loop"].items()},
                   "benchmark": {r: s.to_json() for r, s in v["benchmark"].items()}}
               for k, v in self.reference.items()}
        return {
            "summary": self.summary(),
            "data": self.source, "validation": self.validation_source,
            "validation_has_pulses": self.validation_has_pulses,
            "split": {"train_samples": self.train_samples, "estimation_samples": self.n_samples,
                      "held_out": f"samples {self.train_samples}..{self.n_samples - 1}"},
            "units": {"position": "m", "velocity": "m/s", "force": "N", "rmse": "mm", "errors": "%"},
            "idim": {k: idim_json(k, v) for k, v in self.idim.items()},
            "published_model_simulated": ref,
            "models": {k: v.to_json() for k, v in self.models.items()},
            "best": {"closed_loop": self.best_closed_loop, "benchmark": self.best_benchmark,
                     "chosen_on": "held_out, one-standard-error rule"},
            "published": PUBLISHED,
            "total_time_s": self.total_time_s,
        }


def _scores(model, est: RunArrays, cut: int, val: RunArrays | None, pulses: PulseEstimate | None) -> dict:
    cl = {"estimation": closed_loop_score(model, est), "held_out": closed_loop_score(model, est, cut)}
    if val is not None:
        if val.run.has_pulses:
            ignored = closed_loop_score(model, val)
            cl[VAL_IGNORED] = ignored
            cl[VAL_ESTIMATED] = closed_loop_score(model, val, pulses=pulses.entry) if pulses.established else ignored
            cl[VAL_UNIT] = closed_loop_score(model, val, pulses=UNIT_GAIN)
        else:
            cl["validation"] = closed_loop_score(model, val)
    return cl


def _bench(model, est: RunArrays, cut: int, val: RunArrays | None, pulses: PulseEstimate | None) -> dict:
    b = {"estimation": benchmark_score(model, est), "held_out": benchmark_score(model, est, cut)}
    if val is not None:
        b["validation"] = benchmark_score(model, val)  # the protocol: vir alone, whatever pulses_N holds
        if pulses is not None and pulses.established and pulses.entry.location == PLANT:
            b[VAL_BENCH_VARIANT] = benchmark_score(model, val, pulses=pulses.entry)
    return b


def rms_and_se(err) -> tuple[float, float]:
    """Root mean square of ``err`` and its standard error: the mean of ``err**2`` with a
    Newey-West error (Andrews' bandwidth; simulation errors are strongly autocorrelated), carried
    to the root by the delta method."""
    e2 = np.asarray(err, np.float64) ** 2
    mse = float(e2.mean())
    var = float(newey_west_cov(np.ones((e2.shape[0], 1)), e2 - mse)[0, 0])
    rms = float(np.sqrt(mse))
    return rms, (float(np.sqrt(max(var, 0.0)) / (2 * rms)) if rms > 0 else 0.0)


def one_se_choice(candidates: dict) -> str:
    """The one-standard-error rule (Hastie, Tibshirani & Friedman, Elements of Statistical Learning,
    7.10): among models whose held-out RMS error is within one standard error of the lowest, the
    one with the fewest parameters (then the lowest error). ``candidates``: name -> (held-out error
    series, parameter count). A failed simulation (non-finite errors) is never chosen if another
    is finite."""
    stats = {}
    for k, (e, n) in candidates.items():
        e = np.asarray(e, np.float64)
        stats[k] = (rms_and_se(e) if np.all(np.isfinite(e)) else (np.inf, 0.0)) + (n,)
    best = min(stats, key=lambda k: stats[k][0])
    limit = stats[best][0] + stats[best][1]
    near = [k for k in stats if stats[k][0] <= limit]
    return min(near, key=lambda k: (stats[k][2], stats[k][0]))


def _clock(s: float) -> str:
    s = int(round(s))
    return f"{s // 60}:{s % 60:02d}"


def identify_emps(run: EmpsRun, validation: EmpsRun | None = None, *,
                  models: tuple[type[AbstractEmpsModel], ...] = DEFAULT_MODELS, train_fraction: float = 0.7,
                  n_segments: int = 4, segment_len: int | None = None, max_steps: int = FIT_MAX_STEPS,
                  progress: bool | Callable[[str], None] = False) -> EmpsReport:
    """Run the study (module docstring) for ``models`` (default :data:`DEFAULT_MODELS`; the full
    study: :data:`MODELS`). ``progress``: a callable receiving one line per step (``True``: print
    to stderr), each with the step count, the total and an ETA.

    Each model is fitted in closed loop from its reference values, then under the protocol from
    the closed-loop estimate with the mass kept at its closed-loop value. The protocol fit cuts
    the training part into ``n_segments`` shooting windows of ``segment_len`` samples (default:
    the windows tile the training part); few long windows suit a protocol that scores a long free
    simulation (docs/emps.md).
    """
    if not 0.2 <= train_fraction <= 0.95:
        raise ValueError(f"train_fraction must be in [0.2, 0.95], got {train_fraction}")
    if progress is True:
        import sys

        def say(line: str) -> None:
            print(line, file=sys.stderr, flush=True)
    else:
        say = progress if callable(progress) else None
    t_start = time.perf_counter()
    est = RunArrays(run)
    val = RunArrays(validation) if validation is not None else None
    cut = int(round(train_fraction * run.n))
    if segment_len is None:
        segment_len = cut // n_segments
    pulses = estimate_pulse_entry(validation) if validation is not None and validation.has_pulses else None
    if say and pulses is not None:
        say(f"validation pulses_N: {pulses.reason}")
    idim = {"symmetric": idim_ls(run), "asymmetric": idim_ls(run, asymmetric=True)}
    n_total = 2 * len(models)
    done = 0
    reference = {}
    for key, cls in (("symmetric", EmpsCoulombViscous), ("asymmetric", AsymmetricCoulombViscous)):
        m = cls.from_dict(idim[key].params)
        reference[key] = {"model": m, "closed_loop": _scores(m, est, cut, val, pulses),
                          "benchmark": _bench(m, est, cut, val, pulses)}
    if say:
        say(f"IDIM-LS {idim['symmetric'].rel_err_pct:.3f} % (published 4.08 %); published models scored; "
            f"{n_total} fits to go ({_clock(time.perf_counter() - t_start)} elapsed)")
    reports = {}
    t_fits = time.perf_counter()  # the ETA counts the fits and the scoring between them
    for cls in models:
        fits = []
        for kind in ("closed loop", "benchmark protocol"):
            if kind == "closed loop":
                fr = fit_closed_loop(cls.reference(), est, 0, cut, max_steps=max_steps)
            else:
                # from the closed-loop estimate, the mass kept: the closed loop measures it through
                # the accelerations; a free simulation sees mostly drift, and a protocol fit left
                # free trades mass for drift (docs/emps.md). The friction is refined for it.
                if fits[0].status != "failed":
                    fr = fit_open_loop(fits[0].model, est, 0, cut, n_segments=n_segments,
                                       segment_len=segment_len, max_steps=max_steps, fixed=("M",))
                else:
                    fr = fit_open_loop(cls.reference(), est, 0, cut, n_segments=n_segments,
                                       segment_len=segment_len, max_steps=max_steps)
            fits.append(fr)
            done += 1
            if say:
                eta = (time.perf_counter() - t_fits) / done * (n_total - done)
                say(f"[{done}/{n_total}] {cls.label}: {kind} fit {fr.time_s:.0f} s, {fr.n_steps} steps, "
                    f"{fr.status}; elapsed {_clock(time.perf_counter() - t_start)}, ETA {_clock(eta)}")
        reports[cls.label] = ModelReport(cls.label, fits[0], fits[1], _scores(fits[0].model, est, cut, val, pulses),
                                         _bench(fits[1].model, est, cut, val, pulses))
    best_cl = one_se_choice({k: (m.closed_loop["held_out"].force - m.closed_loop["held_out"].force_sim,
                                 m.n_params) for k, m in reports.items()})
    best_b = one_se_choice({k: (m.benchmark["held_out"].y - m.benchmark["held_out"].y_sim, m.n_params)
                            for k, m in reports.items()})
    return EmpsReport(run.source, validation.source if validation is not None else None, cut, run.n,
                      idim, reference, reports, best_cl, best_b, time.perf_counter() - t_start,
                      bool(validation is not None and validation.has_pulses), pulses)


def write_emps_outputs(report: EmpsReport, out: str | Path) -> list[Path]:
    """RESULT.json, validation_benchmark.csv, validation_closed_loop.csv and the figures, atomically.

    ``validation_benchmark.csv`` is the protocol (``vir`` alone) for the best protocol model on the
    validation run (the held-out part without one); ``validation_closed_loop.csv`` the best
    closed-loop model driven by ``qg`` with the pulses as estimated (``force_sim_n``) and as
    ignored (``force_sim_pulses_ignored_n``; the same column without pulses)."""
    from ..io import write_csv, write_json
    from ._plots import plot_report

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    run_name = report.protocol_run
    b: BenchmarkScore = report.models[report.best_benchmark].benchmark[run_name]
    cl = report.models[report.best_closed_loop].closed_loop
    c_key = VAL_ESTIMATED if report.validation_has_pulses else run_name
    c: ClosedLoopScore = cl[c_key]
    c_ign: ClosedLoopScore = cl[VAL_IGNORED] if report.validation_has_pulses else c
    j = report.to_json()
    j["csv"] = {"validation_benchmark.csv": {"model": report.best_benchmark, "run": run_name,
                                             "what": PROTOCOL},
                "validation_closed_loop.csv": {"model": report.best_closed_loop, "run": run_name,
                                               "force_sim_n": c_key, "force_sim_pulses_ignored_n":
                                               VAL_IGNORED if report.validation_has_pulses else run_name}}
    paths = [out / "RESULT.json", out / "validation_benchmark.csv", out / "validation_closed_loop.csv"]
    write_json(paths[0], j)
    write_csv(paths[1], {"time_s": b.t, "qm_m": b.y, "qm_sim_m": b.y_sim}, fmt="%.9g")
    write_csv(paths[2], {"time_s": c.t, "qm_m": c.qm, "qm_sim_m": c.q_sim, "force_n": c.force,
                         "force_sim_n": c.force_sim, "force_sim_pulses_ignored_n": c_ign.force_sim}, fmt="%.9g")
    paths += plot_report(report, out, run_name, c_key)
    return paths
