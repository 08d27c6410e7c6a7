"""Friction models of Li et al., "Study on the Low Velocity Stability of a Prostate Seed Implantation
Robot's Rotatory Joint", Electronics 2020, 9, 284, section 4.1: the LuGre model (eq. 9), its steady
state, the Stribeck curve (eq. 10), the high-velocity form (eq. 11), and the segmented (piecewise)
parameterisation of Table 1.

Units everywhere: velocity in deg/s, bristle deflection ``z`` and angle in deg, torque in N*m,
``sigma0`` in N*m/deg, ``sigma1`` and ``sigma2`` in N*m*s/deg, ``vs`` in deg/s.

Design: an abstract base with abstract methods only, and final concrete classes (the equinox
"abstract-or-final" pattern). Every model exposes the same three functions so the simulator does not
care which it holds:

* ``steady_state(v)``: friction torque after sliding at constant ``v`` for a long time;
* ``derivative(z, v)``: ``dz/dt`` of the internal state (zero for static models);
* ``torque(z, v)``: friction torque for state ``z`` and velocity ``v``.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp

from .._params import param
from .._types import Array, ArrayLike, Float

_TINY = 1e-12


def _stribeck_g(v, Fc, Fs, vs, delta):
    """g(v) = Fc + (Fs - Fc) * exp(-|v/vs|^delta), safe (and differentiable) at v = 0."""
    x = jnp.abs(v) / jnp.maximum(vs, _TINY)
    # x**delta written through exp/log with a guard: d/d(delta) of 0**delta would otherwise be 0*log(0).
    positive = x > 0
    xd = jnp.where(positive, jnp.exp(delta * jnp.log(jnp.where(positive, x, 1.0))), 0.0)
    return Fc + (Fs - Fc) * jnp.exp(-xd)


class AbstractFrictionModel(eqx.Module):
    """A friction law in the paper's units (deg/s in, N*m out)."""

    @abc.abstractmethod
    def steady_state(self, v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """Friction torque [N*m] when sliding at constant velocity ``v`` [deg/s]."""

    @abc.abstractmethod
    def derivative(self, z: Float[ArrayLike, "*b"], v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """Rate of the internal state ``dz/dt`` [deg/s] (zero for static models)."""

    @abc.abstractmethod
    def torque(self, z: Float[ArrayLike, "*b"], v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """Friction torque [N*m] opposing motion, for state ``z`` [deg] and velocity ``v`` [deg/s]."""


class CoulombViscous(AbstractFrictionModel):
    """F(v) = Fc*sign(v) + sigma2*v: the classical model, eq. (11) with a sign."""

    Fc: Float[Array, "*b"] = param("N*m", 0.0, 10.0)
    sigma2: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 10.0)

    def steady_state(self, v):
        v = jnp.asarray(v)
        return self.Fc * jnp.sign(v) + self.sigma2 * v

    def derivative(self, z, v):
        return jnp.zeros_like(jnp.asarray(v) * self.Fc)

    def torque(self, z, v):
        return self.steady_state(v)


class Stribeck(AbstractFrictionModel):
    """Static Stribeck curve, eq. (10): F(v) = sign(v)*g(v) + sigma2*v.

    ``g(v) = Fc + (Fs - Fc)*exp(-|v/vs|^delta)``; the paper uses ``delta = 2``. With ``Fs == Fc`` it
    is the high-velocity form, eq. (11). Identification bounds are the paper's (section 4.2.2):
    Fc, Fs, sigma2 in [0, 10] and vs in [0, 1].
    ``delta`` is a differentiable leaf but not one of the four identified parameters.
    """

    Fc: Float[Array, "*b"] = param("N*m", 0.0, 10.0)
    Fs: Float[Array, "*b"] = param("N*m", 0.0, 10.0)
    vs: Float[Array, "*b"] = param("deg/s", 0.0, 1.0)
    sigma2: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 10.0)
    delta: Float[Array, "*b"] = eqx.field(converter=jnp.asarray, default=2.0)

    def g(self, v):
        """Stribeck function g(v) [N*m] (positive)."""
        return _stribeck_g(v, self.Fc, self.Fs, self.vs, self.delta)

    def steady_state(self, v):
        v = jnp.asarray(v)
        return jnp.sign(v) * self.g(v) + self.sigma2 * v

    def derivative(self, z, v):
        return jnp.zeros_like(jnp.asarray(v) * self.Fc)

    def torque(self, z, v):
        return self.steady_state(v)


class LuGre(AbstractFrictionModel):
    """LuGre dynamic friction, eq. (9).

    ``dz/dt = v - sigma0*|v|*z/g(v)`` and ``F = sigma0*z + sigma1*dz/dt + sigma2*v`` with the Stribeck
    ``g`` above. Its steady state at constant ``v`` is the Stribeck curve (eq. 10); under a small
    torque it behaves as a spring of stiffness ``sigma0`` (pre-sliding, eq. 17).
    """

    Fc: Float[Array, "*b"] = param("N*m", 0.0, 10.0)
    Fs: Float[Array, "*b"] = param("N*m", 0.0, 10.0)
    vs: Float[Array, "*b"] = param("deg/s", 0.0, 1.0)
    sigma2: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 10.0)
    sigma0: Float[Array, "*b"] = param("N*m/deg", 0.0, 1.0e4)
    sigma1: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 100.0)
    delta: Float[Array, "*b"] = eqx.field(converter=jnp.asarray, default=2.0)

    def g(self, v):
        """Stribeck function g(v) [N*m] (positive)."""
        return _stribeck_g(v, self.Fc, self.Fs, self.vs, self.delta)

    def static(self) -> Stribeck:
        """The steady-state (Stribeck) part of this model."""
        return Stribeck(self.Fc, self.Fs, self.vs, self.sigma2, self.delta)

    def steady_state(self, v):
        v = jnp.asarray(v)
        return jnp.sign(v) * self.g(v) + self.sigma2 * v

    def derivative(self, z, v):
        # |v|*z, never v/|v|: the latter is 0/0 at rest.
        return v - self.sigma0 * jnp.abs(v) * z / self.g(v)

    def torque(self, z, v):
        return self.sigma0 * z + self.sigma1 * self.derivative(z, v) + self.sigma2 * v


