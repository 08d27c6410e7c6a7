"""Batched simulation of the joint of Li et al. (Electronics 2020, 9, 284): LuGre friction (eq. 9),
joint (eq. 1-2), DC motor (eq. 3-8) and controller (eq. 19-24) as one ODE, solved with diffrax.

State vector (8, float64), in this order (:data:`STATE_NAMES`):
``theta`` [deg], ``omega`` [deg/s], ``z`` bristle deflection [deg], ``current`` [A] (motor with
inductance only), ``xi`` velocity-error integral [deg], ``xd`` derivative filter [deg/s], ``zh``
observer's bristle state [deg], ``xp`` position-error integral [deg*s].

Two integration paths, chosen by measurement (see README, "Simulator"):

* ``method="fixed"`` (default for batches): a diffrax Runge-Kutta solver stepped at a constant
  ``dt`` inside ``lax.scan``. Under ``vmap`` an adaptive solver makes every lane take the slowest
  lane's steps and pays step-size bookkeeping per step; a constant step that resolves the fastest
  time constant of the paper's joint (about 10 ms during pre-sliding) costs the same for every lane
  and is the floor for a batched solve. Its error is measured against a tight stiff reference in
  the tests and the benchmark.
* ``method="adaptive"``: ``diffrax.diffeqsolve`` with an implicit ESDIRK (Kvaerno5) and a PID
  step-size controller, for stiff scenarios (motor inductance, very stiff bristles) and as the
  reference. ``throw=False``: each lane reports its own result code.

Every lane carries a result code: :data:`RESULT_OK`, :data:`RESULT_NONFINITE` (the state blew up),
:data:`RESULT_SOLVER_FAILED` (adaptive solver gave up, e.g. ``max_steps`` reached). A failed lane is
never reported as a silent NaN; :func:`trajectory_loss` maps it to ``+inf``.
"""

from __future__ import annotations

import math
from typing import Literal

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.ad_checkpoint import checkpoint_name
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from ._fusion import derivative_stored_once, runtime_one
from ._fusion import stored_once as _stored_once
from .xla import require_x64
from ._types import Array, Float, Int, PyTree
from .control import AbstractController, AbstractReference
from .control._controllers import CtrlIn
from .friction import AbstractFrictionModel
from .plant import AbstractActuator, IdealTorque, Joint

STATE_NAMES = ("theta", "omega", "z", "current", "xi", "xd", "zh", "xp")
N_STATES = len(STATE_NAMES)
RESULT_OK = 0
RESULT_NONFINITE = 1
RESULT_SOLVER_FAILED = 2


class System(eqx.Module):
    """Joint + friction + actuator + controller + reference: everything one simulation needs.

    Any leaf may carry a leading batch axis (see :func:`simulate`, ``batched=True``); ``y0`` is the
    initial state in the order of :data:`STATE_NAMES` (at rest by default).
    """

    friction: AbstractFrictionModel
    joint: Joint
    controller: AbstractController
    reference: AbstractReference
    actuator: AbstractActuator = eqx.field(default_factory=IdealTorque)
    y0: Float[Array, "*b 8"] = eqx.field(
        converter=jnp.asarray, default_factory=lambda: np.zeros(N_STATES)
    )


def _signals(t, y: tuple, system: System):
    """Rates and output signals for a state given as a tuple of the 8 components."""
    theta, omega, z, current, xi, xd, zh, xp = y
    th_r, v_r, a_r = system.reference(t)
    ctrl = system.controller(CtrlIn(theta, omega, xi, xd, zh, xp, th_r, v_r, a_r))
    tau, di = system.actuator.drive(ctrl.command, system.controller.voltage, current, omega)
    f, dz = system.friction.torque_and_derivative(z, omega)
    # The cotangents of dz/dt and of the net torque feed every kernel of a reverse pass that
    # handles a stage: computed once each (see _fusion; the forward solve compiles as without).
    one = runtime_one(theta)
    dz = derivative_stored_once(dz, one)
    net = derivative_stored_once(tau - f - system.joint.gravity(theta), one)
    # * (1/J): a loop-invariant reciprocal (hoisted) instead of a float64 division per evaluation.
    domega = net * (1.0 / system.joint.J)
    dy = (omega, domega, dz, di, ctrl.dxi, ctrl.dxd, ctrl.dzh, ctrl.dxp)
    return dy, dict(torque_nm=tau, friction_nm=f, command=ctrl.command, theta_ref=th_r, v_ref=v_r)


