"""Table 2 of Li et al., Electronics 2020, 9, 284 (dynamic parameters sigma0, sigma1 per segment)
re-estimated on the simulated joint, and the identifiability study behind it (section 4.2.5).

Three routes, all on the plant (Tables 1-2) as "the real joint", never on the plant's own numbers:

1. the paper's: ``sigma0`` from a pre-sliding torque step read through a quantised encoder (eq. 17),
   ``sigma1`` from eq. (18) with J = 0.128 and the segment's identified ``sigma2``;
2. time series: all six ``(sigma0_k, sigma1_k)`` fitted by Levenberg-Marquardt through the simulator
   to a noisy recording of the Fig. 12 ramp (0 -> 1.5 deg/s in 4 s, velocity PI), started from
   route 1, with Fisher standard errors;
3. excitation design: D-optimal amplitude/frequency of an open-loop torque sine for segment 1's
   ``(sigma0, sigma1)`` over a vmapped grid, and a fit on the best design.

Units: sigma0 N*m/deg, sigma1 N*m*s/deg, J N*m*s^2/deg, noise deg.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from .. import FixedStep, System, simulate
from ..control import VelocityPID, VelocityRamp
from ..dynamic import (
    design_grid,
    fit_dynamic,
    inertia_eq18,
    presliding_step,
    sigma1_eq18,
    torque_sine_system,
    with_dynamics,
)
from ..plant import Joint
from ..plant import TABLE1, TABLE2, paper_inertia_per_segment
from ._setup import ENCODER_RES_DEG, Setup

NOISE_DEG = 1e-4  # encoder-like measurement noise of the recordings [deg]
STEP_SIZES_NM = (0.05, 0.1, 0.2, 0.5, 1.0)


def _recording(build, p, duration_s, sample_hz, key):
    th = np.asarray(simulate(build(jnp.asarray(p, float)), duration_s, sample_hz, stepping=FixedStep()).theta)
    return th + NOISE_DEG * np.asarray(jax.random.normal(key, th.shape))


def table2(setup: Setup, *, quick: bool = False, key=None) -> dict:
    """Re-estimated Table 2 (routes 1 and 2 of the module docstring) beside the paper's."""
    key = jax.random.key(18) if key is None else key
    plant, J = setup.plant, setup.J
    paper = {k: dict(sigma0=TABLE2[k][0], sigma1=TABLE2[k][1], sigma2=TABLE1[k][3]) for k in (1, 2, 3)}
    J_implied = paper_inertia_per_segment()

    # Route 1: step-size dependence of eq. (17) on the segmented plant
    steps = {}
    for s in STEP_SIZES_NM:
        try:
            r = presliding_step(plant, J, s, encoder_res_deg=ENCODER_RES_DEG)
            steps[f"{s:g}"] = r.sigma0
        except ValueError as e:
            steps[f"{s:g}"] = str(e)
    sigma0_step = float(setup.presliding["sigma0_nm_per_deg"])
    pw = setup.static_params["GA-PSO piecewise"]["segments"]
    route1 = {k + 1: dict(sigma0=sigma0_step, sigma1=float(sigma1_eq18(J, sigma0_step, seg["sigma2"])),
                          sigma2_identified=seg["sigma2"]) for k, seg in enumerate(pw)}

    common = dict(paper=paper, J_implied_by_eq18=J_implied, J_used=J, presliding_steps=steps, route1_paper_method=route1)
    if quick:  # the forward-mode LM's compilation would dominate the smoke run
        return dict(common, route2_time_series=None, fit=None, recording=None)

    # Route 2: LM through the simulator on a noisy ramp recording, 6 parameters
    duration, hz = 5.0, 100.0

    def build6(p):
        fr = plant
        for k in range(3):
            fr = with_dynamics(fr, p[2 * k], p[2 * k + 1], k)
        return System(friction=fr, joint=Joint(J=J), controller=VelocityPID(kp=setup.kp, ki=setup.ki),
                      reference=VelocityRamp(1.5, 4.0))

    truth = [v for k in (1, 2, 3) for v in (float(plant.segments[k - 1].sigma0), float(plant.segments[k - 1].sigma1))]
    meas = _recording(build6, truth, duration, hz, key)
    p0 = [v for k in (1, 2, 3) for v in (route1[k]["sigma0"], max(route1[k]["sigma1"], 0.05))]
    names = tuple(f"{n}_{k}" for k in (1, 2, 3) for n in ("sigma0", "sigma1"))
    fit = fit_dynamic(build6, meas, p0, duration_s=duration, sample_hz=hz, noise_deg=NOISE_DEG, names=names,
                      max_steps=40)
    route2 = {k: dict(sigma0=float(fit.p[2 * (k - 1)]), sigma0_se=float(fit.se[2 * (k - 1)]),
                      sigma1=float(fit.p[2 * k - 1]), sigma1_se=float(fit.se[2 * k - 1])) for k in (1, 2, 3)}
    return dict(common, route2_time_series=route2, fit=fit.as_dict(),
                recording=dict(kind="velocity ramp 0->1.5 deg/s in 4 s, velocity PI", duration_s=duration,
                               sample_hz=hz, noise_deg=NOISE_DEG))


