"""``simulate``: one closed-loop scenario, or a batch of them in one jitted call."""

from __future__ import annotations

import dataclasses

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..xla import require_x64
from ._adaptive import solve_adaptive
from ._fixed import rhs_evals, solve_fixed
from ._jit import array_jit
from ._lanes import _SYSTEM_LANES, batch_size_of, chunked_lanes, split_lanes
from ._solution import RESULT_OK, SampleMean, SampleValues, Solution
from ._lanewise import solve_lanewise
from ._stepping import FIXED_STEPPINGS, AbstractStepping, Adaptive, LaneAdaptive, Lanes, SaveAt, step_for, step_plan
from ._system import N_STATES, System, sample, signals, split

# Below this many right-hand-side evaluations per call, splitting lanes over host devices costs more
# than the second device gains (the split has a fixed cost per call; docs/performance.md).
_SHARD_MIN_EVALS = 4e6


# An adaptive step costs about ten times a fixed step's evaluation per stage (error estimate, step
# control, interpolated samples; docs/performance.md): it counts so many fixed-step evaluations
_ADAPTIVE_EVAL_WEIGHT = 10


def _work(stepping: AbstractStepping, n: int, sample_hz: float) -> int:
    """One lane's solve in fixed-step right-hand-side evaluations: a fixed step's exact count; an
    adaptive stepping's at least, at its largest step (``dtmax``) throughout, six stages a step."""
    if isinstance(stepping, FIXED_STEPPINGS):
        return rhs_evals(stepping, n, sample_hz)
    return _ADAPTIVE_EVAL_WEIGHT * 6 * int(np.ceil((n - 1) / sample_hz / stepping.dtmax))


def _sample_grid(duration_s: float, sample_hz: float) -> int:
    if not (np.isfinite(duration_s) and duration_s > 0):
        raise ValueError(f"duration_s must be a positive number of seconds, got {duration_s!r}")
    if not (np.isfinite(sample_hz) and sample_hz > 0):
        raise ValueError(f"sample_hz must be a positive number, got {sample_hz!r}")
    n = int(round(duration_s * sample_hz))
    if abs(n / sample_hz - duration_s) > 1e-9 * max(1.0, duration_s):
        raise ValueError(
            f"duration_s={duration_s} is not a whole number of samples at sample_hz={sample_hz}; "
            "choose them so that duration_s*sample_hz is an integer"
        )
    return n + 1


def _outputs(system: System, ts, ys, result) -> Solution:
    _, aux = jax.vmap(lambda t, y: signals(t, split(y), system))(ts, ys)
    return Solution(ts, ys, aux["torque_nm"], aux["friction_nm"], aux["theta_ref"], aux["v_ref"], result)


_J_MESSAGE = "Joint.J must be > 0 N*m*s^2/deg (equivalent inertia at the joint)"


def _per_sample(system: System, fn, ts, ys):
    """``fn`` of every sample of one lane's sampled solution, stacked along a leading sample axis."""
    return jax.vmap(lambda i, t, y: fn(sample(system, i, t, split(y))))(jnp.arange(ts.shape[0]), ts, ys)


def _finish(system: System, ts, ys, result, saveat: SaveAt):
    """What one lane returns for ``saveat`` (other than ``mean``) from its sampled solution."""
    if saveat.fn is not None:  # from the samples after the solve: as exact as the Solution's own fields
        return SampleValues(_per_sample(system, saveat.fn, ts, ys), result)
    sol = _outputs(system, ts, ys, result)
    return sol if saveat.reduce is None else saveat.reduce(sol)


def _check_inertia(system: System) -> bool:
    """Check a concrete inertia here; say whether the traced program must check it instead.

    A non-positive inertia is a malformed system, not a bad candidate: it fails loudly rather than
    return a lane of NaN that an optimiser would read as merely "infinitely bad". A concrete value
    is checked in Python, so the compiled program holds no host callback and can be kept in JAX's
    persistent compilation cache (programs with callbacks are never written to it).
    """
    J = system.joint.J
    if isinstance(J, jax.core.Tracer):
        return True
    if not np.all(np.asarray(J) > 0):
        raise ValueError(_J_MESSAGE)
    return False


