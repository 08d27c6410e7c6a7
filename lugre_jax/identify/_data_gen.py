"""Synthetic steady-state friction data shaped like the measurements of Li et al., Electronics 2020,
9, 284, section 4.2.2 / Fig. 3b (the paper's measurements are not public).

The paper measured the joint at constant velocities in 0-1.5 deg/s, recorded 30 torques per
set-point and averaged them, 92 sets in all; in the low-velocity segment it measured while
accelerating and while decelerating, the static friction being much higher when starting than when
stopping, the two curves meeting tangentially at the velocity of minimum torque.

We draw the accelerating branch from the paper's own identified model (Table 1, three segments
switched hard at 0.05 and 1.2 deg/s: :func:`table1_static_model`) and the decelerating branch as
that curve minus a Stribeck-shaped dip that vanishes with zero slope at the minimum-torque velocity (tangent there, as
the paper requires),
then add white Gaussian noise per sample.

Units: velocity deg/s, torque N*m.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from .._types import PRNGKeyArray
from ..friction import AbstractFrictionModel, Segmented
from ..io import StribeckData, summarise_samples

PAPER_LIKE_SEED = 284  # the paper's article number; any fixed value would do
PAPER_LIKE_NOISE_SD = 0.08  # N*m per sample
PAPER_LIKE_REPEATS = 30  # samples per set-point (section 4.2.2)
DECEL_STATIC_DROP = 3.0  # N*m: static friction when stopping = when starting minus this
DECEL_VS = 0.0315  # deg/s: width of the decelerating branch's dip (Table 1, segment 1 vs)


def table1_static_model() -> Segmented:
    """Table 1 as printed: the three segments switched hard at 0.05 and 1.2 deg/s (no blending band,
    unlike the simulator's default :func:`lugre_jax.plant.paper_friction`, which smooths the edges
    for the ODE solvers). Steady state in N*m of velocity in deg/s."""
    from ..plant import paper_friction

    m = paper_friction()
    return Segmented(m.segments, m.edges, blend=0.0)


def minimum_torque_velocity(model: AbstractFrictionModel, v_max: float = 1.5, n: int = 150001) -> tuple[float, float]:
    """Velocity [deg/s] and torque [N*m] of the minimum of ``model.steady_state`` on (0, v_max]."""
    v = np.linspace(v_max / n, v_max, n)
    t = np.asarray(model.steady_state(jnp.asarray(v)))
    i = int(np.argmin(t))
    return float(v[i]), float(t[i])


def paper_like_velocities(v_min: float) -> tuple[np.ndarray, np.ndarray]:
    """Set-points [deg/s]: 80 on the accelerating branch (dense below 0.1 deg/s where the torque
    changes fast, 0.005 apart; then 60 evenly up to 1.5) and 12 on the decelerating branch below
    ``v_min``: 92 in all, as in the paper."""
    accel = np.concatenate([np.linspace(0.005, 0.1, 20), np.linspace(0.1 + 1.4 / 60, 1.5, 60)])
    decel = np.linspace(0.0075, 0.98 * v_min, 12)
    return np.round(accel, 6), np.round(decel, 6)


def decel_branch(model: AbstractFrictionModel, v, v_min: float, drop: float = DECEL_STATIC_DROP, vs: float = DECEL_VS):
    """Decelerating-branch torque [N*m]: ``model`` minus a Stribeck-shaped dip
    ``drop*exp(-(v/vs)**2)`` below ``v_min``, with the dip's value and slope at ``v_min`` subtracted
    so that the branch equals the accelerating one in value and slope there (tangent, section 4.2.2).
    The static friction when stopping is ``drop`` lower than when starting."""
    v = jnp.asarray(v)
    e = lambda u: drop * jnp.exp(-((u / vs) ** 2))  # noqa: E731
    e_m = e(v_min)
    de_m = -2.0 * v_min / vs**2 * e_m
    dip = jnp.where(v < v_min, e(v) - e_m - de_m * (v - v_min), 0.0)
    return model.steady_state(v) - dip


def make_paper_like_samples(
    seed: int = PAPER_LIKE_SEED,
    *,
    n_repeats: int = PAPER_LIKE_REPEATS,
    noise_sd: float = PAPER_LIKE_NOISE_SD,
    model: AbstractFrictionModel | None = None,
) -> dict[str, np.ndarray]:
    """Per-sample columns ``velocity_deg_s``, ``torque_nm``, ``branch`` of the shipped data set."""
    model = table1_static_model() if model is None else model
    v_min, _ = minimum_torque_velocity(model)
    va, vd = paper_like_velocities(v_min)
    mean = np.concatenate([np.asarray(model.steady_state(jnp.asarray(va))), np.asarray(decel_branch(model, vd, v_min))])
    vel = np.concatenate([va, vd])
    branch = np.array(["accel"] * va.size + ["decel"] * vd.size)
    noise = np.asarray(jax.random.normal(jax.random.key(seed), (vel.size, n_repeats))) * noise_sd
    tor = mean[:, None] + noise
    return dict(
        velocity_deg_s=np.repeat(vel, n_repeats),
        torque_nm=np.round(tor.ravel(), 6),
        branch=np.repeat(branch, n_repeats),
    )


def sample_stribeck_data(
    model: AbstractFrictionModel,
    velocity,
    *,
    key: PRNGKeyArray,
    n_repeats: int = PAPER_LIKE_REPEATS,
    noise_sd: float = PAPER_LIKE_NOISE_SD,
) -> StribeckData:
    """Averaged synthetic data: ``n_repeats`` noisy samples of ``model.steady_state`` at each velocity
    [deg/s], white noise of ``noise_sd`` [N*m] per sample, averaged with their spread as weights."""
    velocity = np.asarray(velocity, dtype=np.float64)
    mean = np.asarray(model.steady_state(jnp.asarray(velocity)))
    noise = np.asarray(jax.random.normal(key, (velocity.size, n_repeats))) * noise_sd
    return summarise_samples(np.repeat(velocity, n_repeats), (mean[:, None] + noise).ravel(), source="synthetic")


def write_paper_like_csv(path, seed: int = PAPER_LIKE_SEED) -> StribeckData:
    """Generate the shipped data set and write it as a Stribeck CSV (atomically). Returns it averaged."""
    from ..io import atomic_path

    cols = make_paper_like_samples(seed)
    with atomic_path(path) as tmp:
        with open(tmp, "w") as fh:
            fh.write("# Synthetic Stribeck data shaped like Li et al. 2020 Fig. 3b; drawn from the paper's Table 1\n")
            fh.write(f"# model plus white noise (sd {PAPER_LIKE_NOISE_SD} N*m per sample), seed {seed}. See data/README.md.\n")
            fh.write("velocity_deg_s,torque_nm,branch\n")
            for v, t, b in zip(cols["velocity_deg_s"], cols["torque_nm"], cols["branch"]):
                fh.write(f"{v:.6f},{t:.6f},{b}\n")
    return summarise_samples(cols["velocity_deg_s"], cols["torque_nm"], cols["branch"], source=str(path))