def _rates(t, y: tuple, system: System) -> tuple:
    # The solvers carry the state as a tuple of 8 arrays, not one (..., 8) array: stacking the
    # rates into one array makes XLA emit a concatenate-rooted fusion that recomputes the friction
    # law once per output column and cannot vectorise (measured ~3x slower batched RHS).
    return _signals(t, y, system)[0]


def _split(y):
    return tuple(y[..., k] for k in range(N_STATES))


def vector_field(t, y: Float[Array, "8"], system: System) -> Float[Array, "8"]:
    """dy/dt of the full closed loop (units per :data:`STATE_NAMES`, per second)."""
    return jnp.stack(_rates(t, _split(y), system), axis=-1)


class Solution(eqx.Module):
    """Sampled trajectories. Arrays have shape ``(*batch, n_samples)`` (``ys``: ``(..., n, 8)``).

    ``torque_nm`` is the actuator torque at the joint [N*m], ``friction_nm`` the plant's friction
    torque [N*m], ``result`` the per-lane result code (0 = ok).
    """

    ts: Float[Array, " n"]
    ys: Float[Array, "*b n 8"]
    torque_nm: Float[Array, "*b n"]
    friction_nm: Float[Array, "*b n"]
    theta_ref: Float[Array, "*b n"]
    v_ref: Float[Array, "*b n"]
    result: Int[Array, "*b"]

    @property
    def theta(self):
        """Joint angle [deg]."""
        return self.ys[..., 0]

    @property
    def omega(self):
        """Joint velocity [deg/s]."""
        return self.ys[..., 1]

    @property
    def z(self):
        """Bristle deflection [deg]."""
        return self.ys[..., 2]

    @property
    def ok(self):
        return self.result == RESULT_OK


class Sample(eqx.Module):
    """One sample of one simulation, as the ``sample_mean`` function of :func:`simulate` sees it.

    ``index`` is the sample number (0 at t = 0: use it to look up measured data), ``t`` the time
    [s], ``y`` the 8 state components in :data:`STATE_NAMES` order (deg, deg/s, deg, A, deg*s...),
    ``torque_nm`` the actuator torque and ``friction_nm`` the friction torque [N*m], ``theta_ref``
    [deg] and ``v_ref`` [deg/s] the reference. All are scalars; what the function does not read
    is not computed.
    """

    index: Int[Array, ""]
    t: Float[Array, ""]
    y: tuple
    torque_nm: Float[Array, ""]
    friction_nm: Float[Array, ""]
    theta_ref: Float[Array, ""]
    v_ref: Float[Array, ""]

    @property
    def theta(self):
        """Joint angle [deg]."""
        return self.y[0]

    @property
    def omega(self):
        """Joint velocity [deg/s]."""
        return self.y[1]

    @property
    def z(self):
        """Bristle deflection [deg]."""
        return self.y[2]


class SampleMean(eqx.Module):
    """What :func:`simulate` returns with ``sample_mean=fn``: the mean of ``fn`` over every sample.

    ``value`` has ``fn``'s pytree structure, each leaf with a leading batch axis when batched;
    ``result`` is the per-lane result code (0 = ok). A failed lane's value is meaningless (often
    NaN): use :meth:`or_inf` for a loss, so that a failed run is infinitely bad.
    """

    value: PyTree
    result: Int[Array, "*b"]

    @property
    def ok(self):
        return self.result == RESULT_OK

    def or_inf(self):
        """``value`` where the lane succeeded, ``+inf`` where it failed (leaf by leaf)."""
        ok = self.ok
        return jax.tree.map(lambda v: jnp.where(ok.reshape(ok.shape + (1,) * (v.ndim - ok.ndim)), v, jnp.inf),
                            self.value)


def _sample(system, index, t, y) -> Sample:
    _, aux = _signals(t, y, system)
    return Sample(index, t, tuple(y), aux["torque_nm"], aux["friction_nm"], aux["theta_ref"], aux["v_ref"])


_FIXED_SOLVERS = {"tsit5": diffrax.Tsit5, "bosh3": diffrax.Bosh3, "heun": diffrax.Heun,
                  "ralston": diffrax.Ralston, "midpoint": diffrax.Midpoint, "dopri5": diffrax.Dopri5}


def _sample_grid(duration_s: float, sample_hz: float):
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


