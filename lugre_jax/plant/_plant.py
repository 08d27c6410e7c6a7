"""The joint and its DC motor, Li et al. (Electronics 2020, 9, 284), section 3, eq. (1)-(8).

Joint, eq. (1)-(2) with the Coriolis term zero (one joint moves, the others are locked):
``J*theta_dd + tau_f + G(theta) = tau``, angle in deg, torque in N*m, so ``J`` is in N*m*s^2/deg.

DC motor, eq. (3)-(5), referred through a reduction of ratio ``gear_ratio`` (motor turns per joint
turn): ``L di/dt = U - R i - Ke*omega_m`` and joint torque ``tau = gear_ratio*Km*i``, with
``omega_m = gear_ratio*omega`` the motor speed in rad/s. With ``L = 0`` the current is algebraic:
this is the paper's first-order simplification, eq. (8).
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._params import NONNEGATIVE, POSITIVE, check_domains, param
from .._types import Array, Float

DEG = np.pi / 180.0


class Joint(eqx.Module):
    """Rigid rotary joint, eq. (1)-(2).

    ``J`` [N*m*s^2/deg] is the equivalent inertia at the joint. The optional gravity torque is
    ``G(theta) = gravity_nm*sin(theta + gravity_phase_deg)`` [N*m]; the paper compensates gravity, so
    it defaults to 0.
    """

    J: Float[Array, "*b"] = param("N*m*s^2/deg", 1e-6, 10.0, domain=POSITIVE)
    gravity_nm: float | Float[Array, "*b"] = param("N*m", -100.0, 100.0, default=0.0, convert=False)
    gravity_phase_deg: float | Float[Array, "*b"] = param(
        "deg", -180.0, 180.0, default=0.0, convert=False
    )

    def __check_init__(self):
        check_domains(self)

    def gravity(self, theta):
        """Gravity torque G(theta) [N*m] for joint angle ``theta`` [deg]."""
        if isinstance(self.gravity_nm, (int, float)) and self.gravity_nm == 0:
            return jnp.zeros_like(theta)  # compiled away: the paper compensates gravity
        return self.gravity_nm * jnp.sin((theta + self.gravity_phase_deg) * DEG)


class AbstractActuator(eqx.Module):
    """Turns a controller command into joint torque; may carry one state (armature current [A])."""

    @abc.abstractmethod
    def drive(self, command, voltage: bool, current, omega_deg_s) -> tuple[Array, Array]:
        """``(joint torque [N*m], d(current)/dt [A/s])`` for a torque [N*m] or voltage [V] command."""


class IdealTorque(AbstractActuator):
    """A perfect torque source: the joint receives the commanded torque [N*m] (no motor dynamics)."""

    def drive(self, command, voltage, current, omega_deg_s):
        if voltage:
            raise ValueError("a voltage command needs a DCMotor actuator, not IdealTorque")
        return command, jnp.zeros_like(command)


class DCMotor(AbstractActuator):
    """Armature-controlled DC motor with a reducer, eq. (3)-(5); ``L = 0`` gives eq. (8).

    The paper gives none of these constants. Defaults (see :data:`MOTOR_ASSUMPTIONS`) are those of a
    plausible 24 V, ~100 W brushed/brushless DC motor with a 160:1 harmonic or planetary reducer,
    chosen so that the largest torque of Table 1 (~6.5 N*m) needs under 1 A and so that the
    electrical time constant L/R = 2.5e-4 s is far below the mechanical one, as the paper assumes.
    """

    R: Float[Array, "*b"] = param("ohm", 1e-3, 100.0, domain=POSITIVE, default=2.0)
    L: Float[Array, "*b"] = param("H", 0.0, 1.0, domain=NONNEGATIVE, default=5.0e-4)
    Ke: Float[Array, "*b"] = param("V*s/rad", 1e-4, 10.0, domain=POSITIVE, default=0.05)
    Km: Float[Array, "*b"] = param("N*m/A", 1e-4, 10.0, domain=POSITIVE, default=0.05)
    gear_ratio: Float[Array, "*b"] = param("1", 1.0, 1e4, domain=POSITIVE, default=160.0)
    u_max: Float[Array, "*b"] = param("V", 0.0, 1e3, domain=NONNEGATIVE, default=24.0)

    def __check_init__(self):
        check_domains(self)

    def back_emf(self, omega_deg_s):
        """Back-EMF [V] at joint velocity ``omega_deg_s`` [deg/s]."""
        return self.Ke * self.gear_ratio * omega_deg_s * DEG

    def joint_torque(self, current):
        """Torque at the joint [N*m] for armature current [A]."""
        return self.gear_ratio * self.Km * current

    def current_rate(self, current, voltage, omega_deg_s):
        """di/dt [A/s], eq. (3)."""
        return (voltage - self.R * current - self.back_emf(omega_deg_s)) / self.L

    def static_current(self, voltage, omega_deg_s):
        """Current [A] when L is neglected, eq. (8)."""
        return (voltage - self.back_emf(omega_deg_s)) / self.R

    neglect_inductance: bool = eqx.field(static=True, default=False)

    def drive(self, command, voltage, current, omega_deg_s):
        """Torque demand -> voltage by the motor's static inverse (eq. 8), saturated at ``u_max``.

        With ``voltage=True`` the command is already the armature voltage [V]. With
        ``neglect_inductance`` the current is algebraic (eq. 8) and its state stays at zero.
        """
        emf = self.back_emf(omega_deg_s)
        if voltage:
            u = command
        else:
            u = self.R * command / (self.gear_ratio * self.Km) + emf
        u = jnp.clip(u, -self.u_max, self.u_max)
        if self.neglect_inductance:
            return self.joint_torque((u - emf) / self.R), jnp.zeros_like(current)
        return self.joint_torque(current), (u - self.R * current - emf) / self.L

    def time_constants(self, J):
        """(Te, Tm) in s: electrical L/R and mechanical J*R/(Km*Ke) at the joint, eq. (6)-(7)."""
        J_si = J / DEG  # N*m*s^2/deg -> N*m*s^2/rad
        k2 = (self.gear_ratio * self.Km) * (self.gear_ratio * self.Ke)
        return self.L / self.R, J_si * self.R / k2


MOTOR_ASSUMPTIONS = {
    "R": (2.0, "ohm", "armature resistance of a 24 V, ~100 W DC motor"),
    "L": (5.0e-4, "H", "armature inductance; L/R = 2.5e-4 s << mechanical time constant"),
    "Ke": (0.05, "V*s/rad", "back-EMF constant at the motor shaft (= Km in SI units)"),
    "Km": (0.05, "N*m/A", "torque constant at the motor shaft"),
    "gear_ratio": (160.0, "1", "reducer ratio; the paper says only that a reducer is used"),
    "u_max": (24.0, "V", "supply voltage (saturation of the voltage command)"),
}
"""The motor constants the paper does not give: value, unit, and why. One place, stated as assumptions."""
