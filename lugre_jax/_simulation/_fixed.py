"""Fixed-step explicit Runge-Kutta in ``lax.scan``, stages unrolled, samples reduced in the loop."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
from jax.ad_checkpoint import checkpoint_name

from .._fusion import derivative_stored_once, runtime_one
from .._fusion import stored_once as _stored_once
from ._solution import RESULT_NONFINITE, RESULT_OK
from ._stepping import step_for
from ._system import rates, sample, split

_STAGE_INPUT = "lugre_jax_stage_input"
# Reverse mode recomputes each sample block from its stored state, except the stage inputs, which
# its forward sweep stores: recomputing them costs a division per component per backward step (to
# keep them stored once, see _fusion) and their combinations. Saving more (g(v), the net torque)
# did not pay (docs/performance.md).
_REMAT_POLICY = jax.checkpoint_policies.save_only_these_names(_STAGE_INPUT)


def rk_step(tableau, f, t, y, h, k0):
    """One explicit Runge-Kutta step from diffrax's Butcher ``tableau``, stages unrolled.

    diffrax's generic ``step`` runs its stages in a ``while_loop``; under ``vmap`` that loop and its
    bookkeeping cost more than the stages. Unrolled stages fuse into a few vectorised XLA loops.
    ``k0 = f(t, y)`` is passed in so FSAL tableaus reuse it.
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
        # Named so that a reverse pass keeps them from its forward sweep (see _REMAT_POLICY).
        stage = tuple(checkpoint_name(c, _STAGE_INPUT) for c in _stored_once(combo(a), one))
        ks.append(f(t + float(tableau.c[i]) * h, stage))
    y1 = combo(tableau.b_sol)
    k1 = ks[-1] if tableau.fsal else f(t + h, y1)
    return y1, k1


def step_plan(dt: float, sample_hz: float) -> tuple[int, int]:
    """``(steps per sample, samples per step)`` for a fixed step ``dt`` [s]: either a step divides
    the sample period (rounded down to a divisor), or it spans a whole number of samples."""
    h_sample = 1.0 / sample_hz
    if dt <= h_sample * (1 + 1e-9):
        return max(1, math.ceil(h_sample / dt - 1e-9)), 1
    m = round(dt / h_sample)
    if abs(m * h_sample - dt) > 1e-9 * dt:
        raise ValueError(
            f"FixedStep.dt={dt!r} s is longer than the sample period 1/sample_hz={h_sample!r} s but not "
            "a whole multiple of it; choose dt <= 1/sample_hz, or dt = k/sample_hz for an integer k "
            "(the samples between steps are then interpolated)"
        )
    return 1, m


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
    """Fixed-step solve: ``(ys, result)``, or with ``sample_fn`` ``(mean of sample_fn, result)``."""
    tableau = stepping.solver.tableau
    h_sample = 1.0 / sample_hz
    sub, span = step_plan(step_for(stepping, sample_hz), sample_hz)
    h = h_sample * span / sub
    y0 = split(system.y0)

    def f(t, y):
        return rates(t, y, system)

    def substep(carry, _):
        t, y, k = carry
        y1, k1 = rk_step(tableau, f, t, y, h, k)
        return (t + h, y1, k1), None

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
        (_, y1, k1), _ = jax.lax.scan(substep, (t0, y, k), None, length=sub)
        rows = [y] + [_hermite(y, k, y1, k1, h, j / span) for j in range(1, span)]
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