_STAGE_INPUT = "lugre_jax_stage_input"
# Reverse mode recomputes each sample block from its stored state, except the stage inputs, which
# its forward sweep stores: recomputing them cost every backward step a division per component
# (to keep them stored once, see _fusion) and their combinations, measured on the benchmark's
# one-segment joint (200 lanes): 535 -> 452 fused ops, 42 -> 31 divisions per backward step, the
# gradient of 1,000 lanes ~5 % faster. Saving more (g(v), the net torque) helped only in chunks of
# 40 lanes, was slower in chunks of 200 (its residuals leave the cache) and no faster in map_lanes'
# chunks of 64 (14.5-14.8 against 14.3-14.4 ms).
_REMAT_POLICY = jax.checkpoint_policies.save_only_these_names(_STAGE_INPUT)


def _rk_step(tableau, f, t, y, h, k0):
    """One explicit Runge-Kutta step from diffrax's Butcher ``tableau``, stages unrolled.

    diffrax's generic ``step`` runs its stages in a ``while_loop``; under ``vmap`` over a batch that
    loop and its bookkeeping made the solve about 2x slower, measured. Unrolled stages fuse into a
    few vectorised XLA loops. ``k0 = f(t, y)`` is passed in so FSAL tableaus reuse it.
    """
    def combo(coeffs):
        terms = [(float(c), k) for c, k in zip(coeffs, ks) if c != 0]
        return tuple(
            yc + h * sum(c * k[i] for c, k in terms) for i, yc in enumerate(y)
        )

    # 1.0 computed from the state, so XLA can never fold it to a constant (see _fusion); NaN only
    # in a lane whose state is already NaN, so it changes no result.
    one = runtime_one(y[0])
    ks = [k0]
    for i, a in enumerate(tableau.a_lower):
        # Named so that a reverse pass keeps them from its forward sweep (see _solve_fixed).
        stage = tuple(checkpoint_name(c, _STAGE_INPUT) for c in _stored_once(combo(a), one))
        ks.append(f(t + float(tableau.c[i]) * h, stage))
    y1 = combo(tableau.b_sol)
    k1 = ks[-1] if tableau.fsal else f(t + h, y1)
    return y1, k1


def _step_plan(dt: float, sample_hz: float) -> tuple[int, int]:
    """``(steps per sample, samples per step)`` for a fixed step ``dt`` [s]: either a step divides
    the sample period (rounded down to a divisor), or it spans a whole number of samples."""
    h_sample = 1.0 / sample_hz
    if dt <= h_sample * (1 + 1e-9):
        return max(1, math.ceil(h_sample / dt - 1e-9)), 1
    m = round(dt / h_sample)
    if abs(m * h_sample - dt) > 1e-9 * dt:
        raise ValueError(
            f"dt={dt!r} s is longer than the sample period 1/sample_hz={h_sample!r} s but not a whole "
            "multiple of it; choose dt <= 1/sample_hz, or dt = k/sample_hz for an integer k (the "
            "samples between steps are then interpolated)"
        )
    return 1, m


def _hermite(y0, k0, y1, k1, h, s):
    """Cubic Hermite interpolant at fraction ``s`` of a step of length ``h`` (``k`` = dy/dt at the
    ends): third-order accurate, so it keeps the order of the Bosh3/Heun steps it sits between."""
    s2, s3 = s * s, s * s * s
    a, b, c, d = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, 3 * s2 - 2 * s3, s3 - s2
    return tuple(a * p + (b * h) * kp + c * q + (d * h) * kq for p, kp, q, kq in zip(y0, k0, y1, k1))


