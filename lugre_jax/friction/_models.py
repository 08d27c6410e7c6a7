"""Friction models of Li et al., "Study on the Low Velocity Stability of a Prostate Seed Implantation
Robot's Rotatory Joint", Electronics 2020, 9, 284, section 4.1: the LuGre model (eq. 9), its steady
state, the Stribeck curve (eq. 10), the high-velocity form (eq. 11), and the segmented (piecewise)
parameterisation of Table 1.

Units everywhere: velocity in deg/s, bristle deflection ``z`` and angle in deg, torque in N*m,
``sigma0`` in N*m/deg, ``sigma1`` and ``sigma2`` in N*m*s/deg, ``vs`` in deg/s.

Design: an abstract base and final concrete classes (the equinox "abstract-or-final" pattern: the
base's concrete methods are never overridden). Every model exposes the same functions so the simulator
does not care which it holds:

* ``steady_state(v)``: friction torque after sliding at constant ``v`` for a long time;
* ``torque_and_derivative(z, v)``: friction torque and ``dz/dt`` of the internal state (zero for
  static models) in one evaluation, the simulator's hot path;
* ``torque(z, v)`` and ``derivative(z, v)``: either half of it, for readers of one quantity.

Why one combined evaluation: the torque and ``dz/dt`` share the Stribeck function and its
exponential. Evaluated separately, XLA's CPU fusion computes that shared part once per consumer.
Divisions by parameters are written as multiplications by their reciprocal: the reciprocal is
loop-invariant, so XLA hoists it out of the time loop, and a float64 division costs several
multiplications (docs/performance.md).
"""

from __future__ import annotations

import abc
import dataclasses
import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._fusion import derivative_stored_once, runtime_one
from .._params import NONNEGATIVE, check_domains, concrete, describe_value, param
from .._types import Array, ArrayLike, Float

_TINY = 1e-12


def stribeck_g(v, Fc, Fs, vs, delta=2.0):
    """Stribeck function ``g(v) = Fc + (Fs - Fc)*exp(-|v/vs|^delta)`` [torque], eq. (10): the
    sliding friction's magnitude, ``Fs`` at rest and ``Fc`` at speed. Safe and differentiable at
    ``v = 0``; ``vs = 0`` gives ``Fc`` for every ``v != 0``.

    ``delta`` as a Python number is a compile-time constant (``delta = 2``, the paper's, is ``x*x``);
    as an array it is a differentiable leaf. Unit-agnostic: ``v`` and ``vs`` in one velocity unit,
    ``Fc`` and ``Fs`` in one force or torque unit.
    """
    # |v|*(1/vs): the reciprocal of a parameter is hoisted out of the time loop (see module doc).
    x = jnp.abs(v) * (1.0 / jnp.maximum(vs, _TINY))
    if isinstance(delta, (int, float)):
        # A static exponent: the general exp(delta*log x) costs a log and an exp per evaluation and
        # blocks XLA's vectorisation of the whole fused right-hand side.
        xd = x * x if delta == 2 else x**delta
    else:
        # Traced exponent (e.g. fitted): guard 0**delta, whose d/d(delta) would be 0*log(0).
        positive = x > 0
        xd = jnp.where(positive, jnp.exp(delta * jnp.log(jnp.where(positive, x, 1.0))), 0.0)
    return Fc + (Fs - Fc) * jnp.exp(-xd)


def stribeck_curve(v, Fc, Fs, vs, sigma2=0.0, delta=2.0):
    """Steady-state friction ``F(v) = sign(v)*g(v) + sigma2*v``, eq. (10) (eq. 11 with ``Fs = Fc``):
    the torque after sliding at constant ``v`` for a long time, for :class:`Stribeck` and
    :class:`LuGre` alike. ``g`` is :func:`stribeck_g`."""
    v = jnp.asarray(v)
    return jnp.sign(v) * stribeck_g(v, Fc, Fs, vs, delta) + sigma2 * v


