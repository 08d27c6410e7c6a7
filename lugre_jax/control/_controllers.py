"""Controllers of Li et al. (Electronics 2020, 9, 284): open loop, velocity PID, cascaded position +
velocity PID (Fig. 7), and the LuGre observer-based compensation of section 4.3, eq. (19)-(24).

A controller maps the measured state and the reference to a command (a torque demand in N*m, or a
voltage in V for ``OpenLoop(voltage=True)``) and to the rates of its own states. Its states live in
the simulator's state vector (see ``lugre_jax._simulate``): ``xi`` velocity-error integral [deg],
``xd`` derivative filter [deg/s], ``zh`` observed bristle state [deg], ``xp`` position-error
integral [deg*s].
"""

from __future__ import annotations

import abc
from typing import ClassVar, NamedTuple

import equinox as eqx
import jax.numpy as jnp

from .._params import NONNEGATIVE, POSITIVE, check_domains, param
from .._types import Array, Float
from ..friction import AbstractFrictionModel


class CtrlIn(NamedTuple):
    """What a controller sees: measurements, its own states, and the reference."""

    theta: Array
    omega: Array
    xi: Array
    xd: Array
    zh: Array
    xp: Array
    theta_ref: Array
    v_ref: Array
    a_ref: Array


class CtrlOut(NamedTuple):
    """Command and the rates of the controller states."""

    command: Array
    dxi: Array
    dxd: Array
    dzh: Array
    dxp: Array


class AbstractController(eqx.Module):
    """Maps :class:`CtrlIn` to :class:`CtrlOut`. ``voltage`` says whether the command is a voltage."""

    voltage: eqx.AbstractClassVar[bool]

    def __check_init__(self):
        check_domains(self)  # concrete gains and time constants in their domains (no negative gain)

    @abc.abstractmethod
    def __call__(self, s: CtrlIn) -> CtrlOut:
        ...


def _zero(s: CtrlIn):
    return jnp.zeros_like(s.omega)


class OpenLoop(AbstractController):
    """Open loop: ``command = bias + rate*t_equiv + gain*v_ref``.

    With ``gain`` the command is a feedforward of the velocity reference (e.g. the viscous and Coulomb
    torque a user expects to need). ``rate`` integrates the reference position, giving a torque ramp
    as the commanded angle grows. Command units: N*m (torque) or V with :class:`OpenLoopVoltage`.
    """

    bias: Float[Array, "*b"] = param("N*m", -100.0, 100.0, default=0.0)
    gain: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 1e3, default=0.0)
    rate: Float[Array, "*b"] = param("N*m/deg", 0.0, 1e3, default=0.0)
    voltage: ClassVar[bool] = False

    def __call__(self, s):
        z = _zero(s)
        return CtrlOut(self.bias + self.gain * s.v_ref + self.rate * s.theta_ref, z, z, z, z)


class OpenLoopVoltage(AbstractController):
    """Open-loop armature voltage ``u = bias + gain*v_ref`` [V] (needs a :class:`~lugre_jax.DCMotor`)."""

    bias: Float[Array, "*b"] = param("V", -100.0, 100.0, default=0.0)
    gain: Float[Array, "*b"] = param("V*s/deg", 0.0, 1e3, default=0.0)
    voltage: ClassVar[bool] = True

    def __call__(self, s):
        z = _zero(s)
        return CtrlOut(self.bias + self.gain * s.v_ref, z, z, z, z)


def _velocity_pid(kp, ki, kd, tf, e, xi, xd):
    if isinstance(kd, (int, float)) and kd == 0:
        # A PI controller (a static kd = 0, the default) has no derivative term, so its filter
        # state is not integrated: it stays at its initial value. Integrating it anyway cost every
        # step the filter's arithmetic and its Runge-Kutta stages for a state that no output
        # depends on.
        return kp * e + ki * xi, e, jnp.zeros_like(e)
    # Derivative through a first-order filter (time constant tf): the ideal derivative of a velocity
    # error needs the acceleration, which depends on this very command (an algebraic loop).
    d = (e - xd) * (1.0 / tf)  # reciprocal of a parameter: hoisted out of the time loop
    return kp * e + ki * xi + kd * d, e, d