def _solve_one(system: System, n: int, sample_hz: float, stepping: AbstractStepping, saveat: SaveAt,
               check_inertia: bool = True):
    if check_inertia:
        J = eqx.error_if(system.joint.J, ~(system.joint.J > 0), _J_MESSAGE)
        system = eqx.tree_at(lambda s: s.joint.J, system, J)
    ts = jnp.arange(n) / sample_hz
    if isinstance(stepping, FIXED_STEPPINGS):
        if saveat.mean is not None:
            return SampleMean(*solve_fixed(system, n, sample_hz, stepping, saveat.mean))
        ys, res = solve_fixed(system, n, sample_hz, stepping)
    else:
        ys, res = solve_adaptive(system, ts, stepping)
        if saveat.mean is not None:  # the same mean, from the sampled solution
            vals = _per_sample(system, saveat.mean, ts, ys)
            return SampleMean(jax.tree.map(lambda v: jnp.mean(v, axis=0), vals), res)
    return _finish(system, ts, ys, res, saveat)


def _solve_chunk(system: System, n: int, sample_hz: float, stepping: LaneAdaptive, saveat: SaveAt,
                 check_inertia: bool = True):
    """:func:`_solve_one` for a whole chunk of lanes at once (``LaneAdaptive`` runs its loop at the
    level of the batch)."""
    if check_inertia:
        J = eqx.error_if(system.joint.J, ~(system.joint.J > 0), _J_MESSAGE)
        system = eqx.tree_at(lambda s: s.joint.J, system, J)
    if saveat.mean is not None:
        return SampleMean(*solve_lanewise(system, n, sample_hz, stepping, saveat.mean)[:2])
    if saveat.fn is not None:
        # computed where each sample is interpolated: only fn's values are written per sample
        return SampleValues(*solve_lanewise(system, n, sample_hz, stepping, saveat.fn, mean=False)[:2])
    ys, res, _ = solve_lanewise(system, n, sample_hz, stepping)
    ts = jnp.arange(n) / sample_hz

    return eqx.filter_vmap(lambda s_, y_, r_: _finish(s_, ts, y_, r_, saveat))(system, ys, res)


def _solve_lanewise_one(system, n, sample_hz, stepping, saveat, check_inertia=True):
    one = jax.tree.map(lambda x: x[None] if eqx.is_array(x) else x, system)
    return jax.tree.map(lambda x: x[0], _solve_chunk(one, n, sample_hz, stepping, saveat, check_inertia))


# Arrays of the arguments traced, the rest (grid, stepping, saveat, Python numbers) static.
_jit_one = array_jit(lambda args: (_solve_lanewise_one if isinstance(args[3], LaneAdaptive) else _solve_one)(*args))


def default_stepping(batched: bool, system=None) -> AbstractStepping:
    """:func:`simulate`'s stepping when none is given. A batch of concrete arrays (a call outside
    any JAX transformation, so nothing can differentiate through it): :class:`LaneAdaptive`, each
    lane its own error-controlled step, within 2e-6 deg of a tight solve and 3-5x faster than
    ``Adaptive`` (docs/performance.md). Otherwise (one lane, or a batch traced under ``jit``,
    ``grad``, ``vmap``): :class:`Adaptive`, which reverse mode works through."""
    if batched and system is not None and not any(isinstance(x, jax.core.Tracer) for x in jax.tree.leaves(system)):
        return LaneAdaptive()
    return Adaptive()


