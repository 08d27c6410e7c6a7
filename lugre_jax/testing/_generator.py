"""An INDEPENDENT closed-loop recording generator, for testing the diagnose tool on recordings that
this project's simulator did not make (like ``numpy.testing``: a reference, not part of the science).

Plant: a rigid rotary joint (Li et al., Electronics 2020, 9, 284, eq. 1-2) with LuGre friction
(eq. 9) under a velocity PI loop (:class:`VelocityPIController`) or a position PID
(:class:`PositionPIDController`),
written here from the equations with plain numpy and integrated by scipy's ``solve_ivp`` (LSODA or
Radau, tight tolerance), segment by segment between the breakpoints of the reference so that sharp
steps are not stepped over. Nothing of ``lugre_jax``'s simulator or friction code is imported: an
error there cannot cancel an error in the diagnosis.

Measured signals: torque = the controller's command + torque noise (white, or an AR(1) sequence:
:class:`Sensors`); velocity = true velocity + white noise (or no velocity column); position
quantised to the encoder step. Units: the paper's (s, deg, deg/s, N*m; J in N*m*s^2/deg, sigma0 in
N*m/deg, sigma1 and sigma2 in N*m*s/deg).

Effects of the diagnose candidates (each the physics of the candidate of the same ``id``, written
again here): ``gravity``, ``asymmetry``, ``position_ripple``, ``thermal_drift``,
``stribeck_shape``, ``load_dependent``, ``compliance`` (two-mass joint with a spring) and
``backlash`` (a dead band in front of a share of the friction, with its own bristle state).

Effects outside the candidates (:data:`OUTSIDE_EFFECTS`): ``actuator_lag`` (the torque reaches the
joint through a first-order lag; the recorded torque is the command), ``quadratic_drag``
(``c*v*|v|``), ``torque_dependent_friction`` (friction growing with the torque the transmission
carries, the motor's torque less its rotor's inertial torque) and ``time_disturbance`` (a slow
periodic torque in time).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import ClassVar

import numpy as np
from scipy.integrate import solve_ivp

DEG = math.pi / 180.0


# ---------------------------------------------------------------------------------------------
# Plant, controller, sensors


@dataclasses.dataclass(frozen=True)
class Plant:
    """Rigid joint with LuGre friction (paper units). Defaults: the plant of issue #20."""

    J: float = 0.1
    Fc: float = 1.2
    Fs: float = 2.6
    vs: float = 0.08
    sigma2: float = 1.1
    sigma0: float = 60.0
    sigma1: float = 1.5
    delta: float = 2.0

    def g(self, v):
        return self.Fc + (self.Fs - self.Fc) * np.exp(-np.abs(v / self.vs) ** self.delta)


class Controller:
    """Base of the closed loops; ``kind`` names the loop in the recording's settings."""

    kind: ClassVar[str] = "controller"


@dataclasses.dataclass(frozen=True)
class VelocityPIController(Controller):
    """``tau = kp*(v_ref - v) + ki*int(v_ref - v)`` on the TRUE velocity (N*m*s/deg, N*m/deg)."""

    kp: float = 6.0
    ki: float = 40.0
    kind: ClassVar[str] = "velocity_pi"


@dataclasses.dataclass(frozen=True)
class PositionPIDController(Controller):
    """PID on the TRUE position: ``tau = kp*e + ki*int(e) - kd*D + kff*v_ref``, ``e = theta_ref -
    theta`` [deg]. The derivative acts on the measurement, not the error (no kick when the
    reference moves), filtered: ``D`` is the velocity through a first-order low-pass of time
    constant ``tf`` [s] (``tf = 0``: the unfiltered velocity). ``kff`` [N*m*s/deg] feeds the
    reference's velocity forward; ``kff = kd`` with ``tf = 0`` is a PID with its derivative on the
    error. Gains: kp in N*m/deg, ki in N*m/(deg*s), kd and kff in N*m*s/deg. The position reference
    is the excitation's :meth:`Excitation.theta_ref` (the integral of its velocity reference from 0).
    """

    kp: float = 40.0
    ki: float = 160.0
    kd: float = 3.2
    tf: float = 0.002
    kff: float = 0.0
    kind: ClassVar[str] = "position_pid"

    @classmethod
    def tuned(cls, J: float, bandwidth_hz: float = 3.0, zeta: float = 0.8, tf: float = 0.002,
              feedforward: bool = True) -> "PositionPIDController":
        """Gains placing the rigid joint's poles (friction left out) at natural frequency
        ``bandwidth_hz`` and damping ``zeta``: kp = J*w^2, kd = 2*zeta*w*J, ki = kp*w/4; ``kff = kd``
        when ``feedforward``."""
        w = 2 * math.pi * bandwidth_hz
        kp, kd = J * w * w, 2 * zeta * w * J
        return cls(kp=kp, ki=kp * w / 4, kd=kd, tf=tf, kff=kd if feedforward else 0.0)


