"""Dynamic LuGre parameters by the paper's two-step route, Li et al., Electronics 2020, 9, 284,
section 4.2.5: the bristle stiffness ``sigma0`` from a pre-sliding torque step (eq. 16-17,
``sigma0 ~ dF/dtheta``) and the bristle damping ``sigma1`` from eq. (18),
``sigma1 + sigma2 = 1.4*sqrt(J*sigma0)`` (critical-ish damping, ratio 0.7, of the pre-sliding
spring-mass), and the builder that turns an identified static curve into an observer model.

Units: torque N*m, angle deg, sigma0 N*m/deg, sigma1/sigma2 N*m*s/deg, J N*m*s^2/deg.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from .._simulation import FixedStep, System, simulate
from ..control import OpenLoop, VelocitySteps
from ..friction import AbstractFrictionModel, CoulombViscous, LuGre, Segmented, Stribeck
from ..plant import Joint

EQ18_FACTOR = 1.4  # = 2*zeta with zeta = 0.7 (Canudas de Wit / Olsson, the paper's ref. 41)


def sigma1_eq18(J, sigma0, sigma2):
    """Bristle damping [N*m*s/deg] from eq. (18): ``1.4*sqrt(J*sigma0) - sigma2``.

    ``J`` [N*m*s^2/deg], ``sigma0`` [N*m/deg], ``sigma2`` [N*m*s/deg]. May be negative when the
    viscous coefficient alone already over-damps the pre-sliding mode; the caller decides.
    """
    return EQ18_FACTOR * np.sqrt(np.asarray(J) * np.asarray(sigma0)) - np.asarray(sigma2)


def inertia_eq18(sigma0, sigma1, sigma2):
    """The inertia J [N*m*s^2/deg] that makes (sigma0, sigma1, sigma2) satisfy eq. (18)."""
    return ((np.asarray(sigma1) + np.asarray(sigma2)) / EQ18_FACTOR) ** 2 / np.asarray(sigma0)


@dataclasses.dataclass(frozen=True)
class PreslidingResult:
    """A simulated pre-sliding step test (eq. 17) and its ``sigma0`` estimate."""

    sigma0: float  # N*m/deg, dF/dtheta
    step_nm: float  # dF [N*m]
    dtheta_deg: float  # pre-sliding displacement at rest [deg]
    ts: np.ndarray  # s
    theta: np.ndarray  # deg (as measured: with noise/quantisation if requested)
    settled: bool  # velocity at the end below 1e-6 deg/s (the "motion stops" of eq. 17)

    def as_dict(self) -> dict:
        return dict(sigma0_nm_per_deg=self.sigma0, step_nm=self.step_nm, dtheta_deg=self.dtheta_deg,
                    settled=self.settled)


def presliding_step(friction: AbstractFrictionModel, J: float, step_nm: float, *, duration_s: float = 2.0,
                    sample_hz: float = 500.0, encoder_res_deg: float = 0.0, noise_deg: float = 0.0,
                    key=None, settle_s: float = 0.5) -> PreslidingResult:
    """Apply an open-loop torque step ``step_nm`` [N*m] (below breakaway) to a joint of inertia
    ``J`` at rest with ``friction`` and estimate ``sigma0 = dF/dtheta`` (eq. 17) from the final
    displacement (mean over the last ``settle_s`` seconds).

    The measured angle may be quantised to ``encoder_res_deg`` and carry white noise of standard
    deviation ``noise_deg`` (needs ``key``). Raises ValueError if the step breaks the joint away
    (the displacement keeps growing), since eq. (17) then does not apply.
    """
    if not step_nm > 0:
        raise ValueError(f"step_nm must be a positive torque below breakaway, got {step_nm!r}")
    sys_ = System(friction=friction, joint=Joint(J=J), controller=OpenLoop(bias=float(step_nm)),
                  reference=VelocitySteps([0.0]))
    # Fixed steps: the motion is slow and smooth, and this path compiles faster than the adaptive one.
    sol = simulate(sys_, duration_s, sample_hz, stepping=FixedStep())
    if int(sol.result) != 0:
        raise ValueError(f"pre-sliding simulation failed (result {int(sol.result)}); shorten duration_s or the step")
    ts = np.asarray(sol.ts)
    th = np.asarray(sol.theta)
    om = np.asarray(sol.omega)
    if noise_deg > 0:
        if key is None:
            raise ValueError("noise_deg > 0 needs a jax.random key")
        th = th + noise_deg * np.asarray(jax.random.normal(key, th.shape))
    if encoder_res_deg > 0:
        th = np.round(th / encoder_res_deg) * encoder_res_deg
    tail = ts >= ts[-1] - settle_s
    settled = bool(np.max(np.abs(om[tail])) < 1e-6)
    if not settled and abs(np.mean(om[tail])) > 1e-4:
        raise ValueError(
            f"a {step_nm} N*m step broke the joint away (still moving at {np.mean(om[tail]):.3g} deg/s): "
            "use a smaller step, below the static friction"
        )
    dth = float(np.mean(th[tail]))
    return PreslidingResult(float(step_nm / dth), float(step_nm), dth, ts, th, settled)


def lugre_from_static(static: AbstractFrictionModel, sigma0, sigma1, *,
                      require_passive: bool = False) -> AbstractFrictionModel:
    """Give an identified static curve its dynamics: a :class:`LuGre` (from a ``Stribeck`` or
    ``CoulombViscous``) or a ``Segmented`` of LuGres (one ``sigma0``/``sigma1`` per segment, or one
    shared pair). ``CoulombViscous`` (eq. 11) becomes a LuGre with ``Fs = Fc``.

    ``require_passive`` goes to :class:`LuGre`: eq. (18)'s damping ignores passivity, and on a
    pronounced Stribeck curve (the paper's segment 1) it gives a non-passive set, which ``True``
    refuses.
    """
    kw = dict(sigma0=jnp.asarray(sigma0, float), sigma1=jnp.asarray(sigma1, float), require_passive=require_passive)
    if isinstance(static, Segmented):
        n = len(static.segments)
        s0 = np.broadcast_to(np.asarray(sigma0, dtype=np.float64), (n,))
        s1 = np.broadcast_to(np.asarray(sigma1, dtype=np.float64), (n,))
        segs = tuple(lugre_from_static(m, float(a), float(b), require_passive=require_passive)
                     for m, a, b in zip(static.segments, s0, s1))
        return Segmented(segs, static.edges, blend=static.blend)
    if isinstance(static, Stribeck):
        return LuGre(Fc=static.Fc, Fs=static.Fs, vs=static.vs, sigma2=static.sigma2, delta=static.delta, **kw)
    if isinstance(static, CoulombViscous):
        return LuGre(Fc=static.Fc, Fs=static.Fc, vs=jnp.asarray(1.0), sigma2=static.sigma2, **kw)
    if isinstance(static, LuGre):
        return LuGre(Fc=static.Fc, Fs=static.Fs, vs=static.vs, sigma2=static.sigma2, delta=static.delta, **kw)
    raise ValueError(f"cannot build a LuGre model from {type(static).__name__}; pass Stribeck, CoulombViscous, "
                     "LuGre or Segmented")
