"""Baselines for the static identification of Li et al., Electronics 2020, 9, 284, section 4.2: CMA-ES
(Hansen 2016, arXiv:1604.00772) and differential evolution (Storn & Price 1997), both from evosax
0.3.2, wrapped in this package's ``init``/``step`` protocol (driven by ``minimise``); plus
``scipy.optimize.least_squares``.

Bounds:

* CMA-ES searches the unit cube ``y`` (``x = lower + (upper - lower) * y``) with ``sigma0`` as a
  fraction of the range and its mean started uniformly in the box. A sample outside the cube is
  evaluated at its projection onto the box and ranked with the penalty
  ``J(clip(y)) + d^2 * (1 + |J(clip(y))|)``, ``d`` the distance to the cube (penalised repair; CMA-ES
  ranks, so only the order matters). The best point it reports is always the feasible projection.
* DE (rand/1/bin by default) clips its trial vectors to the box before evaluating them.
"""

from __future__ import annotations

import time

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._types import Array, Float, Int, PRNGKeyArray, Scalar
from ._fitness import LossFn, ResidualFn, best_of, evaluate
from ._optimiser import AbstractOptimiser


def _evosax():
    # Imported on first use: importing evosax.algorithms creates arrays, which starts the XLA
    # backend -- at package import that would freeze the host device count before the CLI can set
    # it.
    from evosax import algorithms

    return algorithms


class EvosaxState(eqx.Module):
    """An evosax state (a flax pytree) plus our best-so-far bookkeeping."""

    inner: object
    best_x: Float[Array, " dim"]
    best_loss: Scalar
    n_evals: Int[Array, ""]
    key: PRNGKeyArray


class CMAES(AbstractOptimiser):
    """CMA-ES from evosax in the unit cube of the box. ``pop_size=None`` is ``4 + 3 ln(dim)``;
    ``max_steps`` generations; ``sigma0`` (initial step, fraction of the range) is an array leaf."""

    pop_size: int | None = eqx.field(static=True, default=None)
    max_steps: int = eqx.field(static=True, default=200)
    sigma0: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.3)

    def _algo(self, dim: int):
        n = self.pop_size if self.pop_size is not None else 4 + int(3 * np.log(dim))
        return _evosax().CMA_ES(population_size=n, solution=jnp.zeros(dim))

    def init(self, fn: LossFn, bounds, key: PRNGKeyArray) -> EvosaxState:
        """Mean uniform in the box; no evaluation."""
        lower, upper = bounds
        algo = self._algo(lower.shape[0])
        km, ki, key = jax.random.split(key, 3)
        params = algo.default_params.replace(std_init=jnp.asarray(self.sigma0))
        inner = algo.init(ki, jax.random.uniform(km, lower.shape, dtype=lower.dtype), params)
        return EvosaxState(inner, (lower + upper) / 2, jnp.asarray(jnp.inf), jnp.asarray(0), key)

    def step(self, fn: LossFn, state: EvosaxState, bounds) -> EvosaxState:
        """One ask/evaluate/tell generation (``pop_size`` evaluations)."""
        loss_fn, (lower, upper) = fn, bounds
        algo = self._algo(lower.shape[0])
        params = algo.default_params.replace(std_init=jnp.asarray(self.sigma0))
        key, ka, kt = jax.random.split(state.key, 3)
        y, inner = algo.ask(ka, state.inner, params)
        yc = jnp.clip(y, 0.0, 1.0)
        x = lower + (upper - lower) * yc
        losses = evaluate(loss_fn, x)
        d2 = jnp.sum(jnp.square(y - yc), axis=1)
        ranked = losses + d2 * (1 + jnp.abs(losses))
        inner, _ = algo.tell(kt, y, ranked, inner, params)
        best_x, best_loss = best_of(x, losses, state.best_x, state.best_loss)
        return EvosaxState(inner, best_x, best_loss, state.n_evals + y.shape[0], key)



