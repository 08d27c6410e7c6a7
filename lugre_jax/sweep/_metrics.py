"""Per-lane control metrics, in JAX, evaluated on each simulated lane inside the batched call (so a
sweep stores a few numbers per point, not trajectories).

Same definitions as :mod:`lugre_jax.metrics` (NumPy, for finished trajectories; the tests check the
two agree), over the last ``window`` fraction of the record, with the sample's commanded velocity
``v_ref`` as ``v_cmd`` (a step's constant level once the window starts):

* :class:`DeadZone` [s]: mean of ``(theta_ref - theta)/v_ref`` (``metrics.dead_zone_lag``).
* :class:`CreepAmplitude` [deg]: peak-to-peak of the linearly detrended ``theta - theta_ref``.
* :class:`BandFraction` (0..1): fraction of samples with ``|omega - v_ref| <= band``.
* :class:`TrackingError` [deg]: RMS of ``theta_ref - theta``.
* :class:`StickSlip` (0 or 1): 1 if the joint's velocity falls below ``threshold*|v_ref|`` anywhere
  in the window: it sticks (or never starts) instead of sliding smoothly.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp


class AbstractMetric(eqx.Module):
    """``metric(sol) -> scalar`` for one lane's :class:`lugre_jax.Solution`; ``name`` labels outputs."""

    name: str = eqx.field(static=True)
    window: float = eqx.field(static=True, default=0.5)

    def _mask(self, sol):
        t = sol.ts
        return t >= t[-1] * (1.0 - self.window) - 1e-12

    @abc.abstractmethod
    def __call__(self, sol):
        ...

    def to_json(self) -> dict:
        return {"metric": METRIC_KEYS[type(self)], "name": self.name, "window": self.window}


def _wmean(x, m):
    return jnp.sum(jnp.where(m, x, 0.0)) / jnp.sum(m)


class DeadZone(AbstractMetric):
    window: float = eqx.field(static=True, default=0.25)

    def __call__(self, sol):
        m = self._mask(sol)
        v = jnp.where(m, sol.v_ref, 1.0)
        return _wmean((sol.theta_ref - sol.theta) / v, m)


class CreepAmplitude(AbstractMetric):
    def __call__(self, sol):
        m = self._mask(sol)
        e = sol.theta - sol.theta_ref
        tw = sol.ts - _wmean(sol.ts, m)
        slope = jnp.sum(jnp.where(m, tw * e, 0.0)) / jnp.sum(jnp.where(m, tw * tw, 0.0))
        r = e - _wmean(e, m) - slope * tw
        return jnp.max(jnp.where(m, r, -jnp.inf)) - jnp.min(jnp.where(m, r, jnp.inf))


class BandFraction(AbstractMetric):
    band: float = eqx.field(static=True, default=1e-3)

    def __call__(self, sol):
        return _wmean((jnp.abs(sol.omega - sol.v_ref) <= self.band).astype(sol.omega.dtype), self._mask(sol))

    def to_json(self):
        return {**super().to_json(), "band": self.band}


class TrackingError(AbstractMetric):
    def __call__(self, sol):
        return jnp.sqrt(_wmean((sol.theta_ref - sol.theta) ** 2, self._mask(sol)))


class StickSlip(AbstractMetric):
    threshold: float = eqx.field(static=True, default=0.1)

    def __call__(self, sol):
        m = self._mask(sol)
        # omega*sign(v_ref) >= threshold*|v_ref|, written as a product: no division by v_ref.
        slow = sol.omega * sol.v_ref < self.threshold * sol.v_ref**2
        return jnp.any(m & slow).astype(sol.omega.dtype)

    def to_json(self):
        return {**super().to_json(), "threshold": self.threshold}


METRIC_KEYS = {DeadZone: "dead_zone", CreepAmplitude: "creep_amplitude", BandFraction: "band_fraction",
               TrackingError: "tracking_error", StickSlip: "stick_slip"}
METRICS = {v: k for k, v in METRIC_KEYS.items()}
