"""Objective and fitness of Li et al., Electronics 2020, 9, 284, section 4.2.3 (step 2).

The paper minimises ``J = 1/2 * sum_k e(k)^2`` with ``e(k)`` the identification error, and its GA
maximises the fitness ``f(M_k) = C_m - J(M_k)`` with ``C_m = max_k J(M_k)`` over the current
population. Every optimiser in this package minimises a plain loss ``J``; only GA selection uses
``f``. A loss that is not finite (a failed evaluation, NaN from a bad parameter set) counts as
``+inf``: it is never selected as a best and gets fitness 0 in the GA.

Nothing here knows about friction: a loss is any ``Float[Array, 'dim'] -> scalar``.
"""

from __future__ import annotations

from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._types import Array, Float, Int, Population, Scalar

LossFn = Callable[[Float[Array, " dim"]], Scalar]
ResidualFn = Callable[[Float[Array, " dim"]], Float[Array, " n"]]


def half_sse(residual: Float[Array, " n"]) -> Scalar:
    """The paper's objective ``J = 1/2 * sum(e^2)`` for a residual vector ``e`` (units of e squared)."""
    return 0.5 * jnp.sum(jnp.square(residual))


def loss_from_residual(residual_fn: ResidualFn) -> LossFn:
    """``x -> 1/2 * sum(residual_fn(x)^2)``: the scalar loss of a least-squares problem."""

    def loss(x):
        return half_sse(residual_fn(x))

    return loss


def finite_or_inf(value: Float[Array, "*b"]) -> Float[Array, "*b"]:
    """Map NaN and +-inf to +inf, so a failed evaluation is the worst possible loss."""
    return jnp.where(jnp.isfinite(value), value, jnp.inf)


def evaluate(loss_fn: LossFn, population: Population) -> Float[Array, " pop"]:
    """Loss of every row of ``population`` (vmapped); non-finite values become +inf."""
    return finite_or_inf(jax.vmap(loss_fn)(population))


def paper_fitness(losses: Float[Array, " pop"]) -> Float[Array, " pop"]:
    """The paper's GA fitness ``f = C_m - J`` with ``C_m`` the largest finite ``J`` of the population.

    Non-finite ``J`` get fitness 0 (as bad as the worst finite member). If no member is finite all
    fitnesses are 0.
    """
    finite = jnp.isfinite(losses)
    cm = jnp.max(jnp.where(finite, losses, -jnp.inf))
    return jnp.where(finite, cm - losses, 0.0)


def check_bounds(lower, upper) -> tuple[Float[Array, " dim"], Float[Array, " dim"]]:
    """Bounds as float64 arrays; raises ValueError for shapes or order a box cannot have.

    The order/finiteness checks run on concrete bounds only (traced bounds are trusted).
    """
    concrete = not isinstance(lower, jax.core.Tracer) and not isinstance(upper, jax.core.Tracer)
    if concrete:
        lo, hi = np.asarray(lower, dtype=np.float64), np.asarray(upper, dtype=np.float64)
        if lo.ndim != 1 or lo.shape != hi.shape:
            raise ValueError(
                f"lower and upper must be 1-D arrays of equal length, got shapes {lo.shape} and {hi.shape}"
            )
        if not np.all(lo < hi):
            raise ValueError(f"every lower bound must be < its upper bound, got {lo} and {hi}")
        if not np.all(np.isfinite(lo) & np.isfinite(hi)):
            raise ValueError(
                "population optimisers sample the box uniformly, so bounds must be finite; "
                f"got lower={lo}, upper={hi}"
            )
    return jnp.asarray(lower, dtype=jnp.float64), jnp.asarray(upper, dtype=jnp.float64)


def best_of(
    x: Population, losses: Float[Array, " pop"], best_x: Float[Array, " dim"], best_loss: Scalar
) -> tuple[Float[Array, " dim"], Scalar]:
    """Best-so-far update: keep ``(best_x, best_loss)`` unless a member of ``x`` is strictly better."""
    i = jnp.argmin(losses)
    better = losses[i] < best_loss
    return jnp.where(better, x[i], best_x), jnp.where(better, losses[i], best_loss)


class RunResult(eqx.Module):
    """What ``run`` returns for one seed: final state, best point and per-iteration history.

    ``history_loss[t]`` is the best-so-far loss after iteration ``t`` (``t = 0`` is the initial
    population) and ``history_evals[t]`` the number of loss evaluations used up to then.
    """

    state: eqx.Module
    best_x: Float[Array, " dim"]
    best_loss: Scalar
    history_loss: Float[Array, " iters"]
    history_evals: Int[Array, " iters"]