@dataclasses.dataclass(frozen=True)
class Sensors:
    """Sampling and measurement noise: ``fs`` [Hz]; torque noise std [N*m]; velocity noise std
    [deg/s]; position quantisation step [deg] (0: none); ``velocity_column`` False leaves the
    velocity out (a position-only encoder), ``position_column`` False the position (a tachometer
    only); the recording then derives the missing one.

    Torque-noise colour: ``torque_noise_ar`` in [0, 1) makes the noise an AR(1) sequence
    ``n[k] = phi*n[k-1] + sqrt(1 - phi^2)*torque_noise*w[k]`` (``w`` white, unit variance; the first
    sample from the stationary law), so its lag-1 autocorrelation is ``phi`` and its std
    ``torque_noise``. ``torque_noise_hz`` > 0 states the same by a first-order low-pass corner
    [Hz] instead: ``phi = exp(-2*pi*torque_noise_hz/fs)`` (a drive's averaged or filtered current).
    Both 0: white. At most one of the two may be set."""

    fs: float = 200.0
    torque_noise: float = 0.08
    velocity_noise: float = 0.003
    quantisation: float = 0.0005
    velocity_column: bool = True
    position_column: bool = True
    torque_noise_hz: float = 0.0
    torque_noise_ar: float = 0.0

    def __post_init__(self):
        if not (self.velocity_column or self.position_column):
            raise ValueError("Sensors: at least one of velocity_column and position_column must be True")
        if not 0.0 <= self.torque_noise_ar < 1.0:
            raise ValueError(f"Sensors: torque_noise_ar must be in [0, 1), got {self.torque_noise_ar}")
        if self.torque_noise_ar > 0 and self.torque_noise_hz > 0:
            raise ValueError("Sensors: give the torque noise's colour by torque_noise_ar or torque_noise_hz, not both")

    @property
    def ar_coefficient(self) -> float:
        """The torque noise's AR(1) coefficient (lag-1 autocorrelation); 0 for white noise."""
        if self.torque_noise_hz > 0:
            return float(np.exp(-2.0 * np.pi * self.torque_noise_hz / self.fs))
        return float(self.torque_noise_ar)


# ---------------------------------------------------------------------------------------------
# Excitations: velocity references v_ref(t) [deg/s] with their breakpoints


