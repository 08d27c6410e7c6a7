"""GA-PSO hybrid of Li et al., Electronics 2020, 9, 284, section 4.2.1 (flow) and 4.2.3 (settings).

Built by composition: a :class:`GAPSO` holds a :class:`~._ga.GA` and a :class:`~._pso.PSO` and calls
their operators; it adds only the hand-over between them. The paper's flow, step by step, and what
each step is here (the paper is terse; the reading is ours where marked):

1. "Initialise the swarm (range, x_i, v_i)": ``pso.init`` (evaluates the swarm).
2. "Set GA population size, Pc, Pm, iterations": the fields of ``ga`` (paper: 20, 0.9, 0.005, 20).
3. "GA encodes the initial value of the particle swarm": the ``ga.pop_size`` particles with the best
   current loss are encoded in binary (``ga.init_from``; the quantised points are re-evaluated).
   *Ours*: which particles (the best ones) -- the GA population is smaller than the swarm.
4. "Selection, crossover, mutation": ``ga.step``.
5. "Decode, calculate fitness values, adjust": part of ``ga.step`` (decode + evaluate).
6. "If the GA's iteration count is met, output; else return to 3": ``ga_steps`` GA steps
   (default: the GA's own ``max_steps``, 20, the literal reading; a cheaper variant uses 1).
7. "PSO compares with the individual extrema by the fitness of (5)": the GA's final population is
   handed back to the particles it came from, and ``pso.absorb`` updates their personal bests.
   *Ours*: an offspring replaces its particle's position (velocity kept) only where it has a lower
   loss than the particle's current position; an unconditional write-back snaps the best particles
   onto the 10-bit grid every iteration and caps the accuracy at the grid resolution.
8. "... and with the global extremum": ``pso.absorb`` also updates the global best.
9. "Termination?": the fixed iteration count ``pso.max_steps`` (``minimise``'s ``lax.scan``).
10. "Update velocity and position": ``pso.move`` (evaluates the whole swarm, updates bests).
11. "Return to (3)": next iteration.

Evaluations per iteration: ``pop_size + ga_steps * (pop_size - n_elite)`` for the GA part plus
``pso.n_particles`` for the move: with the paper's settings 20 + 20*19 + 100 = 500 per iteration,
five times the PSO's 100. Compare the two per evaluation, not per iteration.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp

from .._types import Array, Int, PRNGKeyArray, Scalar, Float
from ._fitness import LossFn
from ._optimiser import AbstractOptimiser
from ._ga import GA
from ._pso import PSO, PSOState


class GAPSOState(eqx.Module):
    """The swarm's state (the GA's population lives only inside one iteration)."""

    swarm: PSOState
    best_x: Float[Array, " dim"]
    best_loss: Scalar
    n_evals: Int[Array, ""]


def _mirror(swarm: PSOState) -> GAPSOState:
    return GAPSOState(swarm, swarm.best_x, swarm.best_loss, swarm.n_evals)


class GAPSO(AbstractOptimiser):
    """GA-PSO by composition: ``ga`` (paper's binary GA) and ``pso`` (paper's PSO).

    ``ga_steps`` GA steps per PSO iteration; ``None`` means ``ga.max_steps`` (the literal reading of
    step 6). ``max_steps`` (the number of GA-PSO iterations) is the swarm's, ``pso.max_steps``.
    """

    ga: GA = eqx.field(default_factory=GA)
    pso: PSO = eqx.field(default_factory=PSO)
    ga_steps: int | None = eqx.field(static=True, default=None)

    def __check_init__(self):
        if self.ga.pop_size > self.pso.n_particles:
            raise ValueError(
                f"GA-PSO encodes ga.pop_size={self.ga.pop_size} particles, but the swarm has only "
                f"pso.n_particles={self.pso.n_particles}; make the GA population smaller"
            )

    @property
    def n_ga_steps(self) -> int:
        return self.ga.max_steps if self.ga_steps is None else self.ga_steps

    @property
    def max_steps(self) -> int:
        return self.pso.max_steps

    def init(self, fn: LossFn, bounds, key: PRNGKeyArray) -> GAPSOState:
        """Step 1: the swarm (``pso.n_particles`` evaluations)."""
        return _mirror(self.pso.init(fn, bounds, key))

    def step(self, fn: LossFn, state: GAPSOState, bounds) -> GAPSOState:
        """Steps 3-8 and 10 of the flow above (one GA-PSO iteration)."""
        swarm = state.swarm
        key, kga = jax.random.split(swarm.key)
        # Step 3: the best particles become the GA's population.
        chosen = jnp.argsort(swarm.fx)[: self.ga.pop_size]
        ga_state = self.ga.init_from(fn, swarm.x[chosen], bounds, kga)

        # Steps 4-6: the GA's own loop.
        def ga_body(s, _):
            return self.ga.step(fn, s, bounds), None

        ga_state, _ = jax.lax.scan(ga_body, ga_state, None, length=self.n_ga_steps)
        # Steps 7-8: offspring back into the swarm, personal and global bests updated.
        x_ga = self.ga.population(ga_state, bounds)
        swarm = eqx.tree_at(lambda s: (s.key, s.n_evals), swarm, (key, swarm.n_evals + ga_state.n_evals))
        # Ours: an offspring replaces its particle's position only if it is better there. Writing
        # back unconditionally would snap the best particles to the 10-bit grid every iteration
        # and cap the accuracy at the grid's resolution.
        improves = ga_state.losses < swarm.fx[chosen]
        x_back = jnp.where(improves[:, None], x_ga, swarm.x[chosen])
        f_back = jnp.where(improves, ga_state.losses, swarm.fx[chosen])
        swarm = self.pso.absorb(swarm, chosen, x_back, f_back)
        # Elitism keeps the GA's best in its final population, but be explicit: it may have been
        # found in an earlier generation and the global best must never miss it.
        better = ga_state.best_loss < swarm.best_loss
        swarm = eqx.tree_at(
            lambda s: (s.best_x, s.best_loss),
            swarm,
            (jnp.where(better, ga_state.best_x, swarm.best_x), jnp.where(better, ga_state.best_loss, swarm.best_loss)),
        )
        # Step 10: velocity and position update.
        return _mirror(self.pso.move(fn, swarm, bounds))
