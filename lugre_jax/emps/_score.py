"""Scores: the benchmark's closed-loop relative errors and the nonlinear-benchmark protocol.

Closed loop (Simulation_EMPS.m): ``100*norm(meas - sim)/norm(meas)`` of position (filtered ``q_f``),
velocity (``dq_f``) and motor force ``gtau*vir``, from MATLAB sample 50 on.

Benchmark protocol (nonlinearbenchmark.org, EMPS): input ``vir``, output ``qm``; the state is set from
the first 20 samples (here: a quadratic least-squares fit of ``qm[0:20]`` gives position and velocity
at sample 19; LuGre's bristles start in steady sliding), then the model simulates freely; scored on
samples 20 to the end: RMSE [mm], ``R^2 = 1 - SSE/SST`` and the fit index
``100*(1 - ||y - y_hat||/||y - mean(y)||)``.
"""

from __future__ import annotations

import dataclasses

import jax.numpy as jnp
import numpy as np

from .._results import RESULTS
from ._fit import RunArrays, closed_loop_window
from ._idim import N_BORDER
from ._models import AbstractEmpsModel
from ._pulses import IGNORED, PulseEntry
from ._simulate import open_loop

N_INIT = 20  # samples the benchmark protocol lets the model use to set its state


def _result(ok: bool) -> RESULTS:
    return RESULTS.successful if ok else RESULTS.nonfinite


def rel_err_pct(meas, sim) -> float:
    meas, sim = np.asarray(meas), np.asarray(sim)
    return float(100 * np.linalg.norm(meas - sim) / np.linalg.norm(meas))


class _Scored:
    """``ok``: the simulation behind a score was finite (``result`` is ``RESULTS.successful``)."""

    @property
    def ok(self) -> bool:
        return bool(self.result == RESULTS.successful)


@dataclasses.dataclass(frozen=True)
class ClosedLoopScore(_Scored):
    """Closed-loop errors [%]; ``result`` is ``RESULTS.successful``, or ``RESULTS.nonfinite`` for a
    simulation that is not finite (its errors are then +inf). JSON: ``ok`` = successful."""

    position_pct: float
    velocity_pct: float
    force_pct: float
    result: RESULTS
    t: np.ndarray = dataclasses.field(repr=False)
    q: np.ndarray = dataclasses.field(repr=False)
    q_sim: np.ndarray = dataclasses.field(repr=False)
    v: np.ndarray = dataclasses.field(repr=False)
    v_sim: np.ndarray = dataclasses.field(repr=False)
    force: np.ndarray = dataclasses.field(repr=False)
    force_sim: np.ndarray = dataclasses.field(repr=False)
    qm: np.ndarray = dataclasses.field(repr=False)  # raw measured position (q is the filtered one)

    def to_json(self) -> dict:
        return {"position_pct": self.position_pct, "velocity_pct": self.velocity_pct,
                "force_pct": self.force_pct, "ok": self.ok, "n_samples": int(self.t.shape[0])}


@dataclasses.dataclass(frozen=True)
class BenchmarkScore(_Scored):
    """The protocol's RMSE [mm], R² and fit index [%]; ``result`` as :class:`ClosedLoopScore`'s
    (a non-finite simulation scores RMSE +inf, R² and fit index -inf)."""

    rmse_mm: float
    r2: float
    fit_index: float
    result: RESULTS
    t: np.ndarray = dataclasses.field(repr=False)
    y: np.ndarray = dataclasses.field(repr=False)
    y_sim: np.ndarray = dataclasses.field(repr=False)

    def to_json(self) -> dict:
        return {"rmse_mm": self.rmse_mm, "r2": self.r2, "fit_index": self.fit_index, "ok": self.ok,
                "n_samples": int(self.t.shape[0])}


def closed_loop_score(model: AbstractEmpsModel, data: RunArrays, start: int = 0, stop: int | None = None,
                      *, pulses: PulseEntry = IGNORED) -> ClosedLoopScore:
    """Closed-loop simulation of ``start:stop`` from the measured state, scored as the benchmark does;
    ``pulses`` says how the run's ``pulses_N`` enters (default: left out)."""
    stop = data.run.n if stop is None else stop
    q, v, f, ok = closed_loop_window(model, data, start, stop, pulses=pulses)
    s = slice(max(start, N_BORDER) - start, None)
    w = slice(max(start, N_BORDER), stop)
    q, v, f = np.asarray(q)[s], np.asarray(v)[s], np.asarray(f)[s]
    ok = bool(ok)
    inf = float("inf")  # a failed simulation scores +inf, never NaN
    return ClosedLoopScore(
        rel_err_pct(data.q_f[w], q) if ok else inf, rel_err_pct(data.dq_f[w], v) if ok else inf,
        rel_err_pct(data.force[w], f) if ok else inf, _result(ok),
        data.run.t[w], data.q_f[w], q, data.dq_f[w], v, data.force[w], f, data.run.qm[w])


def initial_state_from_samples(qm, T: float):
    """Position and velocity at sample 19 from a quadratic fit of the first 20 samples."""
    k = np.arange(N_INIT) - (N_INIT - 1)
    c = np.polyfit(k * T, np.asarray(qm[:N_INIT]), 2)
    return float(c[2]), float(c[1])


def benchmark_score(model: AbstractEmpsModel, data: RunArrays, start: int = 0, stop: int | None = None,
                    *, pulses: PulseEntry = IGNORED) -> BenchmarkScore:
    """The nonlinear-benchmark protocol on samples ``start:stop`` (module docstring). The protocol
    is ``u = vir`` alone (the default); a ``pulses`` entry at the plant adds them as a known force,
    which is a variant, not the protocol."""
    r = data.run
    stop = r.n if stop is None else stop
    q0, v0 = initial_state_from_samples(r.qm[start:start + N_INIT], data.T)
    x0 = jnp.array([q0, v0, 0.0]).at[2].set(model.z_sliding(v0))
    a = start + N_INIT - 1
    f = pulses.inputs(r.pulses_N, r.gtau)[0][a:stop]
    q, _, ok = open_loop(model, r.vir[a:stop], f, x0, gtau=r.gtau, T=data.T)
    y, yh = r.qm[a + 1:stop], np.asarray(q)[1:]
    ok = bool(ok)
    if not ok:
        return BenchmarkScore(float("inf"), float("-inf"), float("-inf"), RESULTS.nonfinite, r.t[a + 1:stop], y, yh)
    e = y - yh
    return BenchmarkScore(float(1e3 * np.sqrt(np.mean(e * e))),
                          float(1 - np.sum(e * e) / np.sum((y - y.mean()) ** 2)),
                          float(100 * (1 - np.linalg.norm(e) / np.linalg.norm(y - y.mean()))), RESULTS.successful,
                          r.t[a + 1:stop], y, yh)
