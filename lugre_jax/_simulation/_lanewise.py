"""Error-controlled explicit Runge-Kutta with a step size of each lane's own, in one lean loop.

Under ``vmap`` every lane runs the same number of loop iterations (the largest lane's count), but
each lane advances its own time with its own step: a lane that slips takes small steps while its
neighbours in the batch take large ones. An iteration is one step attempt: the stages unrolled
(as the fixed-step loop), an embedded error estimate, an integral step-size controller, the
samples crossed by the step written by cubic Hermite interpolation, and no other bookkeeping.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._fixed import above, below
from ._solution import RESULT_NONFINITE, RESULT_OK, RESULT_SOLVER_FAILED
from ._system import rates, sample, split


def end_stage(tableau) -> int:
    """Index (into the stages, 0 = ``k0``) of a stage at the step's end that enters the update:
    its slope, taken at the left limit, is the step's end slope."""
    for i, (c, b) in enumerate(zip(tableau.c, tableau.b_sol[1:])):
        if float(c) == 1.0 and float(b) != 0.0 and not (tableau.fsal and i == len(tableau.c) - 1):
            return i + 1
    raise ValueError("LaneAdaptive needs a tableau with a stage at the step's end that enters the update "
                     "(Tsit5, Dopri5)")


def frozen_states(system) -> tuple:
    """For each state, whether its rate is the constant zero for this system's structure (a PI
    controller's derivative filter, an ideal actuator's current, a controller's unused integrals):
    such a state keeps its initial value, so the solver neither integrates nor error-checks it.
    Read from the right-hand side's traced program for one lane; a rate that is zero only for
    some parameter values is integrated."""
    from jax.extend.core import Literal

    arrays, static = eqx.partition(system, eqx.is_array)  # Python numbers stay compile-time constants
    lane = jax.tree.map(lambda x: jax.ShapeDtypeStruct(x.shape[1:], x.dtype), arrays)
    scalar = jax.ShapeDtypeStruct((), system.y0.dtype)
    out = jax.make_jaxpr(lambda a, t, y: rates(t, y, eqx.combine(a, static)))(
        lane, scalar, (scalar,) * system.y0.shape[-1]).jaxpr.outvars
    return tuple(isinstance(v, Literal) and np.ndim(v.val) == 0 and float(v.val) == 0.0 for v in out)


def writes_per_lane() -> bool:
    """Whether the sample buffers are written one lane at a time (XLA:CPU, see
    :func:`solve_lanewise`); an accelerator gets one scatter per step, whose windows it writes in
    parallel (a loop over the lanes would be one kernel launch per lane and step there)."""
    return jax.default_backend() == "cpu"


def _hermite(y0, k0, y1, k1, h, s):
    s2, s3 = s * s, s * s * s
    a, b, c, d = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, 3 * s2 - 2 * s3, s3 - s2
    return tuple(a * p + (b * h) * kp + c * q + (d * h) * kq for p, kp, q, kq in zip(y0, k0, y1, k1))


