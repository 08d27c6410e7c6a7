"""Genetic algorithms of Li et al., Electronics 2020, 9, 284, section 4.2.3 (binary) and a real-coded one.

:class:`GA` is the paper's GA: binary genes of ``bits = 10`` per parameter (``lower + k/(2^bits-1)
* (upper - lower)``, ``k`` an unsigned integer, most significant bit first), population 20,
crossover probability ``Pc = 0.9``, mutation probability ``Pm = 0.005`` per bit, 20 generations
(``max_steps``).
The paper does not state the selection or the crossover; ours:

* selection: roulette wheel on the paper's fitness ``f = C_m - J`` (section 4.2.3, step 2), with
  replacement; if every ``f`` is 0 (all equal, or all failed) the draw is uniform. ``selection =
  "tournament"`` gives binary tournaments on ``J`` instead;
* crossover: single-point on the whole chromosome, per pair with probability ``Pc``;
* mutation: independent bit flips with probability ``Pm``;
* elitism: the ``n_elite`` (default 1) best of the parents replace the first children unchanged,
  so the best-so-far never gets worse; elites are not re-evaluated.

:class:`RealGA` is the real-coded variant: tournament selection on ``J``, simulated binary crossover
(SBX, Deb & Agrawal 1995, ``eta_c``) per pair with probability ``pc``, polynomial mutation
(``eta_m``) per gene with probability ``pm``, children clipped to the box, same elitism.

Operators are written for one individual (or one pair) and vmapped over the population.
Evaluations per generation: ``pop_size - n_elite``; :func:`~._optimiser.minimise` counts the initial
population as generation 0 and then runs ``max_steps`` generations.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp

from .._types import Array, Bool, Float, Int, Population, PRNGKeyArray, Scalar
from ._fitness import LossFn, evaluate, paper_fitness
from ._optimiser import AbstractOptimiser

# ---------------------------------------------------------------- shared selection


def _roulette(key, losses, n):
    f = paper_fitness(losses)
    total = jnp.sum(f)
    p = jnp.where(total > 0, f / jnp.where(total > 0, total, 1.0), 1.0 / losses.shape[0])
    return jax.random.choice(key, losses.shape[0], (n,), replace=True, p=p)


def _tournament(key, losses, n, size):
    cand = jax.random.randint(key, (n, size), 0, losses.shape[0])
    # argmin over candidates; ties (and inf vs inf) go to the first drawn, which is random already.
    return cand[jnp.arange(n), jnp.argmin(losses[cand], axis=1)]


def _select(key, losses, n, selection, size):
    if selection == "roulette":
        return _roulette(key, losses, n)
    return _tournament(key, losses, n, size)


def _pairs(parents):
    """Reshape ``(n, ...)`` parents into ``ceil(n/2)`` pairs (the last one wraps if ``n`` is odd)."""
    n = parents.shape[0]
    m = (n + 1) // 2
    idx = jnp.arange(2 * m) % n
    p = parents[idx]
    return p[0::2], p[1::2]


def _unpair(a, b, n):
    return jnp.stack([a, b], axis=1).reshape((-1,) + a.shape[1:])[:n]


def _with_elites(children, parents, parent_losses, n_elite):
    """First ``n_elite`` children become the best parents; returns children, elite losses."""
    order = jnp.argsort(parent_losses)[:n_elite]
    return children.at[:n_elite].set(parents[order]), parent_losses[order]


# ---------------------------------------------------------------- binary coding


def encode(x: Float[Array, " dim"], lower, upper, bits: int) -> Bool[Array, " dim*bits"]:
    """Binary genes of one individual: ``bits`` per parameter, MSB first, nearest level."""
    levels = 2**bits - 1
    k = jnp.clip(jnp.round((x - lower) / (upper - lower) * levels), 0, levels).astype(jnp.int64)
    shifts = jnp.arange(bits - 1, -1, -1)
    return ((k[:, None] >> shifts[None, :]) & 1).astype(bool).reshape(-1)


def decode(genes: Bool[Array, " dim*bits"], lower, upper, bits: int) -> Float[Array, " dim"]:
    """Inverse of :func:`encode` (exact on the ``2^bits`` levels)."""
    g = genes.reshape(lower.shape[0], bits).astype(jnp.int64)
    k = jnp.sum(g << jnp.arange(bits - 1, -1, -1)[None, :], axis=1)
    return lower + (upper - lower) * k.astype(lower.dtype) / (2**bits - 1)


def _one_point_crossover(key, a, b, pc):
    kc, kp = jax.random.split(key)
    point = jax.random.randint(kp, (), 1, a.shape[0])
    do = jax.random.uniform(kc) < pc
    tail = (jnp.arange(a.shape[0]) >= point) & do
    return jnp.where(tail, b, a), jnp.where(tail, a, b)


def _bit_flip(key, genes, pm):
    return genes ^ (jax.random.uniform(key, genes.shape) < pm)


class GAState(eqx.Module):
    """Population (genes for :class:`GA`, reals for :class:`RealGA`) with its losses and the best."""

    genes: Array
    losses: Float[Array, " pop"]
    best_x: Float[Array, " dim"]
    best_loss: Scalar
    n_evals: Int[Array, ""]
    key: PRNGKeyArray


def _advance(state, genes, x, losses, n_new, key):
    """Next generation's state: keep the best-so-far unless this generation beat it."""
    i = jnp.argmin(losses)
    better = losses[i] < state.best_loss
    return GAState(genes, losses, jnp.where(better, x[i], state.best_x),
                   jnp.where(better, losses[i], state.best_loss), state.n_evals + n_new, key)


