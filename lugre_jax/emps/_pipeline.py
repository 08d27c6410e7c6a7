"""The whole EMPS study: IDIM-LS reproduction, output-error fits per model, scores per run, outputs.

Split: every model is fitted on the first ``train_fraction`` (default 70 %) of the estimation run;
scores are reported on the whole estimation run (which contains the training part, as the
published closed-loop errors do), on the held-out last 30 %, and on the validation run when one is
given (``pulses_N`` is a known input of the closed loop; the benchmark protocol is scored with and
without it). The best model of each protocol is chosen on the held-out part.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path


from ..io import EmpsRun
from ._fit import FitResult, RunArrays, fit_closed_loop, fit_open_loop
from ._idim import IdimResult, idim_ls
from ._models import MODELS, AbstractEmpsModel, AsymmetricCoulombViscous, CoulombViscous
from ._score import BenchmarkScore, ClosedLoopScore, benchmark_score, closed_loop_score

#: Published anchors (Janot, Gautier, Brunot 2019; Forgione & Piga 2021).
PUBLISHED = {
    "idim_symmetric": {"M": 95.1089, "Fv": 203.5034, "Fc": 20.3935, "offset": -3.1648, "rel_err_pct": 4.08},
    "idim_asymmetric": {"Fv+": 166.71, "Fc+": 20.14, "Fv-": 240.42, "Fc-": 20.63, "rel_err_pct": 3.11},
    "closed_loop_estimation": {"position_pct": 0.0138, "velocity_pct": 0.229, "force_pct": 5.85},
    "closed_loop_validation": {"force_pct": 8.94},
    "benchmark_neural_ss_validation": {"rmse_mm_about": 8.0, "r2_above": 0.99},
}


@dataclasses.dataclass(frozen=True)
class ModelReport:
    label: str
    closed_loop_fit: FitResult
    benchmark_fit: FitResult
    closed_loop: dict  # run name -> ClosedLoopScore
    benchmark: dict  # run name -> BenchmarkScore (validation also as 'validation_without_pulses')

    def to_json(self) -> dict:
        m = self.closed_loop_fit.model
        units = type(m).units()
        jn = type(m).json_names
        return {"params": m.to_dict(), "units": {jn.get(k, k): u for k, u in units.items()},
                "closed_loop_fit": self.closed_loop_fit.to_json(),
                "benchmark_fit": self.benchmark_fit.to_json(),
                "runs": {run: {"closed_loop": self.closed_loop[run].to_json() if run in self.closed_loop else None,
                               "benchmark": self.benchmark[run].to_json() if run in self.benchmark else None}
                         for run in dict.fromkeys([*self.closed_loop, *self.benchmark])}}


@dataclasses.dataclass(frozen=True)
class EmpsReport:
    source: str
    validation_source: str | None
    train_samples: int
    n_samples: int
    idim: dict  # 'symmetric'/'asymmetric' -> IdimResult
    reference: dict  # 'symmetric'/'asymmetric' -> ModelReport-like dict of scores of the published models
    models: dict  # label -> ModelReport
    best_closed_loop: str
    best_benchmark: str
    total_time_s: float
    validation_has_pulses: bool = False

    def to_json(self) -> dict:
        def idim_json(key, r: IdimResult):
            pub = PUBLISHED[f"idim_{key}"]
            j = r.to_json()
            j["published"] = pub
            j["rel_diff_pct"] = {k: 100 * (r.params[k] - pub[k]) / abs(pub[k]) for k in r.params if k in pub}
            j["rel_diff_pct"]["rel_err_pct"] = 100 * (r.rel_err_pct - pub["rel_err_pct"]) / pub["rel_err_pct"]
            return j

        return {
            "data": self.source, "validation": self.validation_source,
            "validation_has_pulses": self.validation_has_pulses,
            "split": {"train_samples": self.train_samples, "estimation_samples": self.n_samples,
                      "held_out": f"samples {self.train_samples}..{self.n_samples - 1}"},
            "units": {"position": "m", "velocity": "m/s", "force": "N", "rmse": "mm", "errors": "%"},
            "idim": {k: idim_json(k, v) for k, v in self.idim.items()},
            "published_model_simulated": self.reference,
            "models": {k: v.to_json() for k, v in self.models.items()},
            "best": {"closed_loop": self.best_closed_loop, "benchmark": self.best_benchmark,
                     "chosen_on": "held_out"},
            "published": PUBLISHED,
            "total_time_s": self.total_time_s,
        }


def _scores(model, est: RunArrays, cut: int, val: RunArrays | None):
    cl = {"estimation": closed_loop_score(model, est), "held_out": closed_loop_score(model, est, cut)}
    if val is not None:
        cl["validation"] = closed_loop_score(model, val)
    return cl


def _bench(model, est: RunArrays, cut: int, val: RunArrays | None):
    b = {"estimation": benchmark_score(model, est), "held_out": benchmark_score(model, est, cut)}
    if val is not None:
        b["validation"] = benchmark_score(model, val)
        if val.run.has_pulses:
            b["validation_without_pulses"] = benchmark_score(model, val, use_pulses=False)
    return b


def identify_emps(run: EmpsRun, validation: EmpsRun | None = None, *,
                  models: tuple[type[AbstractEmpsModel], ...] = MODELS, train_fraction: float = 0.7,
                  n_segments: int = 4, segment_len: int | None = None, max_steps: int = 60,
                  progress: bool = False) -> EmpsReport:
    """Run the whole study (module docstring). ``progress`` shows a tqdm bar per fit.

    The benchmark-protocol fit cuts the training part into ``n_segments`` shooting windows of
    ``segment_len`` samples (default: the windows tile the training part). Few long windows suit a
    protocol that scores a long free simulation (benchmarks/emps_fit.py, docs/emps.md: with the
    published structure, 4 windows give 3.0 mm held out, 64 windows of 271 samples 7.5 mm).
    """
    if not 0.2 <= train_fraction <= 0.95:
        raise ValueError(f"train_fraction must be in [0.2, 0.95], got {train_fraction}")
    t_start = time.perf_counter()
    est = RunArrays(run)
    val = RunArrays(validation) if validation is not None else None
    cut = int(round(train_fraction * run.n))
    if segment_len is None:
        segment_len = cut // n_segments
    idim = {"symmetric": idim_ls(run), "asymmetric": idim_ls(run, asymmetric=True)}
    reference = {}
    for key, cls in (("symmetric", CoulombViscous), ("asymmetric", AsymmetricCoulombViscous)):
        m = cls.from_dict(idim[key].params)
        reference[key] = {"params": m.to_dict(),
                          "closed_loop": {k: v.to_json() for k, v in _scores(m, est, cut, val).items()},
                          "benchmark": {k: v.to_json() for k, v in _bench(m, est, cut, val).items()}}
    reports = {}
    for cls in models:
        start_model = cls.reference()
        fits = []
        for kind in ("closed loop", "benchmark"):
            bar = None
            cb = None
            if progress:
                from tqdm.auto import tqdm

                bar = tqdm(desc=f"{cls.label}: {kind} fit", unit=" evals", leave=False)
                cb = lambda k, bar=bar: bar.update(int(k))  # noqa: E731
            if kind == "closed loop":
                fr = fit_closed_loop(start_model, est, 0, cut, max_steps=max_steps, progress=cb)
            else:
                fr = fit_open_loop(start_model, est, 0, cut, n_segments=n_segments,
                                   segment_len=segment_len, max_steps=max_steps, progress=cb)
            if bar is not None:
                bar.close()
                print(f"{cls.label}: {kind} fit {fr.time_s:.1f} s, {fr.n_steps} LM steps, "
                      f"{'converged' if fr.success else 'step limit/failed'}", flush=True)
            fits.append(fr)
        reports[cls.label] = ModelReport(cls.label, fits[0], fits[1], _scores(fits[0].model, est, cut, val),
                                         _bench(fits[1].model, est, cut, val))
    best_cl = min(reports, key=lambda k: reports[k].closed_loop["held_out"].force_pct)
    best_b = min(reports, key=lambda k: reports[k].benchmark["held_out"].rmse_mm)
    return EmpsReport(run.source, validation.source if validation is not None else None, cut, run.n,
                      idim, reference, reports, best_cl, best_b, time.perf_counter() - t_start,
                      bool(validation is not None and validation.has_pulses))


def write_emps_outputs(report: EmpsReport, out: str | Path) -> list[Path]:
    """RESULT.json, validation_benchmark.csv, validation_closed_loop.csv and the figures, atomically."""
    from ..io import write_csv, write_json
    from ._plots import plot_report

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    run_name = "validation" if report.validation_source else "held_out"
    b: BenchmarkScore = report.models[report.best_benchmark].benchmark[run_name]
    c: ClosedLoopScore = report.models[report.best_closed_loop].closed_loop[run_name]
    j = report.to_json()
    j["csv"] = {"validation_benchmark.csv": {"model": report.best_benchmark, "run": run_name},
                "validation_closed_loop.csv": {"model": report.best_closed_loop, "run": run_name}}
    paths = [out / "RESULT.json", out / "validation_benchmark.csv", out / "validation_closed_loop.csv"]
    write_json(paths[0], j)
    write_csv(paths[1], {"time_s": b.t, "qm_m": b.y, "qm_sim_m": b.y_sim}, fmt="%.9g")
    write_csv(paths[2], {"time_s": c.t, "qm_m": c.qm, "qm_sim_m": c.q_sim,
                         "force_n": c.force, "force_sim_n": c.force_sim}, fmt="%.9g")
    paths += plot_report(report, out, run_name)
    return paths