def bristle_coefficients(dpath, g, sigma0):
    """``(decay, gain)`` of the exact bristle update ``z+ = decay*z + gain`` over a path increment.

    With the velocity's sign and ``g`` held over the step, ``dz/dt = v - sigma0*|v|*z/g`` is linear
    in ``z`` along the path ``s`` (``dz/ds = 1 - sigma0*sign(ds)*z/g``) and is solved exactly:
    ``decay = exp(-x)``, ``gain = dpath*phi1(x)`` with ``x = sigma0*|dpath|/g`` and
    ``phi1(x) = (1 - exp(-x))/x``. Stable for any step (``x`` is the stiffness times the step, as
    large as the sampling makes it), exact for piecewise-constant velocity, differentiable in every
    argument. ``dpath`` is the displacement over the step (``v*h``), in ``z``'s unit.
    """
    decay, phi, _, _ = exp_phi1(sigma0 * jnp.abs(dpath) / g)
    return decay, dpath * phi


def exp_phi1(x):
    """``(exp(-x), phi1(x), small, xs)`` for ``x >= 0``, from one ``expm1``: ``phi1(x) = (1 -
    exp(-x))/x``, its series ``1 - x/2`` where ``x`` is 1e-8 or less (``small`` is False there;
    ``xs`` is ``x`` with those replaced by 1, so no branch divides by zero, gradients included).
    The exact bristle update of every stepping and of diagnose's inverse model."""
    small = x > 1e-8
    xs = jnp.where(small, x, 1.0)
    em1 = jnp.expm1(-xs)
    return (jnp.where(small, 1.0 + em1, 1.0 - x), jnp.where(small, -em1 / xs, 1.0 - 0.5 * x),
            small, xs)


def bristle_step(z, dpath, g, sigma0):
    """``(z_next, z_mean)``: the bristle deflection after the path increment ``dpath`` and its mean
    over the step (the friction's ``sigma0*z`` averaged over a sample), by the exact update of
    :func:`bristle_coefficients`. ``z_mean = z*phi1 + dpath*(1 - phi1)/x``, ``z + dpath/2`` as
    ``x -> 0``."""
    decay, phi, small, xs = exp_phi1(sigma0 * jnp.abs(dpath) / g)
    z_next = decay * z + dpath * phi
    z_mean = jnp.where(small, z * phi + dpath * (1.0 - phi) / xs, z + 0.5 * dpath)
    return z_next, z_mean


def bristle_force(z, v, g, sigma0, sigma1):
    """LuGre's bristle part, eq. (9): ``(sigma0*z + sigma1*dz/dt, dz/dt)`` with
    ``dz/dt = v - sigma0*|v|*z/g`` for the Stribeck level ``g``; add the viscous term for the friction.
    ``|v|*z``, never ``v/|v|``: the latter is 0/0 at rest."""
    dz = v - sigma0 * jnp.abs(v) * z / g
    return sigma0 * z + sigma1 * dz, dz


