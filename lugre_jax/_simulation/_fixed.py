"""Fixed-step explicit Runge-Kutta in ``lax.scan``, stages unrolled, samples reduced in the loop."""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.ad_checkpoint import checkpoint_name

from .._fusion import derivative_stored_once, runtime_one
from .._fusion import stored_once as _stored_once
from ..friction import exp_phi1
from ._solution import RESULT_NONFINITE, RESULT_OK
from ._stepping import ExponentialBristle, step_for, step_plan
from ._system import rates, sample, split

_STAGE_INPUT = "lugre_jax_stage_input"
# Reverse mode recomputes each sample block from its stored state, except the stage inputs, which
# its forward sweep stores: recomputing them costs a division per component per backward step (to
# keep them stored once, see _fusion) and their combinations. Saving more (g(v), the net torque)
# did not pay (docs/performance.md).
_REMAT_POLICY = jax.checkpoint_policies.save_only_these_names(_STAGE_INPUT)


def rk_step(tableau, f, t, y, h, k0, bristle=None):
    """One explicit Runge-Kutta step from diffrax's Butcher ``tableau``, stages unrolled.

    diffrax's generic ``step`` runs its stages in a ``while_loop``; under ``vmap`` that loop and its
    bookkeeping cost more than the stages. Unrolled stages fuse into a few vectorised XLA loops.
    ``k0 = f(t, y)`` is passed in so FSAL tableaus reuse it.

    ``bristle`` (a :class:`_Bristle`), if given, makes it the step of :class:`ExponentialBristle`:
    where the bristle is stiff, the bristle state of every stage and of the result is its exact
    update from the step's start (velocity frozen at the stage's mean), and the velocity always
    integrates the joint's acceleration without the bristle damping ``sigma1*dz/dt``, whose
    integral is ``sigma1*(z - z0)`` (without stiffness this is the plain Runge-Kutta step).
    """
    def combo(coeffs, c_frac):
        terms = [(float(c), k) for c, k in zip(coeffs, ks) if c != 0]
        out = tuple(
            yc + h * sum(c * k[i] for c, k in terms) for i, yc in enumerate(y)
        )
        if bristle is None:
            return out
        tau = c_frac * h
        dpath = h * sum(c * k[0] for c, k in terms)
        z, s1, x = bristle.advance(y[2], dpath, tau)
        # The solver's own stage where the bristle is not stiff (x = q*tau << 1: it keeps the
        # solver's order there), the exact update where it is; blended smoothly in between.
        x2 = x * x
        x4 = x2 * x2
        w = x4 / (1.0 + x4)
        z = out[2] + w * (z - out[2])
        omega = y[1] + h * sum(c * m for c, m in zip(coeffs, ms) if c != 0) - s1 * (z - y[2]) * bristle.inv_J
        return (out[0], omega, z) + out[3:]

    # 1.0 computed from the state, so XLA can never fold it to a constant (see _fusion); NaN only
    # in a lane whose state is already NaN, so it changes no result.
    one = runtime_one(y[0])
    ks = [k0]
    ms = [] if bristle is None else [bristle.undamped(y, k0)]
    last = len(tableau.a_lower) - 1
    for i, a in enumerate(tableau.a_lower):
        # Named so that a reverse pass keeps them from its forward sweep (see _REMAT_POLICY).
        stage = tuple(checkpoint_name(c, _STAGE_INPUT) for c in _stored_once(combo(a, float(tableau.c[i])), one))
        ks.append(f(stage_time(t, h, float(tableau.c[i]), tableau.fsal and i == last), stage))
        if bristle is not None:
            ms.append(bristle.undamped(stage, ks[-1]))
    y1 = combo(tableau.b_sol, 1.0)
    k1 = ks[-1] if tableau.fsal else f(t + h, y1)
    return y1, k1


class _Bristle:
    """What :func:`rk_step` needs of the friction law and the joint for :class:`ExponentialBristle`."""

    def __init__(self, friction, J):
        self.friction = friction
        self.inv_J = 1.0 / J

    def advance(self, z, dpath, tau):
        """``(z, sigma1, q*tau)``: the bristle state after time ``tau`` [s] in which the joint moved by
        ``dpath`` [deg], the velocity frozen at ``dpath/tau``, exact for ``dz/dt = p(v) - q(v)*z``;
        the bristle damping at that velocity; and the stiffness times the time.

        ``p`` and ``q`` are read off the friction law itself at ``z = 0`` and ``z = 1`` (its
        ``dz/dt`` is affine in ``z``), so segmented and blended laws need nothing of their own.
        ``exp(-q*tau)`` contracts however large the stiffness times the time is. The frozen
        velocity is the mean over ``tau`` (not the velocity at its end, which is less accurate on
        stick-slip lanes: docs/performance.md), so that without stiffness ``z`` advances by the
        displacement."""
        v = dpath * (1.0 / tau)
        zero = jnp.zeros_like(z)
        _, p = self.friction.torque_and_derivative(zero, v)
        _, p_minus_q = self.friction.torque_and_derivative(zero + 1.0, v)
        x = (p - p_minus_q) * tau
        decay, phi, _, _ = exp_phi1(x)
        return decay * z + (p * tau) * phi, self.friction.bristle_damping(v), x

    def undamped(self, y, k):
        """The joint's acceleration without the bristle damping's ``sigma1*dz/dt/J``."""
        return k[1] + self.friction.bristle_damping(y[1]) * k[2] * self.inv_J