def _state_from(genes, x, losses, key, n_evals):
    i = jnp.argmin(losses)
    return GAState(genes, losses, x[i], losses[i], jnp.asarray(n_evals), key)


class GA(AbstractOptimiser):
    """The paper's binary GA (section 4.2.3): population 20, 10-bit genes, Pc 0.9, Pm 0.005, 20 generations.

    ``pc`` and ``pm`` are array leaves (vmappable); the rest is static. ``max_steps`` is the number of
    generations.
    """

    pop_size: int = eqx.field(static=True, default=20)
    bits: int = eqx.field(static=True, default=10)
    max_steps: int = eqx.field(static=True, default=20)
    n_elite: int = eqx.field(static=True, default=1)
    selection: str = eqx.field(static=True, default="roulette")
    tournament_size: int = eqx.field(static=True, default=2)
    pc: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.9)
    pm: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.005)

    def __check_init__(self):
        if self.pop_size < 2 or not 0 <= self.n_elite < self.pop_size:
            raise ValueError(f"GA needs pop_size >= 2 and 0 <= n_elite < pop_size, got {self.pop_size}, {self.n_elite}")
        if not 1 <= self.bits <= 30:
            raise ValueError(f"GA bits must be in 1..30, got {self.bits}")
        if self.selection not in ("roulette", "tournament"):
            raise ValueError(f"selection must be 'roulette' or 'tournament', got {self.selection!r}")

    def encode(self, x, lower, upper):
        """Genes of one individual (vmap for a population)."""
        return encode(x, lower, upper, self.bits)

    def decode(self, genes, lower, upper):
        """Parameters of one individual (vmap for a population)."""
        return decode(genes, lower, upper, self.bits)

    def init(self, fn: LossFn, bounds, key: PRNGKeyArray) -> GAState:
        """Random bits (each 0/1 with probability 1/2), decoded and evaluated (``pop_size`` evaluations)."""
        loss_fn, (lower, upper) = fn, bounds
        kg, key = jax.random.split(key)
        genes = jax.random.bernoulli(kg, 0.5, (self.pop_size, lower.shape[0] * self.bits))
        x = jax.vmap(self.decode, (0, None, None))(genes, lower, upper)
        return _state_from(genes, x, evaluate(loss_fn, x), key, self.pop_size)

    def init_from(self, fn: LossFn, x: Population, bounds, key: PRNGKeyArray) -> GAState:
        """Encode a given population (paper 4.2.1 step 3: "GA encodes the particle swarm").

        The decoded (quantised) points are re-evaluated, so the stored losses are those of the
        points the genes represent (``len(x)`` evaluations).
        """
        loss_fn, (lower, upper) = fn, bounds
        genes = jax.vmap(self.encode, (0, None, None))(x, lower, upper)
        xq = jax.vmap(self.decode, (0, None, None))(genes, lower, upper)
        return _state_from(genes, xq, evaluate(loss_fn, xq), key, x.shape[0])

    def population(self, state: GAState, bounds) -> Population:
        """Decoded population of ``state``."""
        lower, upper = bounds
        return jax.vmap(self.decode, (0, None, None))(state.genes, lower, upper)

    def step(self, fn: LossFn, state: GAState, bounds) -> GAState:
        """Selection, crossover, mutation, elitism; evaluates ``pop_size - n_elite`` children."""
        loss_fn, (lower, upper) = fn, bounds
        n = state.genes.shape[0]
        key, ks, kc, km = jax.random.split(state.key, 4)
        parents = state.genes[_select(ks, state.losses, n, self.selection, self.tournament_size)]
        a, b = _pairs(parents)
        a, b = jax.vmap(_one_point_crossover, (0, 0, 0, None))(jax.random.split(kc, a.shape[0]), a, b, self.pc)
        children = _unpair(a, b, n)
        children = jax.vmap(_bit_flip, (0, 0, None))(jax.random.split(km, n), children, self.pm)
        children, elite_losses = _with_elites(children, state.genes, state.losses, self.n_elite)
        x = jax.vmap(self.decode, (0, None, None))(children, lower, upper)
        losses = jnp.concatenate([elite_losses, evaluate(loss_fn, x[self.n_elite:])])
        return _advance(state, children, x, losses, n - self.n_elite, key)



