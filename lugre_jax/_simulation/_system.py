"""The closed loop as one ODE: reference -> controller -> actuator -> joint with friction.

State (8, float64), in the order of :data:`STATE_NAMES`: ``theta`` [deg], ``omega`` [deg/s],
``z`` bristle deflection [deg], ``current`` [A] (motor with inductance only), ``xi``
velocity-error integral [deg], ``xd`` derivative filter [deg/s], ``zh`` observer's bristle state
[deg], ``xp`` position-error integral [deg*s].
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._fusion import derivative_stored_once, runtime_one
from .._types import Array, Float
from ..control import AbstractController, AbstractReference, CtrlIn
from ..friction import AbstractFrictionModel
from ..plant import AbstractActuator, IdealTorque, Joint
from ._solution import Sample

STATE_NAMES = ("theta", "omega", "z", "current", "xi", "xd", "zh", "xp")
N_STATES = len(STATE_NAMES)


class System(eqx.Module):
    """Joint + friction + actuator + controller + reference: everything one simulation needs.

    Any leaf may carry a leading batch axis (see :func:`simulate`, ``batched=True``); ``y0`` is the
    initial state in the order of :data:`STATE_NAMES` (at rest by default).
    """

    friction: AbstractFrictionModel
    joint: Joint
    controller: AbstractController
    reference: AbstractReference
    actuator: AbstractActuator = eqx.field(default_factory=IdealTorque)
    y0: Float[Array, "*b 8"] = eqx.field(
        converter=jnp.asarray, default_factory=lambda: np.zeros(N_STATES)
    )


def signals(t, y: tuple, system: System):
    """Rates and output signals for a state given as a tuple of the 8 components."""
    theta, omega, z, current, xi, xd, zh, xp = y
    th_r, v_r, a_r = system.reference(t)
    ctrl = system.controller(CtrlIn(theta, omega, xi, xd, zh, xp, th_r, v_r, a_r))
    tau, di = system.actuator.drive(ctrl.command, system.controller.voltage, current, omega)
    f, dz = system.friction.torque_and_derivative(z, omega)
    # The cotangents of dz/dt and of the net torque feed every kernel of a reverse pass that
    # handles a stage: computed once each (see _fusion; the forward solve compiles as without).
    one = runtime_one(theta)
    dz = derivative_stored_once(dz, one)
    net = derivative_stored_once(tau - f - system.joint.gravity(theta), one)
    # * (1/J): a loop-invariant reciprocal (hoisted) instead of a division per evaluation.
    domega = net * (1.0 / system.joint.J)
    dy = (omega, domega, dz, di, ctrl.dxi, ctrl.dxd, ctrl.dzh, ctrl.dxp)
    return dy, dict(torque_nm=tau, friction_nm=f, command=ctrl.command, theta_ref=th_r, v_ref=v_r)


def rates(t, y: tuple, system: System) -> tuple:
    # The solvers carry the state as a tuple of 8 arrays, not one (..., 8) array: stacked rates
    # make XLA emit a concatenate-rooted fusion that recomputes the friction law once per output
    # column and cannot vectorise (docs/performance.md).
    return signals(t, y, system)[0]


def split(y):
    return tuple(y[..., k] for k in range(N_STATES))


def vector_field(t, y: Float[Array, "8"], system: System) -> Float[Array, "8"]:
    """dy/dt of the full closed loop (units per :data:`STATE_NAMES`, per second)."""
    return jnp.stack(rates(t, split(y), system), axis=-1)


def sample(system, index, t, y) -> Sample:
    _, aux = signals(t, y, system)
    return Sample(index, t, tuple(y), aux["torque_nm"], aux["friction_nm"], aux["theta_ref"], aux["v_ref"])
