"""The protocol every population optimiser of the static identification (Li et al., Electronics 2020,
9, 284, section 4.2) follows, and the one loop that drives them all (as optimistix's
``iterative_solve`` drives its solvers).

An optimiser is an equinox Module holding its settings, with

* ``init(fn, bounds, key) -> state``: the initial state (may evaluate an initial population);
* ``step(fn, state, bounds) -> state``: one iteration / generation;
* ``max_steps``: how many ``step`` s :func:`minimise` takes (the one step-count name of the package).

``fn`` is the loss ``Float[Array, 'dim'] -> scalar`` (non-finite = +inf), ``bounds`` the box
``(lower, upper)``. Every state carries ``best_x``, ``best_loss`` and ``n_evals``. Settings that are
floats are array leaves, so a batch of optimisers (a hyper-parameter sweep) is a vmap over the
optimiser; sizes and counts are static. Seeds are a vmap over keys.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp

from .._types import PRNGKeyArray
from ._fitness import LossFn, RunResult, check_bounds


class AbstractOptimiser(eqx.Module):
    """Box-constrained minimiser of ``fn: Float[Array, 'dim'] -> scalar`` (non-finite = +inf).

    Concrete optimisers also have ``max_steps: int`` (a static field, or a property for a composite
    such as GA-PSO, whose count is its swarm's): not declared here as an ``AbstractVar`` because
    equinox does not let a property satisfy one.
    """

    @abc.abstractmethod
    def init(self, fn: LossFn, bounds, key: PRNGKeyArray):
        """Initial state (may evaluate an initial population); ``bounds = (lower, upper)``."""

    @abc.abstractmethod
    def step(self, fn: LossFn, state, bounds):
        """One iteration; returns the new state."""


def minimise(optimiser: AbstractOptimiser, fn: LossFn, bounds, key: PRNGKeyArray, *,
             max_steps: int | None = None) -> RunResult:
    """``optimiser.init`` then ``max_steps`` (default ``optimiser.max_steps``) ``optimiser.step`` s
    under ``lax.scan``, recording the best-so-far loss and the evaluation count after each step.

    The history has ``max_steps + 1`` rows (row 0: the initial state). Jit-, vmap- (over ``key``,
    or over an optimiser built with ``eqx.filter_vmap``) and differentiation-agnostic: it is a
    plain function of its arguments. ``bounds = (lower, upper)`` must be finite with lower < upper.
    """
    n_steps = optimiser.max_steps if max_steps is None else max_steps
    if n_steps < 0:
        raise ValueError(f"max_steps must be >= 0, got {n_steps}")
    lower, upper = check_bounds(*bounds)
    bounds = (lower, upper)
    state0 = optimiser.init(fn, bounds, key)

    def body(state, _):
        state = optimiser.step(fn, state, bounds)
        return state, (state.best_loss, state.n_evals)

    state, (hist_loss, hist_evals) = jax.lax.scan(body, state0, None, length=n_steps)
    hist_loss = jnp.concatenate([state0.best_loss[None], hist_loss])
    hist_evals = jnp.concatenate([jnp.asarray(state0.n_evals)[None], hist_evals])
    return RunResult(state, state.best_x, state.best_loss, hist_loss, hist_evals)