class Segmented(AbstractFrictionModel):
    """Several parameter sets of one model class over velocity ranges (Table 1, section 4.2.2).

    ``segments[k]`` applies for ``edges[k-1] <= |v| < edges[k]`` (``edges`` ascending, one fewer than
    segments, in deg/s). The paper's boundaries are the velocity of minimum torque (~0.05 deg/s) and
    the critical Stribeck velocity (~1.2 deg/s).
    """

    segments: tuple[AbstractFrictionModel, ...]
    edges: Float[Array, " nseg-1"] = eqx.field(converter=jnp.asarray)

    def __check_init__(self):
        if len(self.segments) < 1:
            raise ValueError("Segmented needs at least one segment")
        if self.edges.shape[-1:] != (len(self.segments) - 1,) and not (
            len(self.segments) == 1 and self.edges.size == 0
        ):
            raise ValueError(
                f"Segmented with {len(self.segments)} segments needs {len(self.segments) - 1} edges, "
                f"got edges of shape {self.edges.shape}"
            )

    def _pick(self, v, fn):
        # A where-chain rather than a gather: cheaper under vmap for the 2-4 segments used in practice.
        a = jnp.abs(jnp.asarray(v))
        out = fn(self.segments[-1])
        for k in range(len(self.segments) - 2, -1, -1):
            out = jnp.where(a < self.edges[..., k], fn(self.segments[k]), out)
        return out

    def steady_state(self, v):
        return self._pick(v, lambda m: m.steady_state(v))

    def derivative(self, z, v):
        return self._pick(v, lambda m: m.derivative(z, v))

    def torque(self, z, v):
        return self._pick(v, lambda m: m.torque(z, v))
