"""The protocol every optimiser of the static identification (Li et al., Electronics 2020, 9, 284,
section 4.2) follows: a stateless equinox Module holding its settings, with

* ``init(key, loss_fn, lower, upper) -> state`` (a pytree carrying ``best_x``, ``best_loss`` and
  ``n_evals``),
* ``step(state, loss_fn, lower, upper) -> state`` (one iteration / generation),
* ``run(key, loss_fn, lower, upper) -> RunResult`` (``init`` then ``step`` under ``lax.scan``).

Settings that are floats are array leaves, so a batch of optimisers (a hyper-parameter sweep) is a
vmap; sizes and counts are static. Seeds are a vmap over keys.
"""

from __future__ import annotations

import abc

import equinox as eqx

from .._types import PRNGKeyArray
from ._fitness import LossFn, RunResult


class AbstractOptimiser(eqx.Module):
    """Box-constrained minimiser of ``loss_fn: Float[Array, 'dim'] -> scalar`` (non-finite = +inf)."""

    @abc.abstractmethod
    def init(self, key: PRNGKeyArray, loss_fn: LossFn, lower, upper):
        """Initial state (may evaluate an initial population)."""

    @abc.abstractmethod
    def step(self, state, loss_fn: LossFn, lower, upper):
        """One iteration; returns the new state."""

    @abc.abstractmethod
    def run(self, key: PRNGKeyArray, loss_fn: LossFn, lower, upper) -> RunResult:
        """``init`` plus the configured number of ``step`` s under ``lax.scan``, with history."""