class DE(AbstractOptimiser):
    """Differential evolution from evosax: ``base="rand"`` (DE/rand/1/bin) or ``"best"`` (DE/best/1/bin);
    ``max_steps`` generations; ``F`` and ``CR`` are array leaves."""

    pop_size: int = eqx.field(static=True, default=40)
    max_steps: int = eqx.field(static=True, default=250)
    base: str = eqx.field(static=True, default="rand")
    F: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.8)
    CR: Float[Array, ""] = eqx.field(converter=jnp.asarray, default=0.9)

    def __check_init__(self):
        if self.base not in ("rand", "best"):
            raise ValueError(f"DE base must be 'rand' or 'best', got {self.base!r}")
        if self.pop_size < 4:
            raise ValueError(f"DE needs pop_size >= 4, got {self.pop_size}")

    def _algo(self, dim: int):
        algo = _evosax().DifferentialEvolution(population_size=self.pop_size, solution=jnp.zeros(dim))
        params = algo.default_params.replace(
            elitism=self.base == "best",
            crossover_rate=self.CR,
            differential_weight=self.F,
            differential_weight_min=self.F,
            differential_weight_max=self.F,
        )
        return algo, params

    def init(self, fn: LossFn, bounds, key: PRNGKeyArray) -> EvosaxState:
        """Uniform population in the box (``pop_size`` evaluations)."""
        loss_fn, (lower, upper) = fn, bounds
        algo, params = self._algo(lower.shape[0])
        kx, ki, key = jax.random.split(key, 3)
        x = lower + (upper - lower) * jax.random.uniform(kx, (self.pop_size, lower.shape[0]), dtype=lower.dtype)
        losses = evaluate(loss_fn, x)
        inner = algo.init(ki, x, losses, params)
        i = jnp.argmin(losses)
        return EvosaxState(inner, x[i], losses[i], jnp.asarray(self.pop_size), key)

    def step(self, fn: LossFn, state: EvosaxState, bounds) -> EvosaxState:
        """One generation (``pop_size`` evaluations)."""
        loss_fn, (lower, upper) = fn, bounds
        algo, params = self._algo(lower.shape[0])
        key, ka, kt = jax.random.split(state.key, 3)
        x, inner = algo.ask(ka, state.inner, params)
        x = jnp.clip(x, lower, upper)
        losses = evaluate(loss_fn, x)
        inner, _ = algo.tell(kt, x, losses, inner, params)
        best_x, best_loss = best_of(x, losses, state.best_x, state.best_loss)
        return EvosaxState(inner, best_x, best_loss, state.n_evals + self.pop_size, key)



def scipy_least_squares(
    residual_fn: ResidualFn, x0: Float[Array, "seeds dim"], lower, upper, **kwargs
) -> dict[str, np.ndarray]:
    """``scipy.optimize.least_squares`` (trust-region reflective, bounded) from each row of ``x0``.

    Residual and Jacobian (forward mode) are jitted once and called from scipy on the host; a Python
    loop over starts. Returns numpy arrays ``x``, ``loss`` (= ``cost`` = 1/2 sum r^2), ``nfev``,
    ``njev``, ``status``, ``success`` and ``wall_time`` [s] per start.
    """
    from scipy.optimize import least_squares

    res = jax.jit(residual_fn)
    jac = jax.jit(jax.jacfwd(residual_fn))
    lo, hi = np.asarray(lower, float), np.asarray(upper, float)
    x0 = np.atleast_2d(np.asarray(x0, float))
    res(jnp.asarray(x0[0])).block_until_ready()
    jac(jnp.asarray(x0[0])).block_until_ready()
    out = {k: [] for k in ("x", "loss", "nfev", "njev", "status", "success", "wall_time")}
    for start in x0:
        t0 = time.perf_counter()
        sol = least_squares(
            lambda x: np.asarray(res(jnp.asarray(x))),
            np.clip(start, lo, hi),
            jac=lambda x: np.asarray(jac(jnp.asarray(x))),
            bounds=(lo, hi),
            method=kwargs.get("method", "trf"),
            x_scale=kwargs.get("x_scale", "jac"),
            max_nfev=kwargs.get("max_nfev", 1000),
            ftol=kwargs.get("ftol", 1e-12),
            xtol=kwargs.get("xtol", 1e-12),
            gtol=kwargs.get("gtol", 1e-12),
        )
        out["wall_time"].append(time.perf_counter() - t0)
        cost = float(sol.cost) if np.isfinite(sol.cost) else np.inf
        for k, v in (("x", sol.x), ("loss", cost), ("nfev", sol.nfev), ("njev", sol.njev or 0),
                     ("status", sol.status), ("success", sol.success)):
            out[k].append(v)
    return {k: np.asarray(v) for k, v in out.items()}
