"""Global-best particle swarm optimisation, as in Li et al., Electronics 2020, 9, 284, section 4.2.3.

Update (paper step 3, Kennedy & Eberhart with inertia weight)::

    v <- w*v + c1*r1*(p_i - x) + c2*r2*(p_g - x)
    x <- x + v

Paper defaults: 100 particles, w = 0.62, c1 = c2 = 2, 100 iterations, bounds of section 4.2.2.

Bound handling (the paper does not say; this is ours):

* velocity clamp ``|v_j| <= vmax_frac * (upper_j - lower_j)`` (default 0.2). ``w = 0.62`` with
  ``c1 = c2 = 2`` lies outside the usual stability region (Clerc's ``w = 0.7298, c = 1.49618``), so
  without a clamp the swarm diverges;
* position clipped to the box, and the velocity component that pushed it out set to zero (the
  particle stops at the wall instead of pressing on it every iteration).

The swarm is initialised uniformly in the box with velocities uniform in ``[-vmax, vmax]``.
:func:`~._optimiser.minimise` counts the initial swarm as iteration 0, then does ``max_steps``
updates, so the evaluation count is ``n_particles * (max_steps + 1)``.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp

from .._types import Array, Float, Int, Population, PRNGKeyArray, Scalar
from ._fitness import LossFn, best_of, evaluate
from ._optimiser import AbstractOptimiser


class PSOState(eqx.Module):
    """Swarm state; a pytree, so many seeds are a vmap over keys."""

    x: Population
    v: Population
    fx: Float[Array, " pop"]
    pbest: Population
    pbest_f: Float[Array, " pop"]
    best_x: Float[Array, " dim"]
    best_loss: Scalar
    n_evals: Int[Array, ""]
    key: PRNGKeyArray


def _fmix32(x):
    """MurmurHash3's 32-bit finaliser: a cheap bijection with full avalanche."""
    x = x ^ (x >> 16)
    x = x * jnp.uint32(0x85EBCA6B)
    x = x ^ (x >> 13)
    x = x * jnp.uint32(0xC2B2AE35)
    return x ^ (x >> 16)


def hash_uniform(key: PRNGKeyArray, shape: tuple[int, ...]) -> Float[Array, "..."]:
    """Uniform [0, 1) float64 numbers (24 random bits each) from a counter hash seeded by ``key``.

    Two 32-bit words from ``key`` (one threefry call) seed two rounds of the MurmurHash3 finaliser
    over a counter. Not a cryptographic generator; good enough for PSO's acceleration coefficients,
    and far cheaper than one threefry draw per number, which dominates PSO's own cost when the loss
    is cheap (docs/identification.md, "Speed of the PSO").
    """
    seed = jax.random.bits(key, (2,), dtype=jnp.uint32)
    n = 1
    for d in shape:
        n *= d
    x = jax.lax.iota(jnp.uint32, n).reshape(shape)
    x = _fmix32(_fmix32(x ^ seed[0]) ^ seed[1])
    return (x >> 8).astype(jnp.float64) * (1.0 / (1 << 24))


def _move_one(x, v, p, g, r1, r2, w, c1, c2, vmax, lower, upper):
    """One particle's velocity and position update, with the clamp and the wall rule above.

    ``r1``, ``r2`` are the particle's uniform draws (drawn for the whole swarm at once: one PRNG
    call per iteration is much cheaper than a key split per particle).
    """
    v = w * v + c1 * r1 * (p - x) + c2 * r2 * (g - x)
    v = jnp.clip(v, -vmax, vmax)
    x_new = x + v
    outside = (x_new < lower) | (x_new > upper)
    return jnp.clip(x_new, lower, upper), jnp.where(outside, 0.0, v)


