"""What a simulation returns: sampled trajectories, one sample as a reduction sees it, per-lane
means, and the per-lane result codes."""

from __future__ import annotations


import equinox as eqx
import jax
import jax.numpy as jnp

from .._results import RESULTS, result_name
from .._types import Array, Float, Int, PyTree

# a lane's result code is the index of its item in the package's one enumeration (lugre_jax.RESULTS):
# an int array, so that it stacks, stores and compares as one
RESULT_OK = int(RESULTS.successful._value)
RESULT_NONFINITE = int(RESULTS.nonfinite._value)  # the state blew up
RESULT_SOLVER_FAILED = int(RESULTS.max_steps_reached._value)  # the adaptive solver gave up
RESULT_NAMES = {c: result_name(c) for c in (RESULT_OK, RESULT_NONFINITE, RESULT_SOLVER_FAILED)}


def _component(view, k):
    # A function, not a Module method: equinox wraps every bound method on attribute access, a cost
    # paid on each `sol.theta` of a small unbatched solve.
    return view.ys[..., k] if isinstance(view, Solution) else view.y[k]


class _AbstractStateView(eqx.Module):
    """Named views of the state components shared by :class:`Solution` and :class:`Sample`."""

    @property
    def theta(self):
        """Joint angle [deg]."""
        return _component(self, 0)

    @property
    def omega(self):
        """Joint velocity [deg/s]."""
        return _component(self, 1)

    @property
    def z(self):
        """Bristle deflection [deg]."""
        return _component(self, 2)


class Solution(_AbstractStateView):
    """Sampled trajectories. Arrays have shape ``(*batch, n_samples)`` (``ys``: ``(..., n, 8)``).

    ``torque_nm`` is the actuator torque at the joint [N*m], ``friction_nm`` the plant's friction
    torque [N*m], ``result`` the per-lane result code (:data:`RESULT_OK` = 0; the index of a
    :class:`~lugre_jax.RESULTS` item, named by :func:`~lugre_jax.result_name`).
    """

    ts: Float[Array, " n"]
    ys: Float[Array, "*b n 8"]
    torque_nm: Float[Array, "*b n"]
    friction_nm: Float[Array, "*b n"]
    theta_ref: Float[Array, "*b n"]
    v_ref: Float[Array, "*b n"]
    result: Int[Array, "*b"]

    @property
    def ok(self):
        return self.result == RESULT_OK

    def to_json(self) -> dict:
        """Plain lists with units in the keys (what ``lugre-jax simulate`` writes as columns)."""
        import numpy as np

        def col(x):
            return np.asarray(x).tolist()
        return {"time_s": col(self.ts), "position_deg": col(self.theta), "velocity_deg_s": col(self.omega),
                "torque_nm": col(self.torque_nm), "friction_nm": col(self.friction_nm), "z_deg": col(self.z),
                "position_ref_deg": col(self.theta_ref), "velocity_ref_deg_s": col(self.v_ref),
                "result": col(self.result), "result_name": _result_names(self.result)}


class Sample(_AbstractStateView):
    """One sample of one simulation, as a ``SaveAt(fn=g)`` or ``SaveAt(mean=g)`` function sees it.

    ``index`` is the sample number (0 at t = 0: use it to look up measured data), ``t`` the time
    [s], ``y`` the 8 state components in ``STATE_NAMES`` order (deg, deg/s, deg, A, deg*s...),
    ``torque_nm`` the actuator torque and ``friction_nm`` the friction torque [N*m], ``theta_ref``
    [deg] and ``v_ref`` [deg/s] the reference. All are scalars; what the function does not read
    is not computed.
    """

    index: Int[Array, ""]
    t: Float[Array, ""]
    y: tuple
    torque_nm: Float[Array, ""]
    friction_nm: Float[Array, ""]
    theta_ref: Float[Array, ""]
    v_ref: Float[Array, ""]


class AbstractLaneValues(eqx.Module):
    """Per-lane values of a solve with the lane's result code: what :class:`SampleMean` and
    :class:`SampleValues` share."""

    value: eqx.AbstractVar[PyTree]
    result: eqx.AbstractVar[Int[Array, "*b"]]

    @property
    def ok(self):
        return self.result == RESULT_OK

    def to_json(self) -> dict:
        import numpy as np

        return {"value": jax.tree.map(lambda v: np.asarray(v).tolist(), self.value),
                "result": np.asarray(self.result).tolist(), "result_name": _result_names(self.result)}

    def or_inf(self):
        """``value`` where the lane succeeded, ``+inf`` (at every sample) where it failed, leaf by leaf."""
        return _or_inf(self.ok, self.value)


class SampleMean(AbstractLaneValues):
    """What :func:`simulate` returns with ``SaveAt(mean=g)``: the mean of ``g`` over every sample.

    ``value`` has ``g``'s pytree structure, each leaf with a leading batch axis when batched;
    ``result`` is the per-lane result code (0 = ok). A failed lane's value is meaningless (often
    NaN): use :meth:`or_inf` for a loss, so that a failed run is infinitely bad.
    """

    value: PyTree
    result: Int[Array, "*b"]


class SampleValues(AbstractLaneValues):
    """What :func:`simulate` returns with ``SaveAt(fn=g)``: ``g(sample)`` at every sample, stacked.

    ``value`` has ``g``'s pytree structure, each leaf with a leading sample axis (``(n, ...)``;
    ``(batch, n, ...)`` when batched); ``result`` is the per-lane result code (0 = ok). A failed
    lane's values are meaningless (often NaN): :meth:`or_inf` makes them ``+inf``.
    """

    value: PyTree
    result: Int[Array, "*b"]


def _or_inf(ok, value):
    # a lane's code broadcast over the leaf's trailing axes (samples, the function's own axes)
    return jax.tree.map(lambda v: jnp.where(ok.reshape(ok.shape + (1,) * (v.ndim - ok.ndim)), v, jnp.inf), value)


def _result_names(result):
    import numpy as np

    r = np.asarray(result)
    return result_name(int(r)) if r.ndim == 0 else [result_name(int(x)) for x in r.ravel()]


def trajectory_loss(sol: Solution, reduce) -> Array:
    """``reduce(sol)`` where the lane succeeded, ``+inf`` where it failed: failed runs are infinitely bad."""
    val = reduce(sol)
    return jnp.where(sol.result == RESULT_OK, val, jnp.inf)
