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
import math

import equinox as eqx
import jax.numpy as jnp


class AbstractMetric(eqx.Module):
    """``metric(sol) -> scalar`` for one lane's :class:`lugre_jax.Solution`; ``name`` labels outputs."""

    name: str = eqx.field(static=True)
    window: float = eqx.field(static=True, default=0.5)

    def _window(self, sol):
        """``(ts, theta, omega, theta_ref, v_ref)`` over the window, sliced with a static start
        (the sample grid ``k/sample_hz`` is fixed): no masked arithmetic on the other samples."""
        n = sol.ts.shape[-1]
        k0 = max(0, min(n - 1, math.ceil((n - 1) * (1.0 - self.window) - 1e-9)))
        return tuple(x[..., k0:] for x in (sol.ts, sol.theta, sol.omega, sol.theta_ref, sol.v_ref))

    @abc.abstractmethod
    def __call__(self, sol):
        ...

    def to_json(self) -> dict:
        return {"metric": METRIC_KEYS[type(self)], "name": self.name, "window": self.window}


class DeadZone(AbstractMetric):
    window: float = eqx.field(static=True, default=0.25)

    def __call__(self, sol):
        _, th, _, ref, v = self._window(sol)
        return jnp.mean((ref - th) / v)


class CreepAmplitude(AbstractMetric):
    def __call__(self, sol):
        t, th, _, ref, _ = self._window(sol)
        e = th - ref
        tw = t - jnp.mean(t)
        r = e - jnp.mean(e) - (jnp.sum(tw * e) / jnp.sum(tw * tw)) * tw
        return jnp.max(r) - jnp.min(r)


class BandFraction(AbstractMetric):
    band: float = eqx.field(static=True, default=1e-3)

    def __call__(self, sol):
        _, _, om, _, v = self._window(sol)
        return jnp.mean((jnp.abs(om - v) <= self.band).astype(om.dtype))

    def to_json(self):
        return {**super().to_json(), "band": self.band}


class TrackingError(AbstractMetric):
    def __call__(self, sol):
        _, th, _, ref, _ = self._window(sol)
        return jnp.sqrt(jnp.mean((ref - th) ** 2))


class StickSlip(AbstractMetric):
    threshold: float = eqx.field(static=True, default=0.1)

    def __call__(self, sol):
        _, _, om, _, v = self._window(sol)
        # omega*sign(v_ref) >= threshold*|v_ref|, written as a product: no division by v_ref.
        return jnp.any(om * v < self.threshold * v**2).astype(om.dtype)

    def to_json(self):
        return {**super().to_json(), "threshold": self.threshold}


METRIC_KEYS = {DeadZone: "dead_zone", CreepAmplitude: "creep_amplitude", BandFraction: "band_fraction",
               TrackingError: "tracking_error", StickSlip: "stick_slip"}
METRICS = {v: k for k, v in METRIC_KEYS.items()}