class AbstractFrictionModel(eqx.Module):
    """A friction law in the paper's units (deg/s in, N*m out).

    Concrete parameter values are checked when a model is built: each must lie in its declared
    domain (no negative friction, stiffness or damping), else ``ValueError`` names it, e.g.
    ``LuGre(sigma1=-5.0): sigma1 must be >= 0 [N*m*s/deg]``. Traced values (under ``jit``,
    ``vmap``, ``grad``) are not checked; batched concrete values are checked element by element.
    """

    def __check_init__(self):
        check_domains(self)

    @abc.abstractmethod
    def steady_state(self, v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """Friction torque [N*m] when sliding at constant velocity ``v`` [deg/s]."""

    @abc.abstractmethod
    def torque_and_derivative(
        self, z: Float[ArrayLike, "*b"], v: Float[ArrayLike, "*b"]
    ) -> tuple[Float[Array, "*b"], Float[Array, "*b"]]:
        """``(torque [N*m], dz/dt [deg/s])`` for state ``z`` [deg] and velocity ``v`` [deg/s].

        The torque opposes motion; ``dz/dt`` is zero for static models.
        """

    def derivative(self, z: Float[ArrayLike, "*b"], v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """Rate of the internal state ``dz/dt`` [deg/s] (zero for static models)."""
        return self.torque_and_derivative(z, v)[1]

    def torque(self, z: Float[ArrayLike, "*b"], v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """Friction torque [N*m] opposing motion, for state ``z`` [deg] and velocity ``v`` [deg/s]."""
        return self.torque_and_derivative(z, v)[0]

    @abc.abstractmethod
    def bristle_damping(self, v: Float[ArrayLike, "*b"]) -> Float[Array, "*b"]:
        """dF/d(dz/dt) [N*m*s/deg]: sigma1 for LuGre, 0 for static models (used by observers)."""


class CoulombViscous(AbstractFrictionModel):
    """F(v) = Fc*sign(v) + sigma2*v: the classical model, eq. (11) with a sign."""

    Fc: Float[Array, "*b"] = param("N*m", 0.0, 10.0, domain=NONNEGATIVE)
    sigma2: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 10.0, domain=NONNEGATIVE)

    def steady_state(self, v):
        v = jnp.asarray(v)
        return self.Fc * jnp.sign(v) + self.sigma2 * v

    def torque_and_derivative(self, z, v):
        f = self.steady_state(v)
        return f, jnp.zeros_like(f)

    def bristle_damping(self, v):
        return jnp.zeros_like(jnp.asarray(v) * self.Fc)


class Stribeck(AbstractFrictionModel):
    """Static Stribeck curve, eq. (10): F(v) = sign(v)*g(v) + sigma2*v.

    ``g(v) = Fc + (Fs - Fc)*exp(-|v/vs|^delta)``; the paper uses ``delta = 2``. With ``Fs == Fc`` it
    is the high-velocity form, eq. (11). Identification bounds are the paper's (section 4.2.2):
    Fc, Fs, sigma2 in [0, 10] and vs in [0, 1].
    ``delta`` is not one of the four identified parameters: a Python number is a compile-time
    constant (fast), an array is a differentiable leaf (e.g. to fit the Stribeck shape).
    """

    Fc: Float[Array, "*b"] = param("N*m", 0.0, 10.0, domain=NONNEGATIVE)
    Fs: Float[Array, "*b"] = param("N*m", 0.0, 10.0, domain=NONNEGATIVE)
    vs: Float[Array, "*b"] = param("deg/s", 0.0, 1.0, domain=NONNEGATIVE)
    sigma2: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 10.0, domain=NONNEGATIVE)
    delta: float | Float[Array, "*b"] = 2.0

    def g(self, v):
        """Stribeck function g(v) [N*m] (positive)."""
        return stribeck_g(v, self.Fc, self.Fs, self.vs, self.delta)

    def steady_state(self, v):
        return stribeck_curve(v, self.Fc, self.Fs, self.vs, self.sigma2, self.delta)

    def torque_and_derivative(self, z, v):
        f = self.steady_state(v)
        return f, jnp.zeros_like(f)

    def bristle_damping(self, v):
        return jnp.zeros_like(jnp.asarray(v) * self.Fc)


class NonPassiveWarning(UserWarning):
    """A concrete :class:`LuGre` set that does not meet the passivity condition (built anyway)."""


class LuGre(AbstractFrictionModel):
    """LuGre dynamic friction, eq. (9).

    ``dz/dt = v - sigma0*|v|*z/g(v)`` and ``F = sigma0*z + sigma1*dz/dt + sigma2*v`` with the Stribeck
    ``g`` above. Its steady state at constant ``v`` is the Stribeck curve (eq. 10); under a small
    torque it behaves as a spring of stiffness ``sigma0`` (pre-sliding, eq. 17).

    Passivity. ``LuGre(..., require_passive=True)`` built from concrete values must be passive (the
    map ``v -> F`` dissipates energy): ``sigma2*min(Fc, Fs) >= sigma1*|Fs - Fc|``, i.e.
    ``sigma2 >= sigma1*(Fs - Fc)/Fc`` for the usual ``Fs >= Fc``, else ``ValueError`` names
    ``sigma2`` and the least value it needs (cf.
    Barabanov and Ortega, "Necessary and sufficient conditions for passivity of the LuGre friction
    model", IEEE Trans. Automatic Control 45(4):830-832, 2000). Derivation: with the storage
    ``V = sigma0*z^2/2`` and ``w = sigma0*z/g``, ``F*v - dV/dt = |v|*(g*w^2 - sigma1*v*w +
    (sigma1 + sigma2)*|v|)``. On the invariant set ``|z| <= max(Fc, Fs)/sigma0`` this is
    non-negative for every ``v`` exactly when the condition holds: at high speed (``g -> min``) with
    the bristles fully deflected in the direction of motion (``w = max/min``) it is the condition
    itself; at lower speed the quadratic's minimum in ``w`` needs less.

    By default (``require_passive=None``) a concrete non-passive set is built with a
    ``NonPassiveWarning`` that names ``sigma2`` and the least value it needs; ``False`` builds it
    silently, for the sets in use that violate the condition on purpose: the paper's Table 2
    segment 1 (``sigma1*(Fs - Fc)/Fc = 14.0`` against ``sigma2 = 2.98``), eq. (18)'s damping on a
    pronounced Stribeck curve, a fit's intermediate values; the equations are still well defined.
    The sign checks of :class:`AbstractFrictionModel` always apply.
    """

    Fc: Float[Array, "*b"] = param("N*m", 0.0, 10.0, domain=NONNEGATIVE)
    Fs: Float[Array, "*b"] = param("N*m", 0.0, 10.0, domain=NONNEGATIVE)
    vs: Float[Array, "*b"] = param("deg/s", 0.0, 1.0, domain=NONNEGATIVE)
    sigma2: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 10.0, domain=NONNEGATIVE)
    sigma0: Float[Array, "*b"] = param("N*m/deg", 0.0, 1.0e4, domain=NONNEGATIVE)
    sigma1: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 100.0, domain=NONNEGATIVE)
    delta: float | Float[Array, "*b"] = 2.0
    require_passive: dataclasses.InitVar[bool | None] = dataclasses.field(default=None, kw_only=True)

    def __post_init__(self, require_passive: bool | None):
        if require_passive is False:
            return
        check_domains(self)  # a wrong sign is reported as such, before the passivity it implies
        vals = [concrete(getattr(self, n)) for n in ("Fc", "Fs", "sigma1", "sigma2")]
        if any(x is None for x in vals):
            return  # traced: the check belongs to whoever builds the concrete set
        Fc, Fs, s1, s2 = np.broadcast_arrays(*vals)
        need = s1 * np.abs(Fs - Fc)
        # a relative margin of 1e-12 accepts a set that meets the condition with equality
        bad = s2 * np.minimum(Fc, Fs) < need * (1.0 - 1e-12)
        if bad.any():
            i = tuple(int(k) for k in np.argwhere(bad)[0])
            least = need[i] / np.minimum(Fc, Fs)[i] if np.minimum(Fc, Fs)[i] > 0 else np.inf
            msg = (f"LuGre({describe_value('sigma2', s2, bad)}): not passive; sigma2 must be >= "
                   f"sigma1*|Fs - Fc|/min(Fc, Fs) = {least:.6g} [N*m*s/deg] (sigma1={s1[i]:g}, Fc={Fc[i]:g}, "
                   f"Fs={Fs[i]:g})")
            if require_passive:
                raise ValueError(msg)
            warnings.warn(msg + "; require_passive=False builds it silently", NonPassiveWarning, stacklevel=5)

    def g(self, v):
        """Stribeck function g(v) [N*m] (positive)."""
        return stribeck_g(v, self.Fc, self.Fs, self.vs, self.delta)

    def static(self) -> Stribeck:
        """The steady-state (Stribeck) part of this model."""
        return Stribeck(self.Fc, self.Fs, self.vs, self.sigma2, self.delta)

    def steady_state(self, v):
        return self.static().steady_state(v)

    def torque_and_derivative(self, z, v):
        v = jnp.asarray(v)
        # g's cotangent is read by every parameter's and the state's adjoint: computed once under
        # reverse mode (see lugre_jax._fusion); the value itself is unchanged.
        g = derivative_stored_once(self.g(v), runtime_one(v))
        f, dz = bristle_force(z, v, g, self.sigma0, self.sigma1)
        return f + self.sigma2 * v, dz

    def bristle_damping(self, v):
        return jnp.zeros_like(jnp.asarray(v)) + self.sigma1