def stage_time(t, h, c: float, fsal_stage: bool = False):
    """Time of a stage at fraction ``c`` of the step ``[t, t + h]``.

    A stage at the step's end that enters the step's update (Tsit5's and Dopri5's sixth) is
    evaluated at the left limit, just below ``t + h``: the step belongs to the interval before a
    discontinuity of the reference landing there. An FSAL stage is the next step's first slope and
    is evaluated at ``t + h`` itself (the right limit)."""
    if c == 1.0 and not fsal_stage:
        return below(t + h)
    return t + c * h


# One or two units in the last place below / above a positive time: jnp.nextafter is a scalar
# library call per element that XLA:CPU neither fuses nor vectorises.
_ULP = 2.0**-52


def below(t):
    """A float just below a positive time ``t`` (the left limit of a discontinuity there)."""
    return t * (1.0 - _ULP)


def above(t):
    """A float just above a positive time ``t`` (the right limit of a discontinuity there)."""
    return t * (1.0 + _ULP)


def rhs_evals(stepping, n: int, sample_hz: float) -> int:
    """Right-hand-side evaluations of one lane's fixed-step solve over ``n`` samples."""
    sub, span = step_plan(step_for(stepping, sample_hz), sample_hz)
    return -(-(n - 1) // span) * sub * stepping.evals_per_step


def _hermite(y0, k0, y1, k1, h, s):
    """Cubic Hermite interpolant at fraction ``s`` of a step of length ``h`` (``k`` = dy/dt at the
    ends): third-order accurate, so it keeps the order of the Bosh3/Heun steps it sits between."""
    s2, s3 = s * s, s * s * s
    a, b, c, d = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, 3 * s2 - 2 * s3, s3 - s2
    return tuple(a * p + (b * h) * kp + c * q + (d * h) * kq for p, kp, q, kq in zip(y0, k0, y1, k1))


def solve_fixed(system, n: int, sample_hz: float, stepping, sample_fn=None):
    """Fixed-step solve: ``(ys, result)``, or with ``sample_fn`` ``(mean of sample_fn, result)``.
    ``stepping`` is a :class:`FixedStep` or an :class:`ExponentialBristle` (bristle state exact)."""
    tableau = stepping.solver.tableau
    bristle = _Bristle(system.friction, system.joint.J) if isinstance(stepping, ExponentialBristle) else None
    h_sample = 1.0 / sample_hz
    sub, span = step_plan(step_for(stepping, sample_hz), sample_hz)
    h = h_sample * span / sub
    y0 = split(system.y0)

    def f(t, y):
        return rates(t, y, system)

    def substep(carry, j):
        t0, y, k = carry
        # Times from the block's start and the substep's index, the last one ending exactly at the
        # next block's start: a discontinuity of the reference on the grid is met at the same
        # float time by the step that ends there and the step that starts there.
        t = t0 + j * h
        t_end = jnp.where(j == sub - 1, t0 + span * h_sample, t + h)
        y1, k1 = rk_step(tableau, f, t, y, t_end - t, k, bristle)
        return (t0, y1, k1), None

    def block(carry, i):
        # Emit the state at the block's first sample, then step to the next block (one sample, or
        # ``span`` samples with one long step whose inner samples are interpolated from the step's
        # end values and slopes, both already computed: no extra right-hand-side evaluations).
        # Rows are written in place (no concatenation of y0 afterwards); the last step is wasted
        # (1/n). Time restarts from the sample index each block so rounding never accumulates.
        # Each state component is its own output, stacked only after the loop, so jit drops every
        # trajectory (and tangent trajectory) that nothing reads.
        y, k, finite, acc = carry
        for c in y:
            finite = finite & jnp.isfinite(c)
        t0 = i * span * h_sample
        (_, y1, k1), _ = jax.lax.scan(substep, (t0, y, k), jnp.arange(sub))
        rows = [y] + [_hermite(y, k, y1, k1, h, j / span) for j in range(1, span)]
        if bristle is not None:
            # between steps the bristle state too is the exact update, along the interpolated path
            rows = [rows[0]] + [r[:2] + (bristle.advance(y[2], r[0] - y[0], (j / span) * h)[0],) + r[3:]
                                for j, r in enumerate(rows[1:], start=1)]
        if sample_fn is None:
            out = y if span == 1 else tuple(jnp.stack(col) for col in zip(*rows))
            return (y1, k1, finite, acc), out
        # Each sample is reduced where it is computed: no trajectory is stored, and a reverse pass
        # reads no trajectory of cotangents. An interpolated sample's derivative is read by the
        # four inputs of its interpolant: computed once (see _fusion).
        one = runtime_one(y[0])
        for j, row in enumerate(rows):
            if j:
                row = tuple(derivative_stored_once(c, one) for c in row)
            index = i * span + j
            val = sample_fn(sample(system, index, t0 + j * h_sample, row))
            acc = jax.tree.map(lambda a, v: a + jnp.where(index < n, v, 0.0), acc, val)
        return (y1, k1, finite, acc), None

    n_blocks = -(-n // span)
    k0 = f(jnp.asarray(0.0), y0)
    acc0 = None
    if sample_fn is not None:
        shapes = jax.eval_shape(sample_fn, sample(system, jnp.asarray(0), jnp.asarray(0.0), y0))
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