DESIGN_AMPS = (0.02, 0.1, 0.5, 2.0)
DESIGN_FREQS = (0.2, 1.0, 3.0, 10.0, 20.0)


def excitation_design(setup: Setup, *, quick: bool = False, key=None) -> dict:
    """D-optimal open-loop torque sine for segment 1's (sigma0, sigma1): Fisher information on an
    amplitude x frequency grid (one vmapped evaluation), and an LM fit on the best design."""
    key = jax.random.key(19) if key is None else key
    plant, J = setup.plant, setup.J
    nominal = [float(setup.presliding["sigma0_nm_per_deg"]),
               float(sigma1_eq18(J, setup.presliding["sigma0_nm_per_deg"], setup.static_params["GA-PSO piecewise"]["segments"][0]["sigma2"]))]
    nominal[1] = max(nominal[1], 0.1)
    duration, hz = (1.0, 100.0) if quick else (2.0, 100.0)
    grid = np.array([(a, f) for a in DESIGN_AMPS for f in DESIGN_FREQS if f <= hz / 4])

    def build_exc(p, e):
        return torque_sine_system(with_dynamics(plant, p[0], p[1], 0), J, e[0], e[1])

    d = design_grid(build_exc, nominal, grid, duration_s=duration, sample_hz=hz, noise_deg=NOISE_DEG)
    best = grid[d["best"]]
    worst = int(np.argmin(d["logdet"]))
    truth = [float(plant.segments[0].sigma0), float(plant.segments[0].sigma1)]
    build_best = lambda p: build_exc(p, best)  # noqa: E731
    meas = _recording(build_best, truth, duration, hz, key)
    fit = fit_dynamic(build_best, meas, nominal, duration_s=duration, sample_hz=hz, noise_deg=NOISE_DEG,
                      names=("sigma0_1", "sigma1_1"), max_steps=15 if quick else 40)
    # The paper's own kind of recording: the 0.005 deg/s velocity-PI step (Fig. 9c). Does it determine them?
    from ..control import VelocitySteps
    from ..dynamic import fisher_information, standard_errors_from_fisher

    def build_step(p):
        return System(friction=with_dynamics(plant, p[0], p[1], 0), joint=Joint(J=J),
                      controller=VelocityPID(kp=setup.kp, ki=setup.ki), reference=VelocitySteps([0.005]))

    F_step = np.asarray(fisher_information(build_step, jnp.asarray(truth), 10.0, 20.0, NOISE_DEG))
    rel_step = standard_errors_from_fisher(F_step) / np.asarray(truth)
    return dict(typical_recording=dict(kind="velocity PI, 0.005 deg/s step, 10 s at 20 Hz (Fig. 9c)",
                                       relative_se_sigma0=float(rel_step[0]), relative_se_sigma1=float(rel_step[1])),
                grid=dict(amplitude_nm=grid[:, 0].tolist(), frequency_hz=grid[:, 1].tolist(), logdet=d["logdet"].tolist(),
                          relative_se_sigma0=d["relative_se"][:, 0].tolist(), relative_se_sigma1=d["relative_se"][:, 1].tolist()),
                nominal=nominal, truth=truth, best=dict(amplitude_nm=float(best[0]), frequency_hz=float(best[1])),
                worst=dict(amplitude_nm=float(grid[worst, 0]), frequency_hz=float(grid[worst, 1]),
                           relative_se_sigma0=float(d["relative_se"][worst, 0]), relative_se_sigma1=float(d["relative_se"][worst, 1])),
                fit_on_best=fit.as_dict(), recording=dict(duration_s=duration, sample_hz=hz, noise_deg=NOISE_DEG),
                inertia_check=dict(J_from_truth_eq18=float(inertia_eq18(truth[0], truth[1], TABLE1[1][3]))))