def _solve_fixed(system: System, n: int, sample_hz: float, dt: float, solver_name: str, sample_fn=None):
    """Fixed-step solve: ``(ys, result)``, or with ``sample_fn`` ``(mean of sample_fn, result)``."""
    tableau = _FIXED_SOLVERS[solver_name].tableau
    h_sample = 1.0 / sample_hz
    sub, span = _step_plan(dt, sample_hz)
    h = h_sample * span / sub
    y0 = _split(system.y0)

    def f(t, y):
        return _rates(t, y, system)

    def substep(carry, _):
        t, y, k = carry
        y1, k1 = _rk_step(tableau, f, t, y, h, k)
        return (t + h, y1, k1), None

    def block(carry, i):
        # Emit the state at the block's first sample, then step to the next block (one sample, or
        # ``span`` samples with one long step whose inner samples are interpolated from the step's
        # end values and slopes, both already computed: no extra right-hand-side evaluations).
        # The rows are written in place, with no concatenation of y0 afterwards (a second pass
        # over the whole trajectory buffer); the last step is wasted (1/n). Restart time from the
        # sample index each block so rounding in t never accumulates.
        # Each state component is emitted as its own trajectory and stacked only after the loop:
        # a stacked (n, 8) row is one output, written whole every step even when the caller reads
        # one column, and under jacfwd its six tangent copies too. Separate outputs let jit drop
        # every trajectory (and tangent trajectory) that nothing reads. Measured, one core:
        # batch-1 solve 1.8 -> 0.29 ms, 200 single-segment lanes 14.7 -> 5.2 ms, their forward-mode
        # Jacobian 205 -> 70 ms.
        y, k, finite, acc = carry
        for c in y:
            finite = finite & jnp.isfinite(c)
        t0 = i * span * h_sample
        (_, y1, k1), _ = jax.lax.scan(substep, (t0, y, k), None, length=sub)
        rows = [y] + [_hermite(y, k, y1, k1, h, j / span) for j in range(1, span)]
        if sample_fn is None:
            out = y if span == 1 else tuple(jnp.stack(col) for col in zip(*rows))
            return (y1, k1, finite, acc), out
        # With sample_fn each sample is reduced where it is computed: no trajectory is stored, and
        # a reverse pass reads no trajectory of cotangents. An interpolated sample's derivative is
        # read by the four inputs of its interpolant: computed once (see _fusion).
        one = runtime_one(y[0])
        for j, row in enumerate(rows):
            if j:
                row = tuple(derivative_stored_once(c, one) for c in row)
            index = i * span + j
            val = sample_fn(_sample(system, index, t0 + j * h_sample, row))
            acc = jax.tree.map(lambda a, v: a + jnp.where(index < n, v, 0.0), acc, val)
        return (y1, k1, finite, acc), None

    n_blocks = -(-n // span)
    k0 = f(jnp.asarray(0.0), y0)
    acc0 = None
    if sample_fn is not None:
        shapes = jax.eval_shape(sample_fn, _sample(system, jnp.asarray(0), jnp.asarray(0.0), y0))
        acc0 = jax.tree.map(lambda x: jnp.zeros(x.shape, x.dtype), shapes)
    init = (y0, k0, jnp.asarray(True), acc0)
    body = jax.checkpoint(block, policy=_REMAT_POLICY)
    (_, _, ok, acc), ys = jax.lax.scan(body, init, jnp.arange(n_blocks))
    code = jnp.where(ok, RESULT_OK, RESULT_NONFINITE)
    if sample_fn is not None:
        return jax.tree.map(lambda a: a / n, acc), code
    if span > 1:  # (blocks, span, ...) -> samples, dropping the interpolated tail past the end
        ys = tuple(c.reshape((n_blocks * span,) + c.shape[2:])[:n] for c in ys)
    return jnp.stack(ys, axis=-1), code


def _solve_adaptive(system: System, ts, rtol, atol, max_steps, solver_name, dt0):
    solver = {"kvaerno5": diffrax.Kvaerno5, "kvaerno3": diffrax.Kvaerno3,
              "tsit5": diffrax.Tsit5, "dopri5": diffrax.Dopri5}[solver_name]()
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(vector_field), solver, t0=ts[0], t1=ts[-1], dt0=dt0, y0=system.y0,
        args=system, saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol, dtmax=1.0 / 50),
        max_steps=max_steps, throw=False,
    )
    solved = sol.result == diffrax.RESULTS.successful
    finite = jnp.all(jnp.isfinite(sol.ys))
    code = jnp.where(solved, jnp.where(finite, RESULT_OK, RESULT_NONFINITE), RESULT_SOLVER_FAILED)
    return sol.ys, code


def _outputs(system: System, ts, ys, result) -> Solution:
    _, aux = jax.vmap(lambda t, y: _signals(t, _split(y), system))(ts, ys)
    return Solution(ts, ys, aux["torque_nm"], aux["friction_nm"], aux["theta_ref"], aux["v_ref"],
                    result)


