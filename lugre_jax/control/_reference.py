"""Reference signals of the paper's experiments (sections 5-6).

Each reference returns ``(theta_ref [deg], v_ref [deg/s], a_ref [deg/s^2])`` at time ``t`` [s], with
the position the exact integral of the velocity, so position and velocity loops never disagree.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._types import Array, Float


class AbstractReference(eqx.Module):
    """A commanded motion: ``ref(t) -> (theta_ref [deg], v_ref [deg/s], a_ref [deg/s^2])``."""

    @abc.abstractmethod
    def __call__(self, t) -> tuple[Array, Array, Array]:
        ...


class VelocitySteps(AbstractReference):
    """Piecewise-constant velocity command: ``levels[k]`` [deg/s] for ``t0 + k*dwell_s <= t``.

    The last level holds until the end. A single level with ``t0 = 0`` is the paper's velocity step
    (e.g. 0.005 deg/s); several levels make a staircase.
    """

    levels: Float[Array, " n"] = eqx.field(converter=lambda x: jnp.atleast_1d(jnp.asarray(x, float)))
    dwell_s: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=np.inf)
    t0: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.0)

    def __call__(self, t):
        n = self.levels.shape[-1]
        tau = jnp.maximum(t - self.t0, 0.0)
        started = t >= self.t0
        if n == 1:
            # The paper's single step: no level index to find (static shape), so no gather.
            v = jnp.where(started, self.levels[..., 0], 0.0)
            return jnp.where(started, self.levels[..., 0] * tau, 0.0), v, jnp.zeros_like(v)
        dwell = jnp.minimum(self.dwell_s, 1e30)
        k = jnp.clip(jnp.floor(tau / dwell), 0, n - 1)
        # One-hot select rather than levels[k]: under vmap an index per lane becomes a gather,
        # which XLA cannot fuse or vectorise with the rest of the right-hand side.
        idx = jnp.arange(n)
        v_k = jnp.sum(jnp.where(idx == k, self.levels, 0.0))
        v = jnp.where(started, v_k, 0.0)
        # Position: full dwells of earlier levels plus the part of the current one.
        full = jnp.sum(jnp.where(idx < k, self.levels, 0.0)) * dwell
        theta = jnp.where(started, full + v_k * (tau - k * dwell), 0.0)
        return theta, v, jnp.zeros_like(v)


class VelocityRamp(AbstractReference):
    """Velocity ramp from 0 to ``v_final`` [deg/s] over ``ramp_s`` [s], then constant (Fig. 12: 0 -> 1.5 in 4 s)."""

    v_final: Float[Array, ""] = eqx.field(converter=jnp.asarray)
    ramp_s: Float[Array, ""] = eqx.field(converter=jnp.asarray)

    def __call__(self, t):
        rate = self.v_final / self.ramp_s
        tr = jnp.clip(t, 0.0, self.ramp_s)
        v = rate * tr
        theta = 0.5 * rate * tr**2 + self.v_final * jnp.maximum(t - self.ramp_s, 0.0)
        a = jnp.where((t >= 0) & (t < self.ramp_s), rate, 0.0)
        return theta, v, a


class PositionSine(AbstractReference):
    """Position sine ``amplitude_deg*sin(2*pi*frequency_hz*t)`` (Figs. 9, 10, 15: 3*sin(0.8*pi*t))."""

    amplitude_deg: Float[Array, ""] = eqx.field(converter=jnp.asarray)
    frequency_hz: Float[Array, ""] = eqx.field(converter=jnp.asarray)

    def __call__(self, t):
        w = 2 * jnp.pi * self.frequency_hz
        A = self.amplitude_deg
        return A * jnp.sin(w * t), A * w * jnp.cos(w * t), -A * w**2 * jnp.sin(w * t)
