"""One entry point for every optimiser of the static identification (Li et al., Electronics 2020, 9,
284, section 4.2): :func:`optimise`.

It builds the optimiser from a method name and settings, runs ``n_seeds`` independent seeds in one
jitted, vmapped call (compilation timed apart from the run), optionally refines each seed's best
point with Levenberg-Marquardt or BFGS, and returns host-side numpy arrays in an
:class:`OptimResult`.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from ._baselines import CMAES, DE, scipy_least_squares
from ._fitness import LossFn, ResidualFn, check_bounds, finite_or_inf, loss_from_residual
from ._ga import GA, RealGA
from ._gapso import GAPSO
from ._optimiser import AbstractOptimiser, minimise
from ._pso import PSO
from .._results import result_codes as codes_of
from ._refine import Refine, result_name

METHODS = ("ga", "ga_real", "pso", "gapso", "cmaes", "de", "lm", "bfgs", "scipy_lsq")
_POPULATION = {"ga": GA, "ga_real": RealGA, "pso": PSO, "cmaes": CMAES, "de": DE}
_LOCAL = {"lm": "lm", "bfgs": "bfgs"}


@dataclasses.dataclass(frozen=True)
class OptimResult:
    """Result of :func:`optimise` for ``n_seeds`` seeds (numpy arrays, seeds first).

    * ``x`` (seeds, dim), ``loss`` (seeds,): best point and its loss per seed (after refinement if
      asked);
    * ``x_global``, ``loss_global``: the same before refinement;
    * ``history`` (seeds, iters+1): best-so-far loss after each iteration/generation (column 0 =
      initial population; for local methods: start and end);
    * ``evals_history`` (seeds, iters+1): loss evaluations used up to each column;
    * ``n_evals`` (seeds,): total evaluations including refinement (a Jacobian or gradient counts as
      ``dim`` evaluations);
    * ``wall_time`` [s]: execution of all seeds, compilation excluded; ``compile_time`` [s];
    * ``refine_result`` (seeds,): ``optimistix.RESULTS`` indices (0 = successful) or ``None`` when
      no refinement ran; name them with ``result_name``. For ``scipy_lsq`` the scipy ``status``.
    """

    method: str
    x: np.ndarray
    loss: np.ndarray
    x_global: np.ndarray
    loss_global: np.ndarray
    history: np.ndarray
    evals_history: np.ndarray
    n_evals: np.ndarray
    wall_time: float
    compile_time: float
    refine_result: np.ndarray | None
    settings: dict[str, Any]

    @property
    def evaluations(self) -> np.ndarray:
        """Alias of ``n_evals`` (total loss evaluations per seed)."""
        return self.n_evals

    @property
    def best(self) -> tuple[np.ndarray, float]:
        """Best point over all seeds and its loss."""
        i = int(np.argmin(self.loss))
        return self.x[i], float(self.loss[i])

    @property
    def steps(self) -> int:
        """Optimiser steps (iterations/generations) per seed; 1 for the local methods' single call."""
        return int(self.history.shape[1] - 1)

    def to_json(self) -> dict[str, Any]:
        """Plain-Python dict (lists, floats, str) of every field above plus ``steps``;
        ``refine_result`` as names (``successful``, ...) where optimistix ran. Write it with
        :func:`lugre_jax.io.write_json`, which turns a non-finite loss into ``"inf"``/``null``."""
        codes = None
        if self.refine_result is not None:
            codes = (self.refine_result.tolist() if self.method == "scipy_lsq"
                     else [result_name(int(c)) for c in np.ravel(self.refine_result)])
        return dict(
            method=self.method, steps=self.steps, x=self.x.tolist(), loss=self.loss.tolist(),
            x_global=self.x_global.tolist(), loss_global=self.loss_global.tolist(),
            history=self.history.tolist(), evals_history=self.evals_history.tolist(),
            n_evals=self.n_evals.tolist(),
            wall_time_s=self.wall_time, compile_time_s=self.compile_time, refine_result=codes,
            settings={k: v for k, v in self.settings.items()
                      if isinstance(v, (str, int, float, bool, dict, type(None)))},
        )


# Other names for a step count: a setting with one of them is told the name to use.
_RENAMED = {"generations": "max_steps", "n_iterations": "max_steps", "ga_generations": "ga_steps"}


