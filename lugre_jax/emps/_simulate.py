"""EMPS as a sampled-data system: a continuous mass with friction under a discrete 1 kHz controller.

At sample ``k`` the drive reads ``qm[k]``, estimates the velocity with its 2-tap filter
``dqm[k] = (qm[k] - qm[k-2])/(2*T)`` (the benchmark's ``filterq1 = [0.5 0.5]`` on the backward
difference), outputs ``vir[k] = sat_10V(kp*kv*(qg[k] - qm[k]) - kv*dqm[k])`` and holds it over
``[t_k, t_k+1)`` (zero-order hold). On the recording this law reproduces the logged ``vir`` with no
extra delay; one sample of delay fits it worse (docs/emps.md).

The plant is integrated within each sample by ``substeps`` steps of a :class:`Stepping` choice:

* :class:`RungeKutta`: any explicit diffrax solver (default ``Tsit5``) on ``(q, v, z)``;
* :class:`ExponentialMidpoint`: the bristle state advanced by its exact exponential with ``v``
  frozen over the substep (:func:`lugre_jax.friction.bristle_step`) (stable however stiff LuGre's ``sigma0*|v|/g`` is), the mass by an
  explicit midpoint step with the substep-mean friction force; the default for models with state.

Both loops are ``lax.scan`` over samples: differentiable (forward and reverse), vmappable over
parameter sets and initial states. Every function returns its trajectories and ``ok`` (all finite);
callers turn a non-finite run into a failure, never a silent NaN.
"""

from __future__ import annotations

import abc

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp

from ..friction import bristle_force, bristle_step
from ._models import AbstractEmpsModel

VIR_MAX = 10.0  # V, the drive's saturation


class AbstractSubstepping(eqx.Module):
    substeps: eqx.AbstractVar[int]

    @abc.abstractmethod
    def advance(self, model: AbstractEmpsModel, x, u, T):
        """State ``x = (q, v, z)`` at ``t + T`` under the constant force ``u`` [N]."""


def _rhs(model: AbstractEmpsModel, x, u):
    q, v, z = x
    if not model.has_state:
        F, dz = model.friction(q, v, z), jnp.zeros_like(z)
    else:
        s0, s1, g, other = model.bristle_terms(q, v)
        fb, dz = bristle_force(z, v, g, s0, s1)
        F = fb + other
    return jnp.stack([v, (u - F) * (1.0 / model.M), dz])


class RungeKutta(AbstractSubstepping):
    """``substeps`` steps of an explicit diffrax solver per sample."""

    solver: diffrax.AbstractSolver = diffrax.Tsit5()
    # 10 substeps of 1e-4 s: the smooth Coulomb sign is stiff below ~1e-4 m/s and a reversal
    # crosses that band in ~2e-4 s, which fewer substeps step over (agreement with scipy,
    # tests/test_emps.py: docs/emps.md).
    substeps: int = eqx.field(static=True, default=10)

    def advance(self, model, x, u, T):
        term = diffrax.ODETerm(lambda t, y, args: _rhs(model, y, u))
        h = T / self.substeps
        solver = self.solver
        if getattr(solver, "scan_kind", "") is None:
            # diffrax's default stage loop is a checkpointed while loop (custom VJP): it blocks the
            # forward-mode Jacobian the least-squares fits use; "lax" blocks reverse mode. The
            # bounded loop allows both.
            solver = eqx.tree_at(lambda s: s.scan_kind, solver, "bounded", is_leaf=lambda x: x is None)

        def body(i, y):
            t0 = i * h
            # a fresh solver state per substep: the force input changes every sample anyway
            state = solver.init(term, t0, t0 + h, y, None)
            y1, _, _, _, _ = solver.step(term, t0, t0 + h, y, None, state, False)
            return y1

        return jax.lax.fori_loop(0, self.substeps, body, x, unroll=True)