class VelocityPID(AbstractController):
    """Velocity PID, position loop off: ``tau = kp*e + ki*int(e) + kd*de/dt``, ``e = v_ref - omega``.

    Gains in N*m*s/deg (kp), N*m/deg (ki), N*m*s^2/deg (kd); the derivative is filtered with time
    constant ``tf`` [s]. ``kd`` stays a Python number unless given as an array: the default 0.0 is
    then a compile-time constant and the controller is a plain PI (its derivative-filter state
    ``xd`` is not integrated and stays at its initial value). Pass an array to vary or
    differentiate ``kd``.
    """

    kp: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 1e4, domain=NONNEGATIVE)
    ki: Float[Array, "*b"] = param("N*m/deg", 0.0, 1e5, domain=NONNEGATIVE, default=0.0)
    kd: float | Float[Array, "*b"] = param("N*m*s^2/deg", 0.0, 1e3, domain=NONNEGATIVE, default=0.0, convert=False)
    tf: Float[Array, "*b"] = param("s", 1e-6, 1.0, domain=POSITIVE, default=1e-2)
    voltage: ClassVar[bool] = False

    def __call__(self, s):
        u, dxi, dxd = _velocity_pid(self.kp, self.ki, self.kd, self.tf, s.v_ref - s.omega, s.xi, s.xd)
        return CtrlOut(u, dxi, dxd, _zero(s), _zero(s))


class PositionPID(AbstractController):
    """Cascade (Fig. 7): position PI ``v_cmd = v_ref + kpp*e_p + kip*int(e_p)`` feeding a velocity PID.

    ``e_p = theta_ref - theta`` [deg]; kpp in 1/s, kip in 1/s^2; the inner loop as :class:`VelocityPID`.
    """

    kpp: Float[Array, "*b"] = param("1/s", 0.0, 1e4, domain=NONNEGATIVE)
    kp: Float[Array, "*b"] = param("N*m*s/deg", 0.0, 1e4, domain=NONNEGATIVE)
    ki: Float[Array, "*b"] = param("N*m/deg", 0.0, 1e5, domain=NONNEGATIVE, default=0.0)
    kd: float | Float[Array, "*b"] = param("N*m*s^2/deg", 0.0, 1e3, domain=NONNEGATIVE, default=0.0, convert=False)
    kip: Float[Array, "*b"] = param("1/s^2", 0.0, 1e5, domain=NONNEGATIVE, default=0.0)
    tf: Float[Array, "*b"] = param("s", 1e-6, 1.0, domain=POSITIVE, default=1e-2)
    voltage: ClassVar[bool] = False

    def __call__(self, s):
        ep = s.theta_ref - s.theta
        v_cmd = s.v_ref + self.kpp * ep + self.kip * s.xp
        u, dxi, dxd = _velocity_pid(self.kp, self.ki, self.kd, self.tf, v_cmd - s.omega, s.xi, s.xd)
        return CtrlOut(u, dxi, dxd, _zero(s), ep)


class LuGreCompensated(AbstractController):
    """PID plus LuGre observer feedforward, section 4.3, eq. (19)-(24).

    Observer (eq. 19): ``dzh/dt = omega - sigma0*|omega|*zh/g(omega) - k*e`` with ``e`` the velocity
    error of the inner loop; estimate (eq. 20): ``Mf_hat = sigma0*zh + sigma1*dzh/dt + sigma2*omega``;
    control law (eq. 24): ``Mc = J_ff*dv_ref/dt + H(s)e + Mf_hat``. ``observer`` is the *identified*
    friction model (LuGre or Segmented), which in any honest experiment differs from the plant's.
    ``inner`` is a :class:`VelocityPID` or :class:`PositionPID` giving ``H(s)e``.
    """

    inner: VelocityPID | PositionPID
    observer: AbstractFrictionModel
    k_obs: Float[Array, "*b"] = param("1", 0.0, 1e4, domain=NONNEGATIVE, default=1.0)
    J_ff: Float[Array, "*b"] = param("N*m*s^2/deg", 0.0, 10.0, domain=NONNEGATIVE, default=0.0)
    voltage: ClassVar[bool] = False

    def __call__(self, s):
        out = self.inner(s)
        # The inner loop's velocity error e = dxi/dt in both PID forms.
        e = out.dxi
        f_obs, dz_obs = self.observer.torque_and_derivative(s.zh, s.omega)
        dzh = dz_obs - self.k_obs * e
        mf_hat = f_obs - self.observer.bristle_damping(s.omega) * self.k_obs * e
        u = self.J_ff * s.a_ref + out.command + mf_hat
        return CtrlOut(u, out.dxi, out.dxd, dzh, out.dxp)