# ---------------------------------------------------------------- real coding


def _sbx(key, a, b, pc, eta, lower, upper):
    ku, kg, kc = jax.random.split(key, 3)
    u = jax.random.uniform(ku, a.shape)
    beta = jnp.where(u <= 0.5, (2 * u) ** (1 / (eta + 1)), (1 / (2 * (1 - u))) ** (1 / (eta + 1)))
    c1 = 0.5 * ((1 + beta) * a + (1 - beta) * b)
    c2 = 0.5 * ((1 - beta) * a + (1 + beta) * b)
    # Each gene recombines with probability 1/2 (Deb's convention), the pair with probability pc.
    mix = (jax.random.uniform(kg, a.shape) < 0.5) & (jax.random.uniform(kc) < pc)
    c1 = jnp.clip(jnp.where(mix, c1, a), lower, upper)
    c2 = jnp.clip(jnp.where(mix, c2, b), lower, upper)
    return c1, c2


def _polynomial_mutation(key, x, pm, eta, lower, upper):
    ku, km = jax.random.split(key)
    u = jax.random.uniform(ku, x.shape)
    delta = jnp.where(u < 0.5, (2 * u) ** (1 / (eta + 1)) - 1, 1 - (2 * (1 - u)) ** (1 / (eta + 1)))
    mutate = jax.random.uniform(km, x.shape) < pm
    return jnp.clip(jnp.where(mutate, x + delta * (upper - lower), x), lower, upper)


class RealGA(AbstractOptimiser):
    """Real-coded GA: tournament selection, SBX crossover, polynomial mutation, elitism.

    Defaults are sized like the paper's GA (population 20, ``max_steps`` = 20 generations) so the two
    compare at the same budget; ``pm`` is per gene.
    """

    pop_size: int = eqx.field(static=True, default=20)
    max_steps: int = eqx.field(static=True, default=20)
    n_elite: int = eqx.field(static=True, default=1)
    tournament_size: int = eqx.field(static=True, default=2)
    pc: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.9)
    pm: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.25)
    eta_c: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=15.0)
    eta_m: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=20.0)

    def __check_init__(self):
        if self.pop_size < 2 or not 0 <= self.n_elite < self.pop_size:
            raise ValueError(f"RealGA needs pop_size >= 2 and 0 <= n_elite < pop_size, got {self.pop_size}, {self.n_elite}")

    def init(self, fn: LossFn, bounds, key: PRNGKeyArray) -> GAState:
        """Uniform population in the box (``pop_size`` evaluations)."""
        loss_fn, (lower, upper) = fn, bounds
        kx, key = jax.random.split(key)
        x = lower + (upper - lower) * jax.random.uniform(kx, (self.pop_size, lower.shape[0]), dtype=lower.dtype)
        return _state_from(x, x, evaluate(loss_fn, x), key, self.pop_size)

    def step(self, fn: LossFn, state: GAState, bounds) -> GAState:
        """Tournament, SBX, polynomial mutation, elitism; evaluates ``pop_size - n_elite`` children."""
        loss_fn, (lower, upper) = fn, bounds
        n = state.genes.shape[0]
        key, ks, kc, km = jax.random.split(state.key, 4)
        parents = state.genes[_tournament(ks, state.losses, n, self.tournament_size)]
        a, b = _pairs(parents)
        sbx = jax.vmap(_sbx, (0, 0, 0, None, None, None, None))
        a, b = sbx(jax.random.split(kc, a.shape[0]), a, b, self.pc, self.eta_c, lower, upper)
        children = _unpair(a, b, n)
        mut = jax.vmap(_polynomial_mutation, (0, 0, None, None, None, None))
        children = mut(jax.random.split(km, n), children, self.pm, self.eta_m, lower, upper)
        children, elite_losses = _with_elites(children, state.genes, state.losses, self.n_elite)
        losses = jnp.concatenate([elite_losses, evaluate(loss_fn, children[self.n_elite:])])
        return _advance(state, children, children, losses, n - self.n_elite, key)

