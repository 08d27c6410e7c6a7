"""Gradient refinement of a global optimiser's best point (an extension of Li et al., Electronics 2020,
9, 284, section 4.2, which stops at GA-PSO).

Levenberg-Marquardt on a residual function (the package's bounded least squares,
:func:`lugre_jax._fit.least_squares`), or BFGS (``optimistix.BFGS``) on the scalar loss. The box is
respected by the same change of variables for both (:class:`~lugre_jax._fit.BoxTransform`: a
sigmoid onto each finite range, a softplus onto a half-line, the identity when unbounded).

Solvers run with ``throw=False``: a failure comes back as an ``optimistix.RESULTS`` code (and a
non-finite final loss is replaced by the starting point and its loss) -- never as a silent NaN.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import optimistix as optx

from .._fit import BoxTransform, least_squares
from .._results import RESULTS, promote, result_name
from .._types import Array, Float, Int, Scalar
from ._fitness import LossFn, ResidualFn, finite_or_inf, half_sse

__all__ = ["BoxTransform", "Refine", "RefineResult", "result_name"]


class RefineResult(eqx.Module):
    """Outcome of one refinement.

    ``result`` is a :class:`lugre_jax._results.RESULTS` item (the solver's optimistix code, promoted;
    ``result == RESULTS.successful``, named by :func:`result_name`); it stacks under vmap.
    """

    x: Float[Array, " dim"]
    loss: Scalar
    x0: Float[Array, " dim"]
    loss0: Scalar
    result: RESULTS
    n_steps: Int[Array, ""]
    n_evals: Int[Array, ""]


class Refine(eqx.Module):
    """Local refinement in box-transformed coordinates: ``method`` = ``"lm"`` or ``"bfgs"``.

    ``n_evals`` of a result counts one evaluation per solver step plus ``dim`` per Jacobian/gradient
    (forward-mode Jacobian for LM, reverse-mode gradient counted as ``dim`` too for comparability
    with derivative-free methods) -- an estimate of work in loss-evaluation units.
    """

    method: str = eqx.field(static=True, default="lm")
    rtol: float = eqx.field(static=True, default=1e-10)
    atol: float = eqx.field(static=True, default=1e-12)
    max_steps: int = eqx.field(static=True, default=200)

    def __check_init__(self):
        if self.method not in ("lm", "bfgs"):
            raise ValueError(f"Refine method must be 'lm' or 'bfgs', got {self.method!r}")

    def __call__(
        self,
        x0: Float[Array, " dim"],
        lower,
        upper,
        *,
        residual_fn: ResidualFn | None = None,
        loss_fn: LossFn | None = None,
    ) -> RefineResult:
        """Refine from ``x0``; LM needs ``residual_fn``, BFGS uses ``loss_fn`` or ``1/2|residual|^2``."""
        lower = jnp.asarray(lower, dtype=jnp.float64)
        upper = jnp.asarray(upper, dtype=jnp.float64)
        box = BoxTransform(lower, upper)
        x0 = jnp.clip(jnp.asarray(x0, dtype=jnp.float64), lower, upper)
        if self.method == "lm":
            if residual_fn is None:
                raise ValueError("Levenberg-Marquardt refinement needs residual_fn (params -> residual vector)")
            objective = lambda x: half_sse(residual_fn(x))  # noqa: E731
            _, sol = least_squares(residual_fn, x0, box, rtol=self.rtol, atol=self.atol, max_steps=self.max_steps)
        else:
            if loss_fn is None and residual_fn is None:
                raise ValueError("BFGS refinement needs loss_fn or residual_fn")
            objective = loss_fn if loss_fn is not None else (lambda x: half_sse(residual_fn(x)))
            fn = lambda u, _: objective(box.to_box(u))  # noqa: E731
            sol = optx.minimise(fn, optx.BFGS(rtol=self.rtol, atol=self.atol), box.from_box(x0),
                                max_steps=self.max_steps, throw=False)
        x = box.to_box(sol.value)
        loss = finite_or_inf(objective(x))
        loss0 = finite_or_inf(objective(x0))
        # Never hand back something worse than (or a NaN instead of) the start.
        keep = ~(loss <= loss0)
        x = jnp.where(keep, x0, x)
        loss = jnp.where(keep, loss0, loss)
        n_steps = jnp.asarray(sol.stats["num_steps"])
        n_evals = n_steps * (1 + x0.shape[0]) + 2
        return RefineResult(x, loss, x0, loss0, promote(sol.result), n_steps, n_evals)