def _solve_one(system, *, n, sample_hz, method, dt, solver, rtol, atol, max_steps, reduce=None,
               sample_fn=None):
    # A non-positive inertia is a malformed system, not a bad candidate: fail loudly (traced check),
    # rather than return a lane of NaN that an optimiser would read as merely "infinitely bad".
    J = eqx.error_if(
        system.joint.J, ~(system.joint.J > 0),
        "Joint.J must be > 0 N*m*s^2/deg (equivalent inertia at the joint)",
    )
    system = eqx.tree_at(lambda s: s.joint.J, system, J)
    ts = jnp.arange(n) / sample_hz
    if method == "fixed" and sample_fn is not None:
        return SampleMean(*_solve_fixed(system, n, sample_hz, dt, solver, sample_fn))
    if method == "fixed":
        ys, res = _solve_fixed(system, n, sample_hz, dt, solver)
    else:
        ys, res = _solve_adaptive(system, ts, rtol, atol, max_steps, solver, dt)
    if sample_fn is not None:  # adaptive: the same mean, from the sampled solution
        vals = jax.vmap(lambda i, t, y: sample_fn(_sample(system, i, t, _split(y))))(jnp.arange(n), ts, ys)
        return SampleMean(jax.tree.map(lambda v: jnp.mean(v, axis=0), vals), res)
    sol = _outputs(system, ts, ys, res)
    return sol if reduce is None else reduce(sol)


def batch_size_of(system: System) -> int:
    """Leading axis shared by every array leaf of a batched system (raises if they disagree).

    Python-number leaves (e.g. ``delta = 2.0``) are compile-time constants shared by all lanes.
    """
    return _lane_count(system, "a batched System", "use lugre_jax.broadcast_system(system, n) or "
                       "lugre_jax.stack_systems([...]) to build one")


def broadcast_system(system: System, n: int) -> System:
    """Repeat an unbatched system ``n`` times along a new leading axis (Python numbers stay shared)."""
    return jax.tree.map(lambda x: jnp.broadcast_to(x, (n,) + x.shape) if eqx.is_array(x) else x, system)


def stack_systems(systems: list[System]) -> System:
    """Stack systems of identical structure into one batched system (Python numbers must agree)."""
    def stack(*xs):
        if eqx.is_array(xs[0]):
            return jnp.stack(xs)
        if any(x != xs[0] for x in xs):
            raise ValueError("stack_systems: Python-number fields differ between systems; pass arrays")
        return xs[0]
    return jax.tree.map(stack, *systems)