def simulate(
    system: System,
    duration_s: float,
    sample_hz: float = 100.0,
    *,
    stepping: AbstractStepping | None = None,
    saveat: SaveAt = SaveAt(),
    batched: bool = False,
    lanes: Lanes = Lanes(),
) -> Solution | SampleValues | SampleMean:
    """Simulate ``system`` from rest (or ``system.y0``) for ``duration_s`` seconds.

    Samples at ``t = 0, 1/sample_hz, ..., duration_s``: positions in deg, velocities in deg/s,
    torques in N*m, time in s.

    ``stepping``: how the ODE is stepped. Default (:func:`default_stepping`): one lane, or a batch
    traced under a JAX transformation, :class:`Adaptive` (Tsit5, rtol 1e-8, atol 1e-10, stepping
    onto every discontinuity of the reference), agreeing with a stiff scipy reference to 1e-6 deg
    in position and 1e-4 N*m in torque, differentiable in reverse mode; a batch of concrete arrays,
    :class:`LaneAdaptive` (each lane its own step, rtol 1e-6, atol 1e-9: within 2e-6 deg of a tight
    solve on every lane of the scipy-loop benchmark; forward mode only). For speed on batches
    choose :class:`FixedStep` explicitly (e.g. ``FixedStep(diffrax.Bosh3(), dt=0.02)``) and check it
    with :func:`check_stepping`; :class:`ExponentialBristle` is a fixed step whose size is not
    limited by stiff bristles (the bristle state advanced exactly); :class:`LaneAdaptive` gives
    each lane its own error-controlled step (forward mode only).

    ``saveat``: what is returned per lane (:class:`SaveAt`): the whole :class:`Solution` (default),
    a function of every sample stacked over the samples (``fn``, a :class:`SampleValues`), a function
    of the whole solution (``reduce``) or a mean over samples accumulated in the time loop (``mean``,
    a :class:`SampleMean`).

    ``batched=True``: every array leaf of ``system`` has a leading batch axis; all lanes are solved
    in one jitted call, spread as ``lanes`` (:class:`Lanes`) says. Under ``vmap`` an adaptive solve
    makes every lane take the slowest lane's steps.

    Every lane carries a result code (``result``): :data:`RESULT_OK`, :data:`RESULT_NONFINITE`
    (the state blew up) or :data:`RESULT_SOLVER_FAILED` (the adaptive solver gave up); failed lanes
    are never reported as success. Differentiable in every leaf of ``system``.
    """
    require_x64()
    stepping = default_stepping(batched, system) if stepping is None else stepping
    if not isinstance(stepping, AbstractStepping):
        raise TypeError(f"stepping must be lugre_jax.Adaptive(...), LaneAdaptive(...), FixedStep(...) or "
                        f"ExponentialBristle(...), got "
                        f"{type(stepping).__name__}")
    if not isinstance(saveat, SaveAt):
        raise TypeError(f"saveat must be a lugre_jax.SaveAt, got {type(saveat).__name__}")
    if not isinstance(lanes, Lanes):
        raise TypeError(f"lanes must be a lugre_jax.Lanes, got {type(lanes).__name__}")
    sample_hz = float(sample_hz)
    n = _sample_grid(float(duration_s), sample_hz)
    if isinstance(stepping, FIXED_STEPPINGS):
        step_plan(step_for(stepping, sample_hz), sample_hz)  # a dt that fits no sample grid is refused here
    check_inertia = _check_inertia(system)
    if not batched:
        return _jit_one((system, n, sample_hz, stepping, saveat, check_inertia))
    split = split_lanes(system, *_SYSTEM_LANES)
    b = split[2]
    shard = lanes.shard
    implicit = isinstance(stepping, Adaptive) and isinstance(stepping.solver, diffrax.AbstractImplicitSolver)
    if shard and implicit and len(jax.local_devices()) > 1:
        raise ValueError(f"Lanes(shard=True): an implicit solver ({type(stepping.solver).__name__}) cannot be "
                         "split over host devices (its linear solves fail inside shard_map); expected "
                         "Lanes(shard=None) or Lanes(shard=False)")
    if shard is None:
        # an implicit solver's linear solves (lineax) fail inside shard_map: its lanes stay on one device
        shard = (len(jax.local_devices()) > 1 and not implicit
                 and b * _work(stepping, n, sample_hz) >= _SHARD_MIN_EVALS)
    key = ("simulate", n, sample_hz, stepping, saveat, check_inertia)
    # a lane's stored samples and working arrays (the solution's columns, a step's stages)
    lane_bytes = 8 * n * (N_STATES + 8) + 8 * 64 * N_STATES
    if isinstance(stepping, LaneAdaptive):
        out = chunked_lanes(key, lambda s: _solve_chunk(s, n, sample_hz, stepping, saveat, check_inertia), split,
                            lanes.chunk_size, shard, batched_fn=True, lane_bytes=lane_bytes)
    else:
        out = chunked_lanes(key, lambda s: _solve_one(s, n, sample_hz, stepping, saveat, check_inertia), split,
                            lanes.chunk_size, shard, lane_bytes=lane_bytes)
    if saveat.fn is None and saveat.reduce is None and saveat.mean is None:  # the whole Solution: one time axis
        out = eqx.tree_at(lambda s: s.ts, out, out.ts[0])
    return out


