"""Synthetic joint recordings with a known (possibly concealed) missing effect, by inverse dynamics.

A smooth trajectory theta(t) is prescribed -- velocity plateaus at +-0.05 ... +-2 deg/s joined by
ramps at a constant +-1.5 deg/s^2 (smooth onset and release), with directions chosen so that the
position slowly sweeps a range, so speed, direction, position, acceleration and time are not
confounded. Along it the LuGre state z is integrated
(exact-exponential update on a grid ``n_sub`` times finer than the samples), the torque is
``J*a + F_LuGre(z, v) + effect + noise`` (Li et al., Electronics 2020, 9, 284, eq. 1-2 and 9), and
the result is sampled. The effect is one of the candidate physics of :mod:`._physics`, evaluated by
the same module the diagnose tool uses, but on the fine grid.

Units: the paper's (s, deg, deg/s, N*m).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..friction import LuGre
from ..io import Recording, recording_from_arrays
from . import _physics as ph
from ._model import JointModel, Kinematics, predict

SPEEDS = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0)  # deg/s
NOISE_STD = 0.05  # N*m, per-sample torque noise of the synthetic recordings
TRUE_J = 0.128  # N*m*s^2/deg (paper, eq. 18)


def true_friction() -> LuGre:
    """Ground-truth LuGre of the synthetic joint: Table 1 orders of magnitude, vs moved to 0.2 deg/s
    so that the plateaus sample the Stribeck region; sigma0, sigma1 of Table 2's order."""
    return LuGre(Fc=1.0, Fs=1.6, vs=0.2, sigma2=0.5, sigma0=100.0, sigma1=2.0, require_passive=False)


ACCEL = 1.5  # deg/s^2, acceleration of every speed change
CORNER = 0.15  # s, smooth onset/release of the acceleration


def _septic(w):
    """Septic smoothstep S(w) and its integral over [0, w]: C3 at both ends."""
    S = -20 * w**7 + 70 * w**6 - 84 * w**5 + 35 * w**4
    I = -2.5 * w**8 + 10 * w**7 - 14 * w**6 + 7 * w**5
    return S, I


def _ramp(tau, dv, accel=ACCEL, corner=CORNER):
    """Velocity change and acceleration ``tau`` seconds into a speed change of ``dv``.

    The acceleration rises smoothly (septic, ``corner`` s) to +-``accel``, holds, and falls back, so
    most of the change happens at one acceleration level: an effect that scales with |a| then has its
    peak close to its RMS over the ramp (the concealed level is set by the peak). Changes smaller
    than ``accel*corner`` use a lower level with no hold. Returns (dv(tau), a(tau), duration)."""
    A = min(accel, abs(dv) / corner) * np.sign(dv)
    hold = max(abs(dv) / accel - corner, 0.0)
    T = 2 * corner + hold
    tau = np.clip(tau, 0.0, T)
    w1 = np.clip(tau / corner, 0, 1)
    w3 = np.clip((tau - corner - hold) / corner, 0, 1)
    S1, I1 = _septic(w1)
    S3, I3 = _septic(w3)
    a = A * (S1 - S3)
    vel = A * (corner * I1 + np.clip(tau - corner, 0, hold) + (corner * w3 - corner * I3))
    return vel, a, T