class Excitation:
    """A velocity reference. ``v_ref(t)``, ``duration`` [s] and ``breakpoints`` (times where the
    reference or its derivative jumps; the integrator restarts there)."""

    duration: float
    id: ClassVar[str] = "excitation"

    def v_ref(self, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def theta_ref(self, t):
        """The position reference [deg], the integral of :meth:`v_ref` from 0, where it has a closed
        form; None: a position loop integrates the velocity reference with the plant's state."""
        return None

    def breakpoints(self):
        return []


def _smoothstep(w):
    w = np.clip(w, 0.0, 1.0)
    return w * w * (3 - 2 * w)


@dataclasses.dataclass(frozen=True)
class Staircase(Excitation):
    """Velocity staircase: every speed in ``speeds`` out (+) and back (-), ``dwell`` s per level,
    ``transition`` s smoothstep between levels (0 = sharp steps), the schedule ``repeats`` times,
    each repeat in its own random order (``seed``). Issue #20's recording: the defaults (288 s)."""

    speeds: tuple = tuple(float(x) for x in np.round(np.logspace(-2, np.log10(4.0), 8), 4))
    dwell: float = 9.0
    transition: float = 0.5
    repeats: int = 2
    seed: int = 0
    id: ClassVar[str] = "staircase"

    def levels(self):
        rng = np.random.default_rng(self.seed)
        out = []
        for k in range(self.repeats):
            order = list(self.speeds) if k == 0 else list(rng.permutation(self.speeds))
            for s in order:
                out += [s, -s]
        return np.array(out, float)

    @property
    def duration(self):
        return self.dwell * len(self.levels())

    def v_ref(self, t):
        lv = self.levels()
        t = np.asarray(t, float)
        k = np.clip((t // self.dwell).astype(int), 0, len(lv) - 1)
        prev = np.where(k > 0, lv[np.maximum(k - 1, 0)], 0.0)
        if self.transition <= 0:
            return lv[k]
        w = _smoothstep((t - k * self.dwell) / self.transition)
        return prev + (lv[k] - prev) * w

    def breakpoints(self):
        n = len(self.levels())
        bp = [k * self.dwell for k in range(1, n)]
        if self.transition > 0:
            bp += [k * self.dwell + self.transition for k in range(n)]
        return sorted(bp)


@dataclasses.dataclass(frozen=True)
class SineSweep(Excitation):
    """Velocity chirp ``amplitude*sin(phase(t))`` from ``f0`` to ``f1`` Hz (log sweep) plus a slow
    drift ``bias`` [deg/s], so that the position wanders over a range; 0.5 s fade in."""

    amplitude: float = 2.0
    f0: float = 0.05
    f1: float = 2.0
    duration: float = 120.0
    bias: float = 0.3
    id: ClassVar[str] = "sine_sweep"

    def v_ref(self, t):
        t = np.asarray(t, float)
        k = math.log(self.f1 / self.f0) / self.duration
        ph = 2 * np.pi * self.f0 * np.expm1(k * t) / k
        fade = _smoothstep(t / 0.5)
        return fade * (self.amplitude * np.sin(ph) + self.bias * np.sin(2 * np.pi * t / self.duration))


@functools.lru_cache(maxsize=64)
def _multisine_parts(amplitude, f0, f1, n, duration):
    f = np.logspace(np.log10(f0), np.log10(f1), n)
    ph = -np.pi * np.arange(1, n + 1) * np.arange(n) / n
    tt = np.linspace(0, duration, 20001)
    peak = np.max(np.abs(np.sum(np.sin(2 * np.pi * f[:, None] * tt + ph[:, None]), 0)))
    return f, ph, amplitude / peak


@dataclasses.dataclass(frozen=True)
class Multisine(Excitation):
    """Sum of ``n`` velocity sines, log-spaced from ``f0`` to ``f1`` Hz, Schroeder phases, scaled to
    peak ``amplitude`` [deg/s]; 0.5 s fade in."""

    amplitude: float = 2.0
    f0: float = 0.02
    f1: float = 1.5
    n: int = 12
    duration: float = 120.0
    id: ClassVar[str] = "multisine"

    def _parts(self):
        # computed once per parameter set: the right-hand side asks for the reference at every step
        return _multisine_parts(self.amplitude, self.f0, self.f1, self.n, self.duration)

    def v_ref(self, t):
        f, ph, s = self._parts()
        t = np.asarray(t, float)
        v = s * np.sum(np.sin(2 * np.pi * f[:, None] * np.atleast_1d(t) + ph[:, None]), 0)
        return (_smoothstep(t / 0.5) * v).reshape(np.shape(t))


@dataclasses.dataclass(frozen=True)
class PositionSineExcitation(Excitation):
    """Position sine of ``amplitude`` [deg] at ``frequency`` [Hz], as a velocity reference (the paper's
    sine-tracking runs: 3 deg at 0.4 Hz)."""

    amplitude: float = 3.0
    frequency: float = 0.4
    duration: float = 30.0
    id: ClassVar[str] = "position_sine"

    def v_ref(self, t):
        w = 2 * np.pi * self.frequency
        return self.amplitude * w * np.cos(w * np.asarray(t, float))

    def theta_ref(self, t):
        return self.amplitude * np.sin(2 * np.pi * self.frequency * np.asarray(t, float))


def _min_jerk(w):
    """Minimum-jerk profile 10w^3 - 15w^4 + 6w^5 on [0, 1] and its derivative (zero velocity and
    acceleration at both ends)."""
    w = np.clip(w, 0.0, 1.0)
    return w ** 3 * (10 - 15 * w + 6 * w * w), 30 * w * w * (1 - w) ** 2


@dataclasses.dataclass(frozen=True)
class PointToPoint(Excitation):
    """Point-to-point moves with dwells: from 0, the position reference moves to each set point of
    ``amplitudes`` [deg] in turn along a minimum-jerk profile lasting ``move_time`` [s], then holds
    it for ``dwell`` [s]; the schedule ``repeats`` times. Velocity and acceleration are continuous;
    the jerk jumps at the start and end of every move (the breakpoints)."""

    amplitudes: tuple = (2.0, -2.0, 4.0, 0.0, -4.0, 1.0)
    move_time: float = 2.0
    dwell: float = 3.0
    repeats: int = 1
    id: ClassVar[str] = "point_to_point"

    def _targets(self):
        return np.array(list(self.amplitudes) * self.repeats, float)

    @property
    def duration(self):
        return (self.move_time + self.dwell) * len(self._targets())

    def _segment(self, t):
        tg = self._targets()
        starts = np.concatenate([[0.0], tg[:-1]])
        period = self.move_time + self.dwell
        t = np.asarray(t, float)
        k = np.clip((t // period).astype(int), 0, len(tg) - 1)
        p, dp = _min_jerk((t - k * period) / self.move_time)
        return starts[k], tg[k] - starts[k], p, dp

    def theta_ref(self, t):
        a, d, p, _ = self._segment(t)
        return a + d * p

    def v_ref(self, t):
        _, d, _, dp = self._segment(t)
        return d * dp / self.move_time

    def breakpoints(self):
        period = self.move_time + self.dwell
        n = len(self._targets())
        return sorted([k * period for k in range(1, n)] + [k * period + self.move_time for k in range(n)])


# ---------------------------------------------------------------------------------------------
# Effects


@dataclasses.dataclass(frozen=True)
class Effect:
    """Base of the effects; each hooks into the plant's right-hand side in one of a few places."""

    id: ClassVar[str] = "effect"

    def load_torque(self, t, theta, v):
        """An extra resisting torque on the joint [N*m]."""
        return 0.0

    def friction_scale(self, t, t_mid):
        return 1.0


@dataclasses.dataclass(frozen=True)
class GravityEffect(Effect):
    amplitude: float = 0.15  # N*m
    phase: float = -0.3  # rad; G = A*sin(theta[rad] + phase)
    id: ClassVar[str] = "gravity"

    def load_torque(self, t, theta, v):
        return self.amplitude * np.sin(theta * DEG + self.phase)


@dataclasses.dataclass(frozen=True)
class AsymmetryEffect(Effect):
    """Friction offset + dsigma2*|v|: Fc is Fc+offset moving positive, Fc-offset negative."""

    offset: float = 0.06  # N*m (5 % of Fc)
    dsigma2: float = 0.0  # N*m*s/deg
    id: ClassVar[str] = "asymmetry"

    def load_torque(self, t, theta, v):
        return self.offset + self.dsigma2 * abs(v)


@dataclasses.dataclass(frozen=True)
class PositionRippleEffect(Effect):
    amplitude: float = 0.07  # N*m
    period: float = 5.0  # deg
    phase: float = 1.0
    id: ClassVar[str] = "position_ripple"

    def load_torque(self, t, theta, v):
        return self.amplitude * np.sin(2 * np.pi * theta / self.period + self.phase)


@dataclasses.dataclass(frozen=True)
class ThermalDriftEffect(Effect):
    """The whole friction torque scaled by ``1 + rate*(t - t_mid)`` [1/s]."""

    rate: float = -1e-4
    id: ClassVar[str] = "thermal_drift"

    def friction_scale(self, t, t_mid):
        return 1.0 + self.rate * (t - t_mid)


@dataclasses.dataclass(frozen=True)
class StribeckShapeEffect(Effect):
    delta: float = 1.0
    id: ClassVar[str] = "stribeck_shape"


@dataclasses.dataclass(frozen=True)
class LoadDependentEffect(Effect):
    """Extra friction ``mu*|J*a|*tanh(v/v_eps)`` (solved exactly: the acceleration depends on it)."""

    mu: float = 0.2
    v_eps: float = 0.02
    id: ClassVar[str] = "load_dependent"


@dataclasses.dataclass(frozen=True)
class ComplianceEffect(Effect):
    """Two-mass joint: ``J_load`` of the total ``J`` sits behind a spring of natural frequency ``fn``
    [Hz] and damping ratio ``zeta``; friction acts on the motor side."""

    fn: float = 3.0
    zeta: float = 0.05
    J_load: float = 0.01
    id: ClassVar[str] = "compliance"


@dataclasses.dataclass(frozen=True)
class BacklashEffect(Effect):
    """A dead band of total ``width`` [deg] in front of ``share`` of the friction, which has its own
    bristle state and is felt only while the band is closed."""

    width: float = 0.01
    share: float = 0.05
    id: ClassVar[str] = "backlash"


EFFECTS = {c.id: c for c in (GravityEffect, AsymmetryEffect, PositionRippleEffect, ThermalDriftEffect,
                             StribeckShapeEffect, LoadDependentEffect, ComplianceEffect, BacklashEffect)}


# Effects outside the diagnose candidates: physics none of the eight candidates writes down.


@dataclasses.dataclass(frozen=True)
class ActuatorLagEffect(Effect):
    """The drive's torque reaches the joint through a first-order lag of time constant ``T`` [s]
    (a slow current loop): ``T*d(tau_j)/dt = tau_cmd - tau_j``, the joint driven by ``tau_j``, while
    the recording holds the command ``tau_cmd``. The recorded torque then exceeds the joint's
    ``J*a + F`` by ``tau_cmd - tau_j``, about ``T*d(tau_cmd)/dt``: it follows the torque's rate.
    Strength: ``T``."""

    T: float = 0.005
    id: ClassVar[str] = "actuator_lag"


@dataclasses.dataclass(frozen=True)
class QuadraticDragEffect(Effect):
    """Fluid (windage, churning) drag ``c*v*|v|`` [N*m], ``c`` in N*m*s^2/deg^2: quadratic in the
    speed, where the paper's viscous term is linear. Strength: ``c``."""

    c: float = 0.002
    id: ClassVar[str] = "quadratic_drag"

    def load_torque(self, t, theta, v):
        return self.c * v * abs(v)


@dataclasses.dataclass(frozen=True)
class TorqueDependentFrictionEffect(Effect):
    """Friction growing with the torque the transmission carries: the mesh (gear, screw) passes the
    motor's torque less the torque that accelerates the rotor in front of it, ``tau_t = tau_m -
    rotor_share*J*a``, and its contact force grows with it, adding ``mu*|tau_t|*tanh(v/v_eps)``.
    ``tau_t`` holds the friction and load the mesh drives, not only the load's inertial torque: it
    is there at constant speed (``mu*|F|``) and is larger accelerating than braking. (The
    ``load_dependent`` candidate's extra friction is ``mu*|J*a|*sign(v)``: zero at constant speed,
    the same accelerating and braking.) Solved exactly (the acceleration depends on it).
    Strength: ``mu``."""

    mu: float = 0.03
    rotor_share: float = 0.5
    v_eps: float = 0.02
    id: ClassVar[str] = "torque_dependent_friction"


@dataclasses.dataclass(frozen=True)
class TimeDisturbanceEffect(Effect):
    """A slow periodic torque in time, not tied to the position or the motion (a cable pulled by a
    neighbouring axis, a pump's pressure, mains-locked hum through a slow filter):
    ``amplitude*sin(2*pi*frequency*t + phase)`` [N*m], ``frequency`` [Hz]. Strength: ``amplitude``."""

    amplitude: float = 0.05
    frequency: float = 0.13
    phase: float = 0.4
    id: ClassVar[str] = "time_disturbance"

    def load_torque(self, t, theta, v):
        return self.amplitude * math.sin(2 * math.pi * self.frequency * t + self.phase)


OUTSIDE_EFFECTS = {c.id: c for c in (ActuatorLagEffect, QuadraticDragEffect, TorqueDependentFrictionEffect,
                                     TimeDisturbanceEffect)}


# ---------------------------------------------------------------------------------------------
# Simulation


@dataclasses.dataclass
class GeneratedRecording:
    """Sampled measurements (``velocity`` None when the sensors give no velocity column), the true
    signals and the settings that made them. Units: s, deg, deg/s, N*m.

    ``torque_noise_std``: the std of the torque noise actually added to this recording (its
    samples: ``true["torque_noise"]``), the value a noise-floor estimate should come out at.
    ``position_ref``: the position reference under a :class:`PositionPIDController` (None otherwise).
    ``true["applied_torque"]``: the torque that reached the joint (the command, except behind an
    :class:`ActuatorLagEffect`)."""

    time: np.ndarray
    position: np.ndarray | None
    velocity: np.ndarray | None
    torque: np.ndarray
    velocity_ref: np.ndarray
    true: dict
    settings: dict
    position_ref: np.ndarray | None = None
    torque_noise_std: float = float("nan")

    def columns(self) -> dict:
        """CSV columns in the project's recording format (``time_s, position_deg, ...``); without a
        velocity sensor there is no ``velocity_deg_s`` column."""
        c = {"time_s": self.time}
        if self.position is not None:
            c["position_deg"] = self.position
        if self.velocity is not None:
            c["velocity_deg_s"] = self.velocity
        c = c | {"torque_nm": self.torque, "velocity_ref_deg_s": self.velocity_ref}
        if self.position_ref is not None:
            c["position_ref_deg"] = self.position_ref
        return c

    def to_recording(self):
        """A :class:`lugre_jax.io.Recording` (imported lazily: this module stays independent); without
        a velocity sensor the recording derives the velocity from the position (and says so)."""
        from ..io import recording_from_arrays

        return recording_from_arrays(
            self.time, self.position, self.velocity, self.torque,
            source=f"testing.generate({self.settings['excitation']}, {self.settings['effects']})",
            extra={"velocity_ref_deg_s": self.velocity_ref}
            | ({} if self.position_ref is None else {"position_ref_deg": self.position_ref}),
            meta={"generator": "lugre_jax.testing"})


class _RHS:
    """Closed-loop right-hand side. State: theta, omega, z, xi (the controller's integral: of the
    velocity error under a :class:`VelocityPIController`, of the position error under a
    :class:`PositionPIDController`)
    [+ e, de (compliance)] [+ theta_load, z_load (backlash)] [+ tau_j (actuator lag)]
    [+ D (position PID's filtered velocity)] [+ theta_ref (position PID, reference integrated)].

    A backlash makes the plant hybrid: ``mode`` is 0 while the gap is open (the load and its bristles
    hold still) and +1/-1 while the motor pushes the load forward/back. The mode is switched by
    events (:meth:`events`), never decided from the state inside the right-hand side: engaged, the
    gap stays at +-width/2 only to the integrator's tolerance, and a test of it there chatters
    between the modes and stalls the integrator at vanishing steps."""

    def __init__(self, plant, ctrl, exc, effects, t_mid):
        self.p, self.ctrl, self.exc, self.t_mid = plant, ctrl, exc, t_mid
        self.effects = effects
        d = {e.id: e for e in effects}
        if len(d) != len(effects):
            raise ValueError(f"effects: each kind at most once, got {[e.id for e in effects]}")
        self.comp = d.get("compliance")
        self.back = d.get("backlash")
        self.loaddep = d.get("load_dependent")
        self.torquedep = d.get("torque_dependent_friction")
        self.lag = d.get("actuator_lag")
        if self.loaddep is not None and self.torquedep is not None:
            raise ValueError("effects: load_dependent and torque_dependent_friction cannot be combined")
        delta = d["stribeck_shape"].delta if "stribeck_shape" in d else plant.delta
        self.plant_g = dataclasses.replace(plant, delta=delta).g
        self.pos = isinstance(ctrl, PositionPIDController)
        n = 4 + (2 if self.comp else 0)
        self.kb = n  # index of theta_load
        n += 2 if self.back else 0
        self.kl = n  # index of the lagged torque
        n += 1 if self.lag else 0
        self.kd = n  # index of the position PID's filtered velocity
        self.filtered = self.pos and ctrl.tf > 0
        n += 1 if self.filtered else 0
        self.kr = n  # index of the integrated position reference
        self.integrate_ref = self.pos and exc.theta_ref(0.0) is None
        n += 1 if self.integrate_ref else 0
        self.n = n
        self.mode = 0  # backlash: the load starts in the middle of the gap

    def theta_ref(self, t, y):
        return float(y[self.kr]) if self.integrate_ref else float(self.exc.theta_ref(t))

    def command(self, t, y):
        """The controller's torque command, the velocity reference and the controller's rates
        (integral, filtered velocity)."""
        th, om, xi = y[0], y[1], y[3]
        vr = float(self.exc.v_ref(t))
        c = self.ctrl
        if not self.pos:
            return c.kp * (vr - om) + c.ki * xi, vr, vr - om, None
        D = y[self.kd] if self.filtered else om
        e = self.theta_ref(t, y) - th
        u = c.kp * e + c.ki * xi - c.kd * D + c.kff * vr
        return u, vr, e, ((om - D) / c.tf if self.filtered else None)

    def events(self):
        """Terminal events ending the current backlash mode (None without a backlash)."""
        if self.back is None:
            return None
        half, kb, m = 0.5 * self.back.width, self.kb, self.mode
        if m == 0:  # open: the gap closes on either side
            def close_fwd(t, y):
                return y[0] - y[kb] - half

            def close_back(t, y):
                return y[0] - y[kb] + half

            close_fwd.terminal, close_fwd.direction = True, 1.0
            close_back.terminal, close_back.direction = True, -1.0
            return [close_fwd, close_back]
        s = float(np.sign(m))
        if abs(m) == 1:  # engaged: the motor stops (it can push the load, not pull it)
            def stop(t, y):
                return y[1]

            stop.terminal, stop.direction = True, -s
            return [stop]

        # pinned: the motor's push drops to zero (it backs off) or overcomes the load's friction
        def back_off(t, y):
            return s * self._net(t, y, 0)

        def push_through(t, y):
            return s * self._net(t, y, int(s))

        back_off.terminal, back_off.direction = True, -1.0
        push_through.terminal, push_through.direction = True, 1.0
        return [back_off, push_through]

    def _net(self, t, y, mode):
        """Net torque on the motor at rest (velocity 0) in ``mode`` (0 open, +-1 engaged)."""
        y = np.array(y, float)
        y[1] = 0.0
        return self.parts(t, y, mode)[2]

    def switch(self, t, y, event):
        """The mode after the current one's ``event`` (index into :meth:`events`), and the state
        made consistent with it.

        At a stop of the engaged motor the next mode follows the forces at rest (Filippov): backing
        off if its push without the load's friction is already reversed; going on if its push with
        that friction is still forward; otherwise pinned at rest against the load (velocity held at 0,
        the load's bristles carrying the difference) until one of those changes: left to the open
        and engaged modes alone, that case chatters between them at vanishing steps."""
        y = np.array(y, float)
        half, kb, m = 0.5 * self.back.width, self.kb, self.mode
        if m == 0:
            self.mode = 1 if y[0] - y[kb] > 0 else -1
            return y
        s = int(np.sign(m))
        y[kb] = y[0] - s * half  # the load at the gap's edge exactly
        y[1] = 0.0
        if abs(m) == 2:  # pinned: the event says which way it is left
            self.mode = s if event == 1 else 0
        elif s * self._net(t, y, s) > 0:
            self.mode = s
        elif s * self._net(t, y, 0) > 0:
            self.mode = 2 * s
        else:
            self.mode = 0
        return y

    def _bristle(self, z, v):
        p = self.p
        g = self.plant_g(v)
        dz = v - p.sigma0 * abs(v) * z / g
        return p.sigma0 * z + p.sigma1 * dz + p.sigma2 * v, dz

    def parts(self, t, y, mode=None):
        p = self.p
        th, om, z, xi = y[:4]
        u, vr, dxi, dD = self.command(t, y)
        applied = y[self.kl] if self.lag is not None else u
        scale = 1.0
        load = 0.0
        for e in self.effects:
            scale *= e.friction_scale(t, self.t_mid)
            load += e.load_torque(t, th, om)
        F, dz = self._bristle(z, om)
        extra = {"dxi": dxi, "dD": dD, "vr": vr, "applied": applied}
        if self.back is not None:
            b = self.back
            zl = y[self.kb + 1]
            mode = self.mode if mode is None else mode
            engaged = abs(mode) == 1
            vl = om if engaged else 0.0
            Fl, dzl = self._bristle(zl, vl)
            F = (1 - b.share) * F + (b.share * Fl if engaged else 0.0)
            extra["back"] = (vl, dzl)
        F = scale * F
        J_motor = p.J
        spring = 0.0
        if self.comp is not None:
            c = self.comp
            e, de = y[4], y[5]
            w = 2 * np.pi * c.fn
            # load-minus-motor angle e: the load J_load*(a_m + e'') = -J_load*(w^2 e + 2 zeta w e');
            # the spring pushes the motor the other way (action and reaction), so the motor feels
            # +J_load*(w^2 e + 2 zeta w e') = -J_load*a_load and u - F = J_motor*a_m + J_load*a_load
            spring = c.J_load * (w * w * e + 2 * c.zeta * w * de)  # torque the load puts on the motor
            J_motor = p.J - c.J_load
        R = applied - F - load + spring
        if self.loaddep is not None:
            s = self.loaddep.mu * np.tanh(om / self.loaddep.v_eps)
            # J*a + mu*|J*a|*tanh(v/v_eps) = R: solve for J*a on the branch of sign(R)
            Ja = R / (1.0 + s * np.sign(R)) if R != 0 else 0.0
            acc = Ja / J_motor
        elif self.torquedep is not None:
            td = self.torquedep
            s = td.mu * np.tanh(om / td.v_eps)
            rr = td.rotor_share * p.J / J_motor
            # x = J_motor*a solves x + s*|applied - rr*x| = R; the left side increases with x
            # (|s|*rr < 1), so the root is on the branch whose sign it satisfies
            x = (R - s * applied) / (1.0 - s * rr)
            if applied - rr * x < 0:
                x = (R + s * applied) / (1.0 + s * rr)
            acc = x / J_motor
        else:
            acc = R / J_motor
        if self.back is not None and abs(mode) == 2:
            # pinned at rest against the load: the load's held friction takes the net torque
            return u, vr, 0.0, dz, extra, F + load + R
        return u, vr, acc, dz, extra, F + load

    def __call__(self, t, y):
        th, om, z, xi = y[:4]
        u, vr, acc, dz, extra, _ = self.parts(t, y)
        out = [om, acc, dz, extra["dxi"]]
        if self.comp is not None:
            c = self.comp
            w = 2 * np.pi * c.fn
            e, de = y[4], y[5]
            out += [de, -w * w * e - 2 * c.zeta * w * de - acc]
        if self.back is not None:
            out += list(extra["back"])
        if self.lag is not None:
            out.append((u - y[self.kl]) / self.lag.T)
        if self.filtered:
            out.append(extra["dD"])
        if self.integrate_ref:
            out.append(vr)
        return out


def generate(excitation: Excitation | None = None, effects=(), plant: Plant | None = None,
             controller: VelocityPIController | PositionPIDController | None = None,
             sensors: Sensors | None = None, seed: int = 0,
             method: str = "LSODA", rtol: float = 1e-9, atol: float = 1e-11) -> GeneratedRecording:
    """Simulate the closed loop from rest and sample it; see the module docstring.

    ``effects``: instances of the classes in :data:`EFFECTS` and :data:`OUTSIDE_EFFECTS` (each kind
    at most once). ``controller``: a :class:`VelocityPIController` (default) or a
    :class:`PositionPIDController`; either
    follows any excitation. ``seed``: measurement noise. The integration is restarted at every
    breakpoint of the excitation; ``rtol``/``atol`` apply to the state (deg, deg/s, deg, deg*s).
    Raises ``RuntimeError`` if the integrator fails.
    """
    exc = excitation if excitation is not None else Staircase()
    plant = plant or Plant()
    pi = controller or VelocityPIController()
    sens = sensors or Sensors()
    effects = tuple(effects)
    T = float(exc.duration)
    # arange's last sample can overshoot T by a rounding error (solve_ivp refuses it)
    ts = np.minimum(np.arange(0.0, T + 0.5 / sens.fs, 1.0 / sens.fs), T)
    rhs = _RHS(plant, pi, exc, effects, 0.5 * T)
    y = np.zeros(rhs.n)
    edges = [0.0] + [b for b in exc.breakpoints() if 0 < b < T] + [T]
    Y = np.empty((ts.size, rhs.n))
    modes = np.zeros(ts.size, int)
    switches = 0
    for a, b in zip(edges[:-1], edges[1:]):
        ta = a
        while True:
            sel = (ts >= ta) & ((ts < b) | (b == T))
            if ta > a:  # a sample at the switch itself came from the previous mode's solve
                sel &= ts > ta
            sol = solve_ivp(rhs, (ta, b), y, method=method, t_eval=ts[sel], rtol=rtol, atol=atol,
                            max_step=min(0.05, b - ta), events=rhs.events())
            if not sol.success:
                raise RuntimeError(f"solve_ivp failed on [{ta}, {b}] s: {sol.message}")
            got = np.flatnonzero(sel)[:np.size(sol.t)]
            if got.size:
                Y[got] = np.asarray(sol.y).T
                modes[got] = rhs.mode
            if sol.status == 1:  # a backlash event: switch the mode and go on from there
                switches += 1
                if switches > 100 * ts.size:
                    raise RuntimeError(f"backlash: more than {switches} mode switches by t = {ta} s")
                ev = next(i for i, te in enumerate(sol.t_events) if te.size)
                ta = float(sol.t_events[ev][0])
                y = rhs.switch(ta, sol.y_events[ev][0], ev)
                continue
            y = sol.y[:, -1] if np.size(sol.t) and sol.t[-1] == b else _endpoint(rhs, ta, b, y, method, rtol, atol)
            break
    u = np.empty(ts.size)
    vr = np.empty(ts.size)
    acc = np.empty(ts.size)
    fr = np.empty(ts.size)
    for i, (t, yy) in enumerate(zip(ts, Y)):
        u[i], vr[i], acc[i], _, _, fr[i] = rhs.parts(t, yy, modes[i])
    thr = np.array([rhs.theta_ref(t, yy) for t, yy in zip(ts, Y)]) if rhs.pos else None
    applied = Y[:, rhs.kl] if rhs.lag is not None else u
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(ts.size)
    phi = sens.ar_coefficient
    if phi > 0:
        from scipy.signal import lfilter

        # stationary AR(1) of unit variance: the first sample drawn from the stationary law
        e[0] /= np.sqrt(1.0 - phi ** 2)
        e = lfilter([np.sqrt(1.0 - phi ** 2)], [1.0, -phi], e)
    noise = sens.torque_noise * e
    tau = u + noise
    vel = Y[:, 1] + sens.velocity_noise * rng.standard_normal(ts.size) if sens.velocity_column else None
    pos = Y[:, 0]
    if sens.quantisation > 0:
        pos = sens.quantisation * np.round(pos / sens.quantisation)
    if not sens.position_column:
        pos = None
    eff_torque = u - plant.J * acc - _plain_friction(plant, rhs, ts, Y)
    settings = {"excitation": exc.id, "excitation_params": dataclasses.asdict(exc),
                "effects": [e.id for e in effects], "effect_params": [dataclasses.asdict(e) for e in effects],
                "plant": dataclasses.asdict(plant), "controller_kind": pi.kind,
                "controller": dataclasses.asdict(pi),
                "sensors": dataclasses.asdict(sens), "seed": seed, "method": method, "rtol": rtol, "atol": atol}
    true = {"theta": Y[:, 0], "omega": Y[:, 1], "z": Y[:, 2], "acceleration": acc, "torque": u,
            "applied_torque": applied, "friction_and_load": fr, "effect_torque": eff_torque,
            "torque_noise": noise}
    return GeneratedRecording(ts, pos, vel, tau, vr, true, settings, position_ref=thr,
                              torque_noise_std=float(np.std(noise)))


def _endpoint(rhs, a, b, y, method, rtol, atol):
    sol = solve_ivp(rhs, (a, b), y, method=method, rtol=rtol, atol=atol, max_step=min(0.05, b - a))
    return sol.y[:, -1]


def _plain_friction(plant, rhs, ts, Y):
    """The effect-free joint's friction along the true motion (for the effect's torque): LuGre of
    ``plant`` driven by the true velocity, its z integrated again without the effect."""
    if not any(e.id in ("stribeck_shape", "backlash", "thermal_drift") for e in rhs.effects):
        g = plant.g(Y[:, 1])
        dz = Y[:, 1] - plant.sigma0 * np.abs(Y[:, 1]) * Y[:, 2] / g
        return plant.sigma0 * Y[:, 2] + plant.sigma1 * dz + plant.sigma2 * Y[:, 1]
    from scipy.interpolate import CubicSpline

    vf = CubicSpline(ts, Y[:, 1])

    def f(t, z):
        v = float(vf(t))
        return [v - plant.sigma0 * abs(v) * z[0] / plant.g(v)]

    sol = solve_ivp(f, (ts[0], ts[-1]), [0.0], method="LSODA", t_eval=ts, rtol=1e-9, atol=1e-12,
                    max_step=0.05)
    z = sol.y[0]
    v = Y[:, 1]
    return plant.sigma0 * z + plant.sigma1 * (v - plant.sigma0 * np.abs(v) * z / plant.g(v)) + plant.sigma2 * v