def simulate(
    system: System,
    duration_s: float,
    sample_hz: float = 100.0,
    *,
    batched: bool = False,
    method: Literal["fixed", "adaptive"] = "fixed",
    dt: float | None = None,
    solver: str | None = None,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 200_000,
    chunk_size: int | None = None,
    shard: bool | None = None,
    reduce=None,
    sample_mean=None,
) -> Solution | SampleMean:
    """Simulate ``system`` from rest (or ``system.y0``) for ``duration_s`` seconds.

    Samples at ``t = 0, 1/sample_hz, ..., duration_s`` (positions in deg, velocities in deg/s,
    torques in N*m). With ``batched=True`` every leaf of ``system`` has a leading batch axis and all
    lanes are solved in one jitted call: lanes are processed ``chunk_size`` at a time (bounded
    memory; the default, about 200 lanes per chunk, keeps a step's working set in cache, measured
    2.5x faster than one big vmap at 10,000 lanes) and, when several devices exist, split across
    them: always with ``shard=True``, never with ``False``, and by default (``None``) when the call
    has enough work to pay for the split (about 4e6 right-hand-side evaluations, measured; e.g.
    2,000 lanes of Bosh3 at 20 ms over 20 s).

    ``method="fixed"``: constant step ``dt`` [s] (default 2.5 ms, capped at the sample period: see
    README for the error it gives) with a diffrax explicit RK ``solver`` (default ``"tsit5"``). A
    ``dt`` shorter than the sample period is rounded down to divide it; a longer one must be a whole
    multiple of it, and the samples between steps are cubic-Hermite interpolated from the step's
    end values and slopes (no extra right-hand-side evaluations). ``method="adaptive"``:
    Kvaerno5 (default) with ``rtol``/``atol`` and ``max_steps``. Differentiable in every leaf of
    ``system``. Measured (README, "Derivatives"): for a scalar loss over a batch of 100 or more
    lanes reverse mode (``jax.grad``) is cheaper; at batch 1, and for a Jacobian of many outputs
    (residuals) with few parameters, forward mode (``jax.jacfwd``).

    ``reduce``: optional function ``Solution -> pytree`` applied to each lane inside the jitted
    call (e.g. a loss); only its result is returned, so memory no longer grows with the number of
    samples (how a swarm of 100,000 parameter sets fits in a few GB). Failed lanes still report
    ``Solution.result``: combine with :func:`trajectory_loss` inside ``reduce``.

    ``sample_mean``: optional function ``Sample -> pytree`` (one sample of one lane: its index,
    time, state, torques and reference; see :class:`Sample`); returns a :class:`SampleMean`
    holding, per lane, the mean of that function over all samples, and the result code. The
    fixed-step solver evaluates it where each sample is computed, inside the time loop: nothing
    of the trajectory is stored, and a gradient's backward pass reads no trajectory of
    cotangents. For a loss that is a mean over samples (tracking errors, a fit to measured data
    through ``Sample.index``) this is the fast path: measured on the benchmark's one-segment joint
    (1,000 lanes, one core, README "Benchmark"), the forward solve 4.7 -> 3.8 ms and its
    reverse-mode gradient 21 -> 14 ms against the same loss read from the stored trajectory.
    ``SampleMean.or_inf()`` makes failed lanes infinitely bad. The adaptive method computes the
    same mean from its samples.
    """
    require_x64()
    if method not in ("fixed", "adaptive"):
        raise ValueError(f"method must be 'fixed' or 'adaptive', got {method!r}")
    if sample_mean is not None and reduce is not None:
        raise ValueError("give reduce (a function of the whole Solution) or sample_mean (a function "
                         "of one Sample, averaged over samples), not both")
    for name, fn in (("reduce", reduce), ("sample_mean", sample_mean)):
        if fn is not None and not callable(fn):
            raise ValueError(f"{name} must be a function, got {type(fn).__name__}")
    n = _sample_grid(float(duration_s), float(sample_hz))
    if method == "fixed":
        # The default step is capped at the sample period; an explicit longer step must span a
        # whole number of samples (checked in _step_plan).
        dt = min(2.5e-3, 1.0 / float(sample_hz)) if dt is None else float(dt)
        solver = solver or "tsit5"
        if solver not in _FIXED_SOLVERS:
            raise ValueError(f"fixed-step solver must be one of {sorted(_FIXED_SOLVERS)}, got {solver!r}")
        if not dt > 0:
            raise ValueError(f"dt must be a positive step in seconds, got {dt!r}")
        _step_plan(dt, float(sample_hz))
    else:
        dt = 1e-4 if dt is None else float(dt)
        solver = solver or "kvaerno5"
    kw = dict(n=n, sample_hz=float(sample_hz), method=method, dt=dt, solver=solver, rtol=rtol,
              atol=atol, max_steps=int(max_steps), reduce=reduce, sample_fn=sample_mean)
    if not batched:
        return _jit_one(system, **kw)
    b = batch_size_of(system)
    return _simulate_batched(system, b, kw, chunk_size, shard)


@eqx.filter_jit
def _jit_one(system, **kw):
    return _solve_one(system, **kw)


_DEFAULT_CHUNK = 200


# Sharding over host devices has a fixed cost of about 2.5 ms per call (100 lanes of the benchmark
# joint, Bosh3 at 20 ms: 2.8-3.1 ms on one device, 5.4 ms on two). Measured on 2 cores, it pays from
# about 4e6 right-hand-side evaluations per call: that Bosh3 run is even at 1,000 lanes (3e6;
# 1.06x) and 1.67x at 2,000 (6e6); Heun at 10 ms 1.15-1.2x at 1,000 lanes (4e6); Tsit5 at 2.5 ms
# 1.5x at 100 lanes (4.8e6). Below it, shard=None runs on one device. Rechecked with 512-bit vectors
# (see _config): the Bosh3 run 0.85-0.89x at 1,000 lanes and 1.37-1.41x at 2,000.
_SHARD_MIN_EVALS = 4e6


def _evals_per_step(solver_name: str) -> int:
    """Right-hand-side evaluations per fixed step (an FSAL tableau's last stage is the next k0)."""
    tableau = _FIXED_SOLVERS[solver_name].tableau
    return len(tableau.a_lower) + (0 if tableau.fsal else 1)


