"""Reference signals of the paper's experiments (sections 5-6), and user tables.

Each reference returns ``(theta_ref [deg], v_ref [deg/s], a_ref [deg/s^2])`` at time ``t`` [s], with
the position the exact integral of the velocity, so position and velocity loops never disagree,
and declares the times where it is not smooth (:meth:`AbstractReference.jump_times`) so that the
simulator can step onto them.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._types import Array, Float


class AbstractReference(eqx.Module):
    """A commanded motion: ``ref(t) -> (theta_ref [deg], v_ref [deg/s], a_ref [deg/s^2])``."""

    @abc.abstractmethod
    def __call__(self, t) -> tuple[Array, Array, Array]:
        ...

    @abc.abstractmethod
    def jump_times(self) -> Float[Array, " k"]:
        """Times [s] where the velocity or the acceleration command jumps (``+inf`` entries are
        placeholders for "none"): an error-controlled solver steps exactly onto them."""


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

    def jump_times(self):
        k = jnp.arange(self.levels.shape[-1])
        return jnp.where(k == 0, self.t0, self.t0 + k * jnp.minimum(self.dwell_s, 1e30))


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

    def jump_times(self):
        return jnp.atleast_1d(self.ramp_s)


class PositionSine(AbstractReference):
    """Position sine ``amplitude_deg*sin(2*pi*frequency_hz*t)`` (Figs. 9, 10, 15: 3*sin(0.8*pi*t))."""

    amplitude_deg: Float[Array, ""] = eqx.field(converter=jnp.asarray)
    frequency_hz: Float[Array, ""] = eqx.field(converter=jnp.asarray)

    def __call__(self, t):
        w = 2 * jnp.pi * self.frequency_hz
        A = self.amplitude_deg
        return A * jnp.sin(w * t), A * w * jnp.cos(w * t), -A * w**2 * jnp.sin(w * t)

    def jump_times(self):
        return jnp.zeros((0,))


class VelocityTable(AbstractReference):
    """A user's velocity table: piecewise linear through ``(times_s[k], velocities_deg_s[k])``, held
    at the first value from ``t = 0`` to ``times_s[0]`` and at the last after ``times_s[-1]``.

    ``times_s`` must be non-decreasing; a repeated time is a velocity step (the later value holds
    from that time on). Position is the exact integral from ``t = 0``.
    """

    times_s: Float[Array, " m"] = eqx.field(converter=lambda x: jnp.atleast_1d(jnp.asarray(x, float)))
    velocities_deg_s: Float[Array, " m"] = eqx.field(converter=lambda x: jnp.atleast_1d(jnp.asarray(x, float)))

    def __check_init__(self):
        if isinstance(self.times_s, jax.core.Tracer) or isinstance(self.velocities_deg_s, jax.core.Tracer):
            return  # built inside a transformation: checked where it was built concretely
        t, v = np.asarray(self.times_s), np.asarray(self.velocities_deg_s)
        if t.shape[-1:] != v.shape[-1:] or t.shape[-1] < 1:
            raise ValueError(f"VelocityTable: times_s and velocities_deg_s need the same length >= 1, got "
                             f"{t.shape[-1:]} and {v.shape[-1:]}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
            raise ValueError("VelocityTable: times and velocities must be finite")
        if np.any(np.diff(t, axis=-1) < 0) or np.any(t < 0):
            raise ValueError("VelocityTable: times_s must be >= 0 and non-decreasing")

    def __call__(self, t):
        ts, vs = self.times_s, self.velocities_deg_s
        a, b, va, vb = ts[..., :-1], ts[..., 1:], vs[..., :-1], vs[..., 1:]
        width = b - a
        safe = jnp.where(width > 0, width, 1.0)
        slope = jnp.where(width > 0, (vb - va) / safe, 0.0)
        u = jnp.clip(t, a, b)
        # Sums over segments (no per-lane gather: see VelocitySteps).
        inside = (t >= a) & (t < b) & (width > 0)
        v_in = jnp.sum(jnp.where(inside, va + slope * (t - a), 0.0))
        acc = jnp.sum(jnp.where(inside, slope, 0.0))
        before, after = t < ts[..., 0], t >= ts[..., -1]
        v = jnp.where(before, vs[..., 0], jnp.where(after, vs[..., -1], v_in))
        theta = (vs[..., 0] * jnp.clip(t, 0.0, ts[..., 0])
                 + jnp.sum(jnp.where(width > 0, (u - a) * (va + 0.5 * slope * (u - a)), 0.0))
                 + vs[..., -1] * jnp.maximum(t - ts[..., -1], 0.0))
        return theta, v, jnp.where(before | after, 0.0, acc)

    def jump_times(self):
        return self.times_s