def _build(cls, what: str, settings: dict[str, Any]):
    fields = {f.name for f in dataclasses.fields(cls)}
    unknown = set(settings) - fields
    if unknown:
        renamed = [f"{k} -> {_RENAMED[k]}" for k in sorted(unknown) if k in _RENAMED and _RENAMED[k] in fields]
        hint = f" (renamed: {', '.join(renamed)})" if renamed else ""
        raise ValueError(f"{what} ({cls.__name__}) accepts settings {sorted(fields)}; "
                         f"got unknown {sorted(unknown)}{hint}")
    return cls(**settings)


def make_optimiser(method: str, **settings: Any) -> AbstractOptimiser:
    """The optimiser object for ``method`` built from ``settings`` (constructor keywords).

    For ``"gapso"``: ``ga=dict(...)``, ``pso=dict(...)``, ``ga_steps=int`` and ``max_steps`` (the
    hybrid's iterations, which are its swarm's: the same as ``pso=dict(max_steps=...)``). Every
    optimiser's iteration/generation count is ``max_steps``.
    """
    if method == "gapso":
        settings = dict(settings)
        pso = dict(settings.pop("pso", {}))
        if "max_steps" in settings:
            if "max_steps" in pso:
                raise ValueError("gapso: give max_steps once, either directly or in pso=dict(max_steps=...)")
            pso["max_steps"] = settings.pop("max_steps")
        return _build(GAPSO, method, dict(
            settings, ga=_build(GA, "gapso's ga", settings.pop("ga", {})), pso=_build(PSO, "gapso's pso", pso)))
    if method in _POPULATION:
        return _build(_POPULATION[method], method, settings)
    raise ValueError(f"unknown method {method!r}; choose one of {METHODS}")


def _timed_jit(fn, *args):
    t0 = time.perf_counter()
    compiled = jax.jit(fn).lower(*args).compile()
    t1 = time.perf_counter()
    out = jax.block_until_ready(compiled(*args))
    return out, t1 - t0, time.perf_counter() - t1


def _starts(key, n_seeds, lower, upper, x0):
    if x0 is None:
        return lower + (upper - lower) * jax.random.uniform(key, (n_seeds, lower.shape[0]), dtype=lower.dtype)
    x0 = jnp.broadcast_to(jnp.asarray(x0, dtype=jnp.float64), (n_seeds, lower.shape[0]))
    return x0


