"""Two identities that steer XLA:CPU's fusion: values and derivatives computed once, not per consumer.

XLA:CPU fuses a cheap elementwise value into every kernel that reads it and recomputes it there.
It never duplicates an op it rates expensive (a division, an exponential), so dividing a value by a
runtime 1.0 makes XLA compute it once and store it. The division is exact, so results change only
by rounding (XLA contracts fused and stored expressions into multiply-adds differently; tested).

* :func:`stored_once` divides a value *and* its derivative: used on the stage inputs of an explicit
  Runge-Kutta step, which every later stage reads (see ``_simulation._fixed.rk_step``).
* :func:`derivative_stored_once` leaves the value alone (a forward solve compiles exactly as without
  it) and divides only its tangent. Under reverse mode the transpose of that division divides the
  cotangent, so a cotangent that many kernels of the backward pass read is computed once. Sites
  (chosen by a greedy search over the compiled backward step): the joint's net torque and dz/dt
  per stage, LuGre's g(v), samples interpolated between steps. It shrinks the compiled backward
  step (``tests/test_simulate.py`` checks the op counts); forward mode pays one division per
  tangent per site. Effects on run time: docs/performance.md, "Fusion barriers".

A value or tangent that is NaN stays NaN: the runtime 1.0 is NaN exactly where its lane has already
failed, which is also what keeps XLA from folding it to a constant. It must be a per-lane value: a
division by a broadcast scalar is rewritten by XLA into a multiplication, and every barrier
vanishes.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


def runtime_one(x):
    """1.0 where ``x`` is a number, NaN where it is NaN: a 1.0 XLA cannot fold (see module doc)."""
    return jnp.where(jnp.isnan(x), jnp.nan, 1.0)


def stored_once(y: tuple, one) -> tuple:
    """``y`` unchanged (``one`` is :func:`runtime_one` of the state), computed once and stored.

    A stage input of an explicit RK step feeds its own right-hand side and every later stage; fused,
    the later stages recomputed the earlier ones. ``lax.optimization_barrier`` does not prevent this
    on CPU (XLA removes it before fusion). The compiled step holds fewer arithmetic ops with it
    (docs/performance.md, "Fusion barriers").
    """
    return tuple(c / one for c in y)


@jax.custom_jvp
def derivative_stored_once(x, one):
    """``x`` itself; its tangent (and so, under reverse mode, its cotangent) is computed once.

    ``one`` is :func:`runtime_one` of a value the caller's kernels already hold (a state component),
    not of ``x``: the kernel that divides the cotangent would otherwise recompute ``x`` only to test
    it for NaN.
    """
    return x


@derivative_stored_once.defjvp
def _derivative_stored_once_jvp(primals, tangents):
    (x, one), (t, _) = primals, tangents
    return x, t / one