@dataclasses.dataclass(frozen=True)
class SteppingCheck:
    """How far a stepping is from a tight adaptive reference on a few lanes (max over lanes and
    samples): position [deg], velocity [deg/s], actuator torque [N*m]; ``theta_deg_per_lane`` the
    largest position deviation of each checked lane (NaN where a solve failed)."""

    stepping: str
    reference: str
    lanes: tuple[int, ...]
    theta_deg: float
    omega_deg_s: float
    torque_nm: float
    failed_lanes: tuple[int, ...]
    theta_deg_per_lane: tuple[float, ...] = ()

    def to_json(self) -> dict:
        return dataclasses.asdict(self)


def check_stepping(system: System, duration_s: float, sample_hz: float, stepping: AbstractStepping | None = None,
                   *, batched: bool = False, n_lanes: int = 4,
                   reference: AbstractStepping = Adaptive(diffrax.Kvaerno5(), rtol=1e-10, atol=1e-12)
                   ) -> SteppingCheck:
    """Re-solve up to ``n_lanes`` lanes (evenly spread over the batch) with ``reference`` and report
    the largest deviation of ``stepping``'s solution (default: what :func:`simulate` uses with
    ``batched``) from it: how far a call's fast path may be from a tight solve. The reference is
    implicit (Kvaerno5) so that it holds on stiff lanes too. It costs a tight solve of
    ``n_lanes`` lanes, so call it once per kind of batch, not on every call.

    Lanes where either solve failed are listed in ``failed_lanes`` and left out of the maxima.
    """
    if batched:
        b = batch_size_of(system)
        idx = tuple(int(i) for i in np.unique(np.linspace(0, b - 1, min(n_lanes, b)).round().astype(int)))
        picked = jax.tree.map(lambda x: x[np.asarray(idx)] if eqx.is_array(x) else x, system)
    else:
        idx, picked = (0,), jax.tree.map(lambda x: x[None] if eqx.is_array(x) else x, system)
    stepping = default_stepping(batched, picked) if stepping is None else stepping
    a = simulate(picked, duration_s, sample_hz, stepping=stepping, batched=True)
    r = simulate(picked, duration_s, sample_hz, stepping=reference, batched=True)
    ok = np.asarray((a.result == RESULT_OK) & (r.result == RESULT_OK))

    def worst(x, y):
        d = np.abs(np.asarray(x) - np.asarray(y))[ok]
        return float(d.max()) if d.size else float("nan")

    return SteppingCheck(
        stepping=stepping.describe(), reference=reference.describe(), lanes=idx,
        theta_deg=worst(a.theta, r.theta), omega_deg_s=worst(a.omega, r.omega),
        torque_nm=worst(a.torque_nm, r.torque_nm),
        failed_lanes=tuple(i for i, good in zip(idx, ok) if not good),
        theta_deg_per_lane=tuple(float(np.max(np.abs(np.asarray(x) - np.asarray(y)))) if good else float("nan")
                                 for x, y, good in zip(a.theta, r.theta, ok)),
    )