class Segmented(AbstractFrictionModel):
    """Several parameter sets of one model class over velocity ranges (Table 1, section 4.2.2).

    The state ``z`` is the bristle deflection in segment-1 units (segments share the bristle force
    ``sigma0*z``; see ``_scales``). ``segments[k]`` applies for ``edges[k-1] <= |v| < edges[k]`` (``edges`` ascending, one fewer than
    segments, in deg/s). The paper's boundaries are the velocity of minimum torque (~0.05 deg/s) and
    the critical Stribeck velocity (~1.2 deg/s). Segments are blended smoothly over a band of
    relative half-width ``blend`` (default 10%) around each edge (see ``_pick``).
    """

    segments: tuple[AbstractFrictionModel, ...]
    edges: Float[Array, " nseg-1"] = eqx.field(converter=jnp.asarray)
    blend: float = eqx.field(static=True, default=0.1)

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

    def _scales(self):
        # Segments share the bristle *force* sigma0*z, not the deflection z: when sigma0 changes at
        # an edge (Table 2: 111 -> 29.9 N*m/deg at 0.05 deg/s) a shared deflection would make the
        # friction torque jump by ~1 N*m, an artefact no real joint shows and a discontinuity that
        # stalls stiff solvers. The state is the deflection in segment-1 units:
        # z_k = z * sigma0_1 / sigma0_k. Returns (c_k, 1/c_k) with c_k = sigma0_k / sigma0_1.
        s0 = [getattr(m, "sigma0", None) for m in self.segments]
        if s0[0] is None or any(x is None for x in s0):
            return [(1.0, 1.0)] * len(self.segments)
        return [(x / s0[0], s0[0] / x) for x in s0]

    def _pick(self, v, fn):
        # Neighbouring segments are blended with a C1 smoothstep over |v| in
        # [edge*(1-blend), edge*(1+blend)]. A hard switch makes the vector field discontinuous in
        # velocity (sigma1 and sigma0 jump at the edges), and a stick-slip trajectory can then slide
        # along |v| = edge, a Filippov sliding mode that stalls adaptive solvers (Radau and Kvaerno5
        # give up at v = 0.05 deg/s). blend = 0 restores the hard switch.
        # ``fn(segment, (c, 1/c))`` may return a pytree (torque and dz/dt blend in one pass).
        a = jnp.abs(jnp.asarray(v))
        scales = self._scales()
        out = fn(self.segments[0], scales[0])
        for k in range(1, len(self.segments)):
            e = self.edges[..., k - 1]
            nxt = fn(self.segments[k], scales[k])
            if self.blend > 0:
                x = jnp.clip((a - e * (1 - self.blend)) * (1.0 / (2 * self.blend * e)), 0.0, 1.0)
                w = x * x * (3 - 2 * x)
                out = jax.tree.map(lambda o, n: o + w * (n - o), out, nxt)
            else:
                out = jax.tree.map(lambda o, n: jnp.where(a < e, o, n), out, nxt)
        return out

    def steady_state(self, v):
        return self._pick(v, lambda m, c: m.steady_state(v))

    def torque_and_derivative(self, z, v):
        def one(m, c):
            f, dz = m.torque_and_derivative(z * c[1], v)
            return f, c[0] * dz

        return self._pick(v, one)

    def bristle_damping(self, v):
        # dF/d(dz/dt) in segment-1 units of z.
        return self._pick(v, lambda m, c: m.bristle_damping(v) * c[1])