def optimise(
    method: str | AbstractOptimiser,
    loss_fn: LossFn | None,
    lower,
    upper,
    *,
    key,
    n_seeds: int = 1,
    residual_fn: ResidualFn | None = None,
    refine: bool = False,
    refine_method: str = "lm",
    refine_settings: dict[str, Any] | None = None,
    **settings: Any,
) -> OptimResult:
    """Minimise ``loss_fn`` over the box ``[lower, upper]`` with ``method``, for ``n_seeds`` seeds.

    Arguments:

    * ``method``: an optimiser object (e.g. ``PSO(max_steps=50)``, any :class:`AbstractOptimiser`),
      or a name: ``"ga"`` (paper's binary GA), ``"ga_real"`` (SBX + polynomial mutation), ``"pso"``
      (paper's PSO), ``"gapso"`` (paper's GA-PSO), ``"cmaes"``, ``"de"`` (evosax), ``"lm"``
      (optimistix Levenberg-Marquardt, needs ``residual_fn``), ``"bfgs"`` (optimistix BFGS),
      ``"scipy_lsq"`` (``scipy.optimize.least_squares``, trf, needs ``residual_fn``).
    * ``loss_fn``: ``Float[Array, 'dim'] -> scalar``, minimised; non-finite values count as +inf.
      May be ``None`` if ``residual_fn`` is given (then ``loss = 1/2 * sum(residual^2)``, the
      paper's ``J``). Must be jax-traceable.
    * ``lower``, ``upper``: finite bounds, shape ``(dim,)``, in the parameters' own units.
    * ``key``: a ``jax.random`` key; seed ``i`` uses ``split(key, n_seeds)[i]``.
    * ``residual_fn``: ``params -> residual vector``; needed by ``"lm"``, ``"scipy_lsq"`` and LM
      refinement.
    * ``refine``: refine each seed's best point with ``refine_method`` (``"lm"`` or ``"bfgs"``,
      box-transformed; ``refine_settings`` go to :class:`Refine`: ``rtol``, ``atol``, ``max_steps``).
    * ``settings``: constructor keywords of the optimiser named by ``method`` (e.g.
      ``n_particles=100, max_steps=100`` for PSO; ``ga={...}, pso={...}, ga_steps=1`` for GA-PSO).
      Local methods (``lm``, ``bfgs``, ``scipy_lsq``) take ``x0`` (``(dim,)`` or ``(n_seeds, dim)``;
      default: uniform random starts in the box, one per seed) and ``rtol``, ``atol``,
      ``max_steps`` (``max_nfev`` for scipy).

    Returns an :class:`OptimResult`. Raises ``ValueError`` for unknown methods or settings, bad
    bounds, or a missing ``residual_fn``.

    This signature is shared with the schemes/CLI code; keep it stable.
    """
    lower, upper = check_bounds(lower, upper)
    if n_seeds < 1:
        raise ValueError(f"n_seeds must be >= 1, got {n_seeds}")
    if loss_fn is None:
        if residual_fn is None:
            raise ValueError("give loss_fn, or residual_fn (then loss = 1/2 * sum(residual^2))")
        loss_fn = loss_from_residual(residual_fn)
    if method in ("lm", "scipy_lsq") and residual_fn is None:
        raise ValueError(f"method {method!r} is a least-squares solver: pass residual_fn (params -> residual vector)")
    if refine and refine_method == "lm" and residual_fn is None:
        raise ValueError("LM refinement needs residual_fn; pass it, or use refine_method='bfgs'")
    keys = jax.random.split(key, n_seeds)
    dim = lower.shape[0]
    if isinstance(method, AbstractOptimiser):
        if settings:
            raise ValueError(f"settings {sorted(settings)} apply to a method name; "
                             "set them on the optimiser object instead")
        opt, method = method, type(method).__name__
    elif method in _LOCAL or method == "scipy_lsq":
        opt = None
    else:
        opt = make_optimiser(method, **settings)

    if opt is None:
        x0 = _starts(key, n_seeds, lower, upper, settings.pop("x0", None))
        if method == "scipy_lsq":
            out = scipy_least_squares(residual_fn, x0, lower, upper, **settings)
            loss0 = np.asarray(jax.vmap(lambda x: finite_or_inf(loss_fn(x)))(x0))
            nfev = out["nfev"] + dim * out["njev"]
            x_g, l_g = out["x"], out["loss"]
            hist = np.stack([loss0, l_g], axis=1)
            evals = np.stack([np.ones(n_seeds, int), nfev], axis=1)
            wall, comp, codes = float(np.sum(out["wall_time"])), 0.0, out["status"]
        else:
            unknown = set(settings) - {"rtol", "atol", "max_steps"}
            if unknown:
                raise ValueError(f"{method} accepts settings x0, rtol, atol, max_steps; got unknown {sorted(unknown)}")
            solver = Refine(_LOCAL[method], **settings)

            def local(x0s):
                return jax.vmap(lambda x: solver(x, lower, upper, residual_fn=residual_fn, loss_fn=loss_fn))(x0s)

            r, comp, wall = _timed_jit(local, x0)
            x_g, l_g = np.asarray(r.x), np.asarray(r.loss)
            hist = np.stack([np.asarray(r.loss0), l_g], axis=1)
            evals = np.stack([np.ones(n_seeds, int), np.asarray(r.n_evals)], axis=1)
            codes = codes_of(r.result)
        x, loss, n_evals = x_g, l_g, evals[:, -1]
        result_codes = codes
    else:
        def many(ks):
            return jax.vmap(lambda k: minimise(opt, loss_fn, (lower, upper), k))(ks)

        r, comp, wall = _timed_jit(many, keys)
        x_g, l_g = np.asarray(r.best_x), np.asarray(r.best_loss)
        hist, evals = np.asarray(r.history_loss), np.asarray(r.history_evals)
        x, loss, n_evals, result_codes = x_g, l_g, evals[:, -1], None

    if refine and opt is not None:
        solver = Refine(refine_method, **(refine_settings or {}))

        def polish(xs):
            return jax.vmap(lambda x: solver(x, lower, upper, residual_fn=residual_fn, loss_fn=loss_fn))(xs)

        rr, comp2, wall2 = _timed_jit(polish, jnp.asarray(x_g))
        x, loss = np.asarray(rr.x), np.asarray(rr.loss)
        n_evals = n_evals + np.asarray(rr.n_evals)
        result_codes = codes_of(rr.result)
        comp, wall = comp + comp2, wall + wall2

    return OptimResult(
        method=method,
        x=np.asarray(x),
        loss=np.asarray(loss),
        x_global=np.asarray(x_g),
        loss_global=np.asarray(l_g),
        history=np.asarray(hist),
        evals_history=np.asarray(evals),
        n_evals=np.asarray(n_evals),
        wall_time=float(wall),
        compile_time=float(comp),
        refine_result=None if result_codes is None else np.asarray(result_codes),
        settings=dict(settings, refine=refine, refine_method=refine_method if refine else None),
    )
