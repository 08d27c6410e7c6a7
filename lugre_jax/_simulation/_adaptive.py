"""Error-controlled stepping with diffrax, landing on the reference's discontinuities."""

from __future__ import annotations

import diffrax
import jax.numpy as jnp

from ._solution import RESULT_NONFINITE, RESULT_OK, RESULT_SOLVER_FAILED
from ._system import vector_field


def solve_adaptive(system, ts, stepping):
    """``(ys, result)`` at the sample times ``ts``; never raises on a failed solve (``throw=False``)."""
    controller = diffrax.PIDController(rtol=stepping.rtol, atol=stepping.atol, dtmax=stepping.dtmax)
    jumps = system.reference.jump_times()
    if jumps.shape[-1]:
        # Step exactly to each discontinuity and restart after it: an error-controlled solver that
        # meets a jump unannounced rejects steps down to tiny sizes and still smears the jump.
        # Times outside (t0, t1) (e.g. +inf for "no jump") are harmless.
        controller = diffrax.ClipStepSizeController(controller, jump_ts=jumps)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(vector_field), stepping.solver, t0=ts[0], t1=ts[-1], dt0=stepping.dt0,
        y0=system.y0, args=system, saveat=diffrax.SaveAt(ts=ts), stepsize_controller=controller,
        max_steps=stepping.max_steps, adjoint=stepping.adjoint, throw=False,
    )
    solved = sol.result == diffrax.RESULTS.successful
    finite = jnp.all(jnp.isfinite(sol.ys))
    code = jnp.where(solved, jnp.where(finite, RESULT_OK, RESULT_NONFINITE), RESULT_SOLVER_FAILED)
    return sol.ys, code