class ExponentialMidpoint(AbstractSubstepping):
    """Exact bristle exponential + explicit-midpoint mass step, ``substeps`` per sample.

    Over a substep of length ``h`` the bristle equation ``dz/dt = v - a*z``, ``a = sigma0*|v|/g(v)``,
    is solved exactly with the velocity frozen at ``v_f`` (stable however large ``a*h`` is); the
    friction force is its substep mean. A predictor with ``v_f = v`` gives the velocity at the
    substep's end; the corrector freezes ``v_f`` at the mean of the two (second order in ``h``
    where the law is smooth). Static laws use the same midpoint step without ``z``.
    """

    substeps: int = eqx.field(static=True, default=10)

    def advance(self, model, x, u, T):
        h = T / self.substeps
        invM = 1.0 / model.M

        def force(q, z, vf):
            if not model.has_state:
                return model.friction(q, vf, z), z
            s0, s1, g, other = model.bristle_terms(q, vf)
            z1, zbar = bristle_step(z, vf * h, g, s0)  # the exact update and the substep mean of z
            F = s0 * zbar + s1 * (z1 - z) * (1.0 / h) + other
            return F, z1

        def body(i, y):
            q, v, z = y[0], y[1], y[2]
            F0, _ = force(q + 0.5 * h * v, z, v)
            vm = v + 0.5 * h * (u - F0) * invM
            F, z1 = force(q + 0.5 * h * vm, z, vm)
            v1 = v + h * (u - F) * invM
            return jnp.stack([q + 0.5 * h * (v + v1), v1, z1])

        return jax.lax.fori_loop(0, self.substeps, body, x, unroll=True)


def default_stepping(model: AbstractEmpsModel) -> AbstractSubstepping:
    return ExponentialMidpoint() if model.has_state else RungeKutta()


def fit_stepping(model: AbstractEmpsModel) -> AbstractSubstepping:
    """The stepping of the output-error fits: for static laws Tsit5 with 2 substeps, whose error
    against the 10-substep default over a free simulation of the whole estimation run is bounded
    in tests/test_emps.py far below the millimetre errors being fitted, at a fraction of the cost;
    laws with state keep their default. Scores use :func:`default_stepping`."""
    return ExponentialMidpoint() if model.has_state else RungeKutta(substeps=2)


def closed_loop(model: AbstractEmpsModel, qg, f_ext, x0, history, *, gtau: float, kp: float,
                kv: float, T: float, stepping: AbstractSubstepping | None = None, u_cmd=None):
    """Simulate the loop driven by the reference ``qg`` (n,) and the external force ``f_ext`` (n,) [N].

    ``u_cmd`` (n,) [V], optional, is added to the controller's output before the saturation (a
    disturbance entering at the command: the returned ``vir`` contains it).
    ``x0 = (q, v, z)`` at sample 0; ``history = (qm[-1], qm[-2])`` for the 2-tap filter.
    Returns ``(q, v, vir, ok)``, each (n,) at the sample instants (state before the hold).
    """
    stepping = default_stepping(model) if stepping is None else stepping
    x0 = jnp.asarray(x0, jnp.float64)
    u_cmd = jnp.zeros_like(jnp.asarray(qg, jnp.float64)) if u_cmd is None else jnp.asarray(u_cmd, jnp.float64)

    def step(carry, inp):
        x, q1, q2 = carry
        qg_k, f_k, u_k = inp
        qk = x[0]
        dqm = (qk - q2) * (1.0 / (2 * T))
        vir = jnp.clip(kp * kv * (qg_k - qk) - kv * dqm + u_k, -VIR_MAX, VIR_MAX)
        xn = stepping.advance(model, x, gtau * vir + f_k, T)
        return (xn, qk, q1), (qk, x[1], vir)

    h1, h2 = history
    _, (q, v, vir) = jax.lax.scan(step, (x0, jnp.asarray(h1, jnp.float64), jnp.asarray(h2, jnp.float64)),
                                  (jnp.asarray(qg), jnp.asarray(f_ext), u_cmd))
    ok = jnp.all(jnp.isfinite(q)) & jnp.all(jnp.isfinite(vir))
    return q, v, vir, ok


def open_loop(model: AbstractEmpsModel, vir, f_ext, x0, *, gtau: float, T: float,
              stepping: AbstractSubstepping | None = None):
    """The benchmark protocol: driven by the recorded ``vir`` (n,) [V] (+ ``f_ext`` [N]) from ``x0``.

    Returns ``(q, v, ok)`` (n,) at the sample instants; ``q[0] = x0[0]``.
    """
    stepping = default_stepping(model) if stepping is None else stepping
    x0 = jnp.asarray(x0, jnp.float64)

    def step(x, inp):
        u_k, f_k = inp
        return stepping.advance(model, x, gtau * u_k + f_k, T), (x[0], x[1])

    _, (q, v) = jax.lax.scan(step, x0, (jnp.asarray(vir), jnp.asarray(f_ext)))
    return q, v, jnp.all(jnp.isfinite(q))