def solve_lanewise(system, n: int, sample_hz: float, stepping, sample_fn=None, mean: bool = True):
    """``(ys (b, n, 8), result (b,), steps (b,))`` at the samples ``i/sample_hz`` for a batched
    ``system`` (every array leaf with a leading lane axis ``b``); never raises. With ``sample_fn``
    (a function of one :class:`Sample`) ``ys`` is instead ``sample_fn``'s values at every sample
    (leaves ``(b, n, ...)``) or, with ``mean``, their per-lane mean, accumulated where each sample
    is interpolated (nothing is stored per sample).

    Written at the level of the batch, not vmapped: under ``vmap`` a ``while_loop`` with a per-lane
    condition selects between the old and the new value of its whole carry on every iteration,
    output buffer included. Here the loop's condition is one scalar (some lane still running), a
    finished lane steps no further (its step is zero) and a step writes a window of samples from
    the first it crosses."""
    tab = stepping.solver.tableau
    order = 5
    i_end = end_stage(tab)
    fsal = tab.fsal
    h_sample = 1.0 / sample_hz
    t_final = (n - 1) * h_sample
    per_step = max(1, int(round(stepping.dtmax * sample_hz)))
    dtmax = per_step * h_sample
    rtol, atol = stepping.rtol, stepping.atol
    y0_all = system.y0
    b = y0_all.shape[0]
    frozen = frozen_states(system)

    def one_lane(sys_, t, y, k0, h, landed):
        def f(ti, yi):
            return rates(ti, yi, sys_)

        ks = [k0]
        t1 = t + h
        for i, a in enumerate(tab.a_lower):
            stage = tuple(yc if frozen[j] else yc + h * sum(float(c) * k[j] for c, k in zip(a, ks) if c != 0)
                          for j, yc in enumerate(y))
            c = float(tab.c[i])
            if fsal and i == len(tab.a_lower) - 1:
                # the next step's first slope: at the right limit when the step lands on a jump
                ti = jnp.where(landed, above(t1), t1)
            elif c == 1.0:
                ti = below(t1)  # the step belongs to the interval before t1
            else:
                ti = t + c * h
            ks.append(f(ti, stage))
        y1 = tuple(yc if frozen[j] else yc + h * sum(float(w) * k[j] for w, k in zip(tab.b_sol, ks) if w != 0)
                   for j, yc in enumerate(y))
        k_next = ks[-1] if fsal else f(t1, y1)
        # On a step that lands on a jump, the end slope for the error estimate and the interpolant
        # is the end stage's (left limit); the FSAL stage's belongs to the next interval.
        k_end = tuple(jnp.where(landed, u, v) for u, v in zip(ks[i_end], ks[-1])) if fsal else ks[i_end]
        err_ks = list(ks)
        if fsal:
            err_ks[-1] = k_end
        ratio = jnp.asarray(0.0)
        for j, (u, v) in enumerate(zip(y, y1)):
            if frozen[j]:
                continue
            e = h * sum(float(w) * k[j] for w, k in zip(tab.b_error, err_ks) if w != 0)
            ratio = jnp.maximum(ratio, jnp.abs(e) / (atol + rtol * jnp.maximum(jnp.abs(u), jnp.abs(v))))
        return y1, k_next, k_end, ratio

    attempt = eqx.filter_vmap(one_lane)
    rhs = eqx.filter_vmap(lambda s_, ti, yi: rates(ti, yi, s_))
    jumps = eqx.filter_vmap(lambda s_: jnp.atleast_1d(s_.reference.jump_times()))(system)  # (b, k)
    k_rows = per_step + 1  # samples a step of about dtmax can cross

    def advance(state):
        """One step attempt of every running lane: the new state and the attempted step
        ``(t, h, y, k0, y1, k_end, first, last, accept)`` (samples ``first..last`` lie in
        ``(t, t + h]``)."""
        t, y, k0, h_try, steps, ok, active = state
        nxt = jnp.min(jnp.where(jumps > t[:, None], jumps, jnp.inf), axis=1)
        h = jnp.minimum(h_try, dtmax)
        # land on the next discontinuity and on the end (a step that would stop just short of
        # either is stretched onto it)
        land = t + 1.01 * h >= nxt
        h = jnp.where(land, nxt - t, h)
        end = t + 1.01 * h >= t_final
        h = jnp.where(end, t_final - t, h)
        land = land & (nxt <= t_final)
        h = jnp.where(active, h, 0.0)
        y1, k1, k_end, ratio = attempt(system, t, y, k0, h, land)
        finite = jnp.isfinite(ratio)
        accept = active & (ratio <= 1.0) & finite
        t1 = jnp.where(end, t_final, t + h)
        seg = (t, h, y, k0, y1, k_end, _reached(t) + 1, _reached(t1), accept)
        factor = jnp.where(finite, 0.9 * jnp.maximum(ratio, 1e-10) ** (-1.0 / order), 0.2)
        h_new = jnp.where(active, h * jnp.clip(factor, 0.2, 5.0), h_try)
        # a step cut short to land on a jump keeps the proposal it was cut from
        h_new = jnp.where(accept & land, jnp.maximum(h_new, h_try), h_new)
        collapsed = active & (h_new < 1e-12 * max(t_final, 1.0))
        t = jnp.where(accept, t1, t)
        y = tuple(jnp.where(accept, u, v) for u, v in zip(y1, y))
        k0 = tuple(jnp.where(accept, u, v) for u, v in zip(k1, k0))
        steps = steps + active
        ok = ok & ~collapsed
        running = ok & (t < t_final) & (steps < stepping.max_steps)
        return (t, y, k0, h_new, steps, ok, running), seg

    def _reached(t):
        # index of the last sample at or before t
        return jnp.floor(t * sample_hz + 1e-7).astype(jnp.int32)

    def interpolate(seg, i):
        """The step ``seg`` at sample indices ``i`` ((b,) or (b, m)): values (8 of ``i``'s shape)
        and which of them the accepted step covers."""
        t, h, y, k0, y1, k_end, first, last, accept = seg
        col = (lambda a: a[:, None]) if i.ndim == 2 else (lambda a: a)  # noqa: E731
        inv_h = 1.0 / jnp.where(h > 0, h, 1.0)
        s = jnp.clip((i * h_sample - col(t)) * col(inv_h), 0.0, 1.0)
        vals = _hermite(tuple(map(col, y)), tuple(map(col, k0)), tuple(map(col, y1)), tuple(map(col, k_end)),
                        col(h), s)
        vals = tuple(jnp.broadcast_to(col(c), s.shape) if fz else v for c, v, fz in zip(y, vals, frozen))
        take = col(accept) & (i >= col(first)) & (i <= col(last))
        return vals, take

    y0 = split(y0_all)
    zeros = jnp.zeros((b,), y0_all.dtype)
    h0 = jnp.full((b,), min(stepping.dt0, dtmax), y0_all.dtype)
    state0 = (zeros, y0, rhs(system, zeros, y0), h0, jnp.zeros((b,), jnp.int32), jnp.ones((b,), bool),
              jnp.full((b,), t_final > 0))

    if sample_fn is None or not mean:
        # One loop, lanes never wait for each other. A step writes ``k_rows`` samples from the first
        # it crosses as one window per lane. Rows past the step's end, and a rejected
        # attempt's rows, are written again later: a sample's last write is the accepted step that
        # covers it. ``k_rows`` rows of slack at the end take the last steps' windows. With
        # ``sample_fn`` the window holds its values, not the states (fewer values to write).
        # Each scalar output (a state, or one element of a ``sample_fn`` leaf) has a buffer of its
        # own, (b, n + k_rows), on a CPU written one lane at a time by an unbatched
        # dynamic_update_slice, in place. Under vmap the same write is a scatter, which XLA:CPU's
        # cost model sizes by the whole buffer and splits over two threads: a hand-off to a worker
        # thread on every step, which doubled the cost of some processes' runs. Interleaved
        # columns, (b, (n + k_rows) * m), are written several times slower (docs/performance.md).
        rows = jnp.arange(k_rows, dtype=jnp.int32)[None, :]
        col = lambda a: a[:, None]  # noqa: E731
        if sample_fn is None:
            def values(i, ti, vals):
                return tuple(vals)  # N_STATES of (b, k_rows)
        else:
            per_row = jax.vmap(lambda s_, i, ti, yi: sample_fn(sample(s_, i, ti, yi)), in_axes=(None, 0, 0, 0))
            per_lane_rows = eqx.filter_vmap(per_row)

            def values(i, ti, vals):
                return per_lane_rows(system, i, ti, tuple(vals))

        def width(x):
            """Scalar columns of a leaf ``(b, rows, ...)``: one per element of a sample's value."""
            return max(1, int(np.prod(x.shape[2:])))

        def columns(tree, rows_):
            """The scalar columns ((b, rows_) each) of every leaf of ``tree``, in order."""
            return [x.reshape(b, rows_, -1)[:, :, j] for x in jax.tree.leaves(tree) for j in range(width(x))]

        per_lane = writes_per_lane()

        def write(buf, first, x):
            if not per_lane:  # an accelerator runs the scatter's windows in parallel
                return jax.vmap(lambda bl, f, u: jax.lax.dynamic_update_slice(bl, u, (f,)))(buf, first, x)

            def put(lane, bl):
                return jax.lax.dynamic_update_slice(bl, jax.lax.dynamic_slice_in_dim(x, lane, 1), (lane, first[lane]))

            return jax.lax.fori_loop(jnp.int32(0), jnp.int32(b), put, buf)

        def body(c):
            st, bufs = c
            st, seg = advance(st)
            first = seg[6]
            i = first[:, None] + rows
            vals, _ = interpolate(seg, i)  # rows the step does not cover are written again later
            cols = columns(values(i, i * h_sample, vals), k_rows)
            # the barrier keeps XLA from fusing the interpolation into the writes, which then
            # recompute it per written value (docs/performance.md)
            first, cols = jax.lax.optimization_barrier((first, cols))
            return st, [write(buf, first, x) for buf, x in zip(bufs, cols)]

        v0 = values(jnp.zeros((b, 1), jnp.int32), zeros[:, None], tuple(map(col, y0)))  # sample 0
        leaves0, treedef = jax.tree.flatten(v0)
        bufs0 = [jnp.zeros((b, n + k_rows), x.dtype).at[:, :1].set(x) for x in columns(v0, 1)]
        state, bufs = jax.lax.while_loop(lambda c: jnp.any(c[0][-1]), body, (state0, bufs0))
        out, k = [], 0
        for x in leaves0:
            m = width(x)
            out.append(jnp.stack([bl[:, :n] for bl in bufs[k: k + m]], axis=-1).reshape((b, n) + x.shape[2:]))
            k += m
        buf = jax.tree.unflatten(treedef, out)
        if sample_fn is None:
            buf = jnp.stack(buf, axis=-1)  # (b, n, N_STATES)
        t, y, _, _, steps, ok, _ = state
        finished = ok & (t >= t_final)
        # an accepted step has a finite error estimate, so finite stages and a finite interpolant:
        # a lane that finished with a finite state wrote only finite samples
        finite = jnp.all(jnp.stack([jnp.isfinite(c) for c in y]), axis=0)
    else:
        per_sample = eqx.filter_vmap(lambda s_, i, ti, yi: sample_fn(sample(s_, i, ti, yi)))
        acc0 = per_sample(system, jnp.zeros((b,), jnp.int32), zeros, y0)  # sample 0

        def body(carry):
            st, acc = carry
            st, seg = advance(st)
            for r in range(k_rows):
                i = seg[6] + r
                vals, take = interpolate(seg, i)
                val = per_sample(system, i, i * h_sample, tuple(vals))
                acc = jax.tree.map(lambda a, v: a + jnp.where(take.reshape(take.shape + (1,) * (v.ndim - 1)), v, 0.0),
                                   acc, val)
            return st, acc

        state, buf = jax.lax.while_loop(lambda c: jnp.any(c[0][-1]), body, (state0, acc0))
        t, y, _, _, steps, ok, _ = state
        finished = ok & (t >= t_final)
        # a state that blew up makes the error estimate non-finite: the lane stops there and
        # fails unless its final state is finite
        finite = jnp.all(jnp.stack([jnp.isfinite(c) for c in y]), axis=0)
        buf = jax.tree.map(lambda a: a / n, buf)
    code = jnp.where(finished, jnp.where(finite, RESULT_OK, RESULT_NONFINITE), RESULT_SOLVER_FAILED)
    return buf, code, steps