def _rhs_evals(b, kw) -> float:
    """Right-hand-side evaluations of a batched fixed-step solve (inf for the adaptive method)."""
    if kw["method"] != "fixed":
        return math.inf
    sub, span = _step_plan(kw["dt"], kw["sample_hz"])
    steps = -(-(kw["n"] - 1) // span) * sub
    return float(b) * steps * _evals_per_step(kw["solver"])


def _simulate_batched(system, b, kw, chunk_size, shard):
    if shard is None:
        shard = _rhs_evals(b, kw) >= _SHARD_MIN_EVALS
    key = ("simulate", tuple(sorted(kw.items())))
    sol = _chunked_lanes(key, lambda s: _solve_one(s, **kw), system, b, chunk_size, shard)
    if kw["reduce"] is not None or kw["sample_fn"] is not None:
        return sol
    return eqx.tree_at(lambda s: s.ts, sol, sol.ts[0])


def _chunked_lanes(key, one_lane, tree, b: int, chunk_size, shard: bool, default_chunk: int = None,
                   lane_multiple: int = 1):
    """``jax.vmap(one_lane)(tree)`` over the ``b`` lanes (leading axis) of ``tree``'s arrays, in
    chunks, split across host devices when ``shard``; compiled once per ``key`` (hashable). A
    default chunk of more than ``lane_multiple`` lanes is rounded up to a multiple of it."""
    default_chunk = default_chunk or _DEFAULT_CHUNK
    devices = jax.devices()
    ndev = max(1, min(len(devices) if shard else 1, b))
    per_dev = -(-b // ndev)
    if chunk_size is None:
        # Chunks of ~_DEFAULT_CHUNK lanes keep a step's working set in cache: measured on the
        # benchmark (2-core CPU, 10,000 lanes) 19,700 sims/s against 7,700 for one 5,000-lane
        # chunk per device. Balanced so that padding stays below one lane per chunk, or below
        # ``lane_multiple`` lanes per chunk when chunks are rounded up to whole vectors.
        n_chunks = -(-per_dev // default_chunk)
        chunk = -(-per_dev // n_chunks)
        if chunk > lane_multiple:
            chunk = -(-chunk // lane_multiple) * lane_multiple
    else:
        chunk = max(1, min(int(chunk_size), per_dev))
    per_dev = -(-per_dev // chunk) * chunk
    total = per_dev * ndev
    if total != b:  # pad with copies of lane 0, dropped afterwards
        tree = jax.tree.map(
            lambda x: jnp.concatenate([x, jnp.repeat(x[:1], total - b, 0)]) if eqx.is_array(x) else x,
            tree,
        )
    fn = _compiled(ndev, chunk, key, one_lane)
    if ndev > 1:
        mesh = Mesh(np.array(devices[:ndev]), ("lanes",))
        tree = eqx.combine(
            jax.device_put(eqx.filter(tree, eqx.is_array), NamedSharding(mesh, PartitionSpec("lanes"))),
            eqx.filter(tree, eqx.is_array, inverse=True),
        )
    dyn, static = eqx.partition(tree, eqx.is_array)
    return jax.tree.map(lambda x: x[:b], fn(dyn, static))


def _lane_count(tree, what: str, fix: str) -> int:
    arrays = [x for x in jax.tree.leaves(tree) if eqx.is_array(x)]
    sizes = {x.shape[0] for x in arrays if x.ndim > 0}
    if len(sizes) != 1 or any(x.ndim == 0 for x in arrays):
        raise ValueError(
            f"{what} needs one leading batch axis on every array leaf; {fix} "
            f"(found leading sizes {sorted(sizes)} and {sum(x.ndim == 0 for x in arrays)} unbatched scalars)"
        )
    return sizes.pop()


_CACHE: dict = {}


def _compiled(ndev: int, chunk: int, key, one_lane):
    """One jitted function per (devices, chunk, key): repeated calls reuse the compilation."""
    key = (ndev, chunk, key)
    if key in _CACHE:
        return _CACHE[key]

    def run_chunks(tree):
        # lax.map over chunks keeps peak memory at one chunk's working set.
        dyn, static = eqx.partition(tree, eqx.is_array)
        n_lanes = jax.tree.leaves(dyn)[0].shape[0]
        dyn = jax.tree.map(lambda x: x.reshape((n_lanes // chunk, chunk) + x.shape[1:]), dyn)
        per_chunk = jax.vmap(lambda d: one_lane(eqx.combine(d, static)))
        if n_lanes > chunk:
            # Under reverse mode, a lax.map stores every iteration's residuals before its first
            # backward step: all chunks' stored states at once, out of cache (measured: the
            # gradient of 1,000 lanes in 5 chunks 53 ms; 21 ms with this; map_lanes 14 ms). Each chunk
            # is recomputed instead, just before its own backward sweep: one more forward sweep.
            # A forward solve is unaffected. For per-lane gradients use map_lanes, which
            # differentiates chunk by chunk and needs neither.
            per_chunk = jax.checkpoint(per_chunk)
        out = jax.lax.map(per_chunk, dyn)
        return jax.tree.map(lambda x: x.reshape((n_lanes,) + x.shape[2:]), out)

    def fn(dyn, static):
        run = lambda d: run_chunks(eqx.combine(d, static))  # noqa: E731
        if ndev > 1:
            mesh = Mesh(np.array(jax.devices()[:ndev]), ("lanes",))
            run = jax.shard_map(run, mesh=mesh, in_specs=PartitionSpec("lanes"),
                                out_specs=PartitionSpec("lanes"), check_vma=False)
        return run(dyn)

    _CACHE[key] = eqx.filter_jit(fn)
    if len(_CACHE) > 64:  # bounded: each entry holds a compiled executable
        _CACHE.pop(next(iter(_CACHE)))
    return _CACHE[key]


def map_lanes(fn, xs: PyTree, *, chunk_size: int | None = None, shard: bool | None = None) -> PyTree:
    """``jax.vmap(fn)(xs)``, computed the way batched :func:`simulate` computes its lanes.

    ``xs`` is a pytree whose array leaves share a leading lane axis (e.g. parameter sets (n, 6), or a
    batched :class:`System`); ``fn`` maps one lane to a pytree. Lanes go ``chunk_size`` at a time
    (default ~64, balanced, a multiple of 8) and, with ``shard=True`` or by default when several
    host devices exist and there are at least two default chunks' worth of lanes (128), split
    across devices: measured for gradients, two devices 0.85x as fast at 64 lanes, 1.5x at 128,
    2.0x at 256. The default chunk
    is the reverse pass's: it stores each lane's state at every step, and in chunks of 200
    (simulate's default, best for forward solves) that left the cache; and a chunk that is not a
    multiple of the 8 float64 lanes of a 512-bit vector is slow. Measured, gradients of 1,000
    one-segment lanes (Bosh3, 20 ms, 20 s), one core: 14.0-16.8 ms in chunks of 56, 64, 72 or 104
    lanes, 17.1 ms in chunks of 100, 23 ms in chunks of 63 or 200, 32-39 ms in chunks of 24-32; on
    two devices 7.9-9.1 ms against 16 ms in chunks of 200.

    The use it is for: per-lane derivatives of per-lane losses, e.g. a swarm's gradients,
    ``map_lanes(jax.value_and_grad(loss), P)`` with ``loss(p)`` simulating one lane (ideally with
    ``simulate(..., sample_mean=...)``). Each chunk is differentiated on its own, so a reverse
    pass's stored states stay in cache. ``jax.grad`` of a sum over one batched ``simulate`` call
    gives the same numbers, but it recomputes each chunk's forward solve before that chunk's
    backward sweep (README, "Simulator": 1,000 lanes 21 ms against 14 ms here, one core).

    ``fn`` is part of the compilation's key, as with ``jax.jit``: pass the same function object to
    reuse the compiled program (a new lambda per call compiles anew).
    """
    if not callable(fn):
        raise ValueError(f"map_lanes needs a function of one lane, got {type(fn).__name__}")
    b = _lane_count(xs, "map_lanes", "give every array leaf of xs the same leading (lane) axis")
    if shard is None:
        shard = len(jax.devices()) > 1 and b >= 2 * _MAP_LANES_CHUNK
    return _chunked_lanes(("map_lanes", fn), fn, xs, b, chunk_size, shard, _MAP_LANES_CHUNK, _VECTOR_LANES)


_MAP_LANES_CHUNK = 64
_VECTOR_LANES = 8  # float64 lanes of the 512-bit vectors lugre_jax asks XLA for (see _config)


def trajectory_loss(sol: Solution, reduce) -> Array:
    """``reduce(sol)`` where the lane succeeded, ``+inf`` where it failed: failed runs are infinitely bad."""
    val = reduce(sol)
    return jnp.where(sol.result == RESULT_OK, val, jnp.inf)