class PSO(AbstractOptimiser):
    """Global-best PSO with the paper's settings as defaults (section 4.2.3).

    ``w``, ``c1``, ``c2`` and ``vmax_frac`` are array leaves: vmap over a stacked ``PSO`` to sweep
    them. ``n_particles`` and ``max_steps`` (the number of iterations) are static. ``rng="hash"`` draws ``r1, r2`` with
    :func:`hash_uniform` instead of ``jax.random.uniform`` (faster when the loss is cheap).
    """

    n_particles: int = eqx.field(static=True, default=100)
    max_steps: int = eqx.field(static=True, default=100)
    w: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.62)
    c1: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=2.0)
    c2: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=2.0)
    vmax_frac: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.2)
    rng: str = eqx.field(static=True, default="threefry")

    def __check_init__(self):
        if self.rng not in ("threefry", "hash"):
            raise ValueError(f"PSO rng must be 'threefry' (jax.random) or 'hash' (hash_uniform), got {self.rng!r}")
        if self.n_particles < 2:
            raise ValueError(f"PSO needs n_particles >= 2, got {self.n_particles}")
        if self.max_steps < 0:
            raise ValueError(f"PSO needs max_steps >= 0, got {self.max_steps}")

    def init(self, fn: LossFn, bounds, key: PRNGKeyArray) -> PSOState:
        """Uniform swarm in the box, evaluated once (``n_particles`` evaluations)."""
        loss_fn, (lower, upper) = fn, bounds
        kx, kv, key = jax.random.split(key, 3)
        dim = lower.shape[0]
        span = upper - lower
        x = lower + span * jax.random.uniform(kx, (self.n_particles, dim), dtype=lower.dtype)
        vmax = self.vmax_frac * span
        v = jax.random.uniform(kv, (self.n_particles, dim), minval=-vmax, maxval=vmax, dtype=lower.dtype)
        fx = evaluate(loss_fn, x)
        i = jnp.argmin(fx)
        return PSOState(x, v, fx, x, fx, x[i], fx[i], jnp.asarray(self.n_particles), key)

    def move(self, fn: LossFn, state: PSOState, bounds) -> PSOState:
        """Velocity/position update of every particle, evaluation, then personal and global bests."""
        loss_fn, (lower, upper) = fn, bounds
        key, sub = jax.random.split(state.key)
        # float32 draws (cast up) halve the PRNG work, which dominates a cheap loss; 24 random bits
        # are plenty for an acceleration coefficient.
        if self.rng == "hash":
            r = hash_uniform(sub, (2,) + state.x.shape).astype(state.x.dtype)
        else:
            r = jax.random.uniform(sub, (2,) + state.x.shape, dtype=jnp.float32).astype(state.x.dtype)
        vmax = self.vmax_frac * (upper - lower)
        x, v = jax.vmap(_move_one, in_axes=(0, 0, 0, None, 0, 0, None, None, None, None, None, None))(
            state.x, state.v, state.pbest, state.best_x, r[0], r[1], self.w, self.c1, self.c2, vmax, lower, upper
        )
        fx = evaluate(loss_fn, x)
        better = fx < state.pbest_f
        pbest = jnp.where(better[:, None], x, state.pbest)
        pbest_f = jnp.where(better, fx, state.pbest_f)
        best_x, best_loss = best_of(x, fx, state.best_x, state.best_loss)
        return PSOState(x, v, fx, pbest, pbest_f, best_x, best_loss, state.n_evals + self.n_particles, key)

    def absorb(self, state: PSOState, index: Int[Array, " k"], x: Population, fx: Float[Array, " k"]) -> PSOState:
        """Write positions ``x`` with losses ``fx`` into particles ``index`` and update the bests.

        Used by :meth:`move` and by GA-PSO to hand the GA's offspring back to the swarm (paper
        section 4.2.1, steps 7-8). Does not evaluate anything.
        """
        better = fx < state.pbest_f[index]
        pbest = state.pbest.at[index].set(jnp.where(better[:, None], x, state.pbest[index]))
        pbest_f = state.pbest_f.at[index].set(jnp.where(better, fx, state.pbest_f[index]))
        best_x, best_loss = best_of(x, fx, state.best_x, state.best_loss)
        return eqx.tree_at(
            lambda s: (s.x, s.fx, s.pbest, s.pbest_f, s.best_x, s.best_loss),
            state,
            (state.x.at[index].set(x), state.fx.at[index].set(fx), pbest, pbest_f, best_x, best_loss),
        )

    def step(self, fn: LossFn, state: PSOState, bounds) -> PSOState:
        """One PSO iteration (``n_particles`` evaluations)."""
        return self.move(fn, state, bounds)