def velocity_profile(seed: int, duration: float = 400.0, dt_fine: float = 1e-3,
                     speeds=SPEEDS, plateau=(1.0, 3.5), sweep=(0.0, 120.0), burst=0.25):
    """(t, v, a) on a fine grid: random plateaus joined by constant-acceleration ramps, the position
    sweeping ``sweep``.

    Every speed change runs at +-``ACCEL`` (smooth 0.15-s onset and release, which also excites an
    elastic mode), so that about a quarter of the time the joint accelerates: load-dependent effects
    are then seen often, not only in brief peaks. The direction of each plateau heads toward a target
    that moves slowly between the ends of ``sweep``; three plateaus in ten go the other way, so every
    speed is seen in both directions at many positions; a quarter of the plateaus are replaced by a
    burst of four short low-speed plateaus of alternating direction, so that reversals are frequent.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + dt_fine / 2, dt_fine)
    v = np.zeros_like(t)
    a = np.zeros_like(t)
    T_sweep = duration / 2
    lo, hi = sweep
    pos, v_prev, t0 = 0.5 * (lo + hi), 0.0, 0.0
    segs = []
    while t0 < duration:
        frac = (t0 % T_sweep) / T_sweep
        target = lo + (hi - lo) * (2 * frac if frac < 0.5 else 2 - 2 * frac)
        sgn = 1.0 if target > pos else -1.0
        if rng.random() < 0.3:
            sgn = -sgn
        if rng.random() < burst:
            # a reversal burst: four short plateaus alternating at a low speed, so that reversals
            # (where backlash acts) are frequent without the position stopping its sweep
            sd = float(rng.choice(speeds[:3]))
            plan = [(-sgn if k % 2 == 0 else sgn) * sd for k in range(4)]
            hold = [float(rng.uniform(0.4, 0.8)) for _ in plan]
        else:
            plan, hold = [sgn * float(rng.choice(speeds))], [float(rng.uniform(*plateau))]
        for s, h in zip(plan, hold):
            tr = _ramp(0.0, s - v_prev)[2]
            dur = tr + h
            segs.append((t0, v_prev, s, dur))
            # a ramp whose acceleration profile is symmetric moves (v0 + v1)/2 * its duration
            pos += 0.5 * (v_prev + s) * tr + s * (dur - tr)
            v_prev, t0 = s, t0 + dur
    for t0, v0, v1, dur in segs:
        m = (t >= t0) & (t < t0 + dur)
        dv, am, _ = _ramp(t[m] - t0, v1 - v0)
        v[m] = v0 + dv
        a[m] = am
    return t, v, a


def effect_instance(name: str, strength: float = 1.0):
    """The effect ``name`` at a reference strength times ``strength`` (1 = the default concealed level)."""
    s = strength
    if name == "position_ripple":
        return ph.PositionRipple(0.5 * NOISE_STD * s, 7.5, 1.0)
    if name == "gravity":
        return ph.Gravity(0.5 * NOISE_STD * s, -np.pi / 3, np.pi / 180)  # zero crossing mid-sweep (60 deg)
    if name == "asymmetry":
        return ph.Asymmetry(0.25 * NOISE_STD * s, 0.125 * NOISE_STD * s)
    if name == "thermal_drift":
        return ph.ThermalDrift(-0.04 * s / 400.0)
    if name == "stribeck_shape":
        return ph.StribeckShape(2.0 - 0.5 * s)
    if name == "backlash":
        # wider than the joint's pre-sliding length Fs/sigma0 = 0.016 deg: a narrower gap is not named
        return ph.Backlash(0.025, 0.028 * s)
    if name == "compliance":
        return ph.Compliance(3.0, 0.05, 0.014 * s)
    if name == "load_dependent":
        return ph.LoadDependent(0.2 * s, 0.02)
    raise ValueError(f"unknown effect {name!r}; expected one of {list(ph.CANDIDATES)}")


def make_recording(seed: int, effect: str | None = None, strength: float = 1.0,
                   duration: float = 400.0, fs: float = 100.0, n_sub: int = 10,
                   noise_std: float = NOISE_STD) -> tuple[Recording, dict]:
    """A synthetic recording (paper units) and its ground truth (parameters, effect torque)."""
    dt_fine = 1.0 / (fs * n_sub)
    t, v, a = velocity_profile(seed, duration, dt_fine)
    theta = np.concatenate([[60.0], 60.0 + np.cumsum(0.5 * (v[1:] + v[:-1]) * dt_fine)])
    kin = Kinematics(jnp.asarray(t), jnp.asarray(theta), jnp.asarray(v), jnp.asarray(a),
                     jnp.asarray(np.diff(t)), jnp.asarray(np.diff(theta)), jnp.asarray(0.0))
    base = JointModel(jnp.asarray(TRUE_J), true_friction(), jnp.asarray(0.0))
    tau0 = predict(base, kin)
    eff = None
    tau = tau0
    if effect is not None and effect != "none":
        eff = effect_instance(effect, strength)
        tau = predict(JointModel(base.J, base.friction, base.offset, (eff,)), kin)
    rng = np.random.default_rng(10_000 + seed)
    idx = slice(0, None, n_sub)
    effect_torque = (tau - tau0)[idx]
    y = tau[idx] + noise_std * rng.standard_normal(effect_torque.shape)
    rec = recording_from_arrays(t[idx], theta[idx], v[idx], y, source=f"synthetic(seed={seed}, effect={effect})",
                                meta={"seed": seed, "effect": effect, "strength": strength})
    truth = {"effect": effect or "none", "strength": strength, "noise_std": noise_std,
             "effect_torque": effect_torque, "effect_peak": float(np.max(np.abs(effect_torque))),
             "effect_rms": float(np.sqrt(np.mean(effect_torque ** 2))),
             "effect_module": eff}
    return rec, truth
