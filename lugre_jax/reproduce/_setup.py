"""The common set-up of every reproduced figure of Li et al., Electronics 2020, 9, 284 (sections 5-6):
the "real joint", the identified observer models and the controller gains.

* **Real joint (plant)**: the paper's own identified model, Tables 1-2 (three LuGre segments split at
  0.05 and 1.2 deg/s, blended), with J = 0.128 N*m*s^2/deg (eq. 18 on segments 1 and 3). It stands
  in for the robot, whose measurements are not public.
* **Identified models (observers)**: never the plant. Static parts are identified by the paper's
  optimisers from *noisy* steady-state data (``data/stribeck_paper_like.csv``, 92 set-points x 30
  samples drawn from the plant with 0.08 N*m noise and a decelerating branch): PSO (whole), GA
  (whole), GA-PSO (whole) and GA-PSO (piecewise at the paper's 0.05 and 1.2 deg/s). ``sigma0`` comes
  from a simulated pre-sliding torque step on the plant read through a quantised encoder (eq. 17),
  ``sigma1`` of each segment from eq. (18) with the known J and the segment's identified ``sigma2``.
* **Gains**: velocity PI ``kp`` = 8 N*m*s/deg (assumed: ``kp/J`` = 62 rad/s, a ~10 Hz velocity loop);
  ``ki`` calibrated by a vmapped grid search so that the *uncompensated* velocity PI shows the paper's
  2 s dead zone at 0.005 deg/s (Fig. 9c) -- the one number we fit to the paper; every other number
  is then a prediction. Position loop ``kpp`` = ``(kp/J)/4`` (the usual cascade rule: position loop
  four times slower than the velocity loop). Observer gain ``k_obs`` = 0.1 (eq. 19 needs k > 0),
  ``J_ff`` = J.

Units: deg, deg/s, N*m, sigma0 N*m/deg, sigma1/sigma2 N*m*s/deg, J N*m*s^2/deg, gains as in
:class:`~lugre_jax.VelocityPID`.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from .. import FixedStep, System, simulate, stack_systems
from ..control import LuGreCompensated, PositionPID, VelocityPID, VelocitySteps
from ..dynamic import lugre_from_static, presliding_step, sigma1_eq18
from ..friction import AbstractFrictionModel, LuGre, Segmented
from ..metrics import dead_zone_lag
from ..plant import PAPER_J, Joint, paper_friction

PAPER_DEAD_ZONE_S = 2.0  # Fig. 9c, velocity PID at 0.005 deg/s
STEP_V = 0.005  # deg/s, the paper's minimum stationary velocity
STEP_DURATION_S = 30.0  # s, long enough for the PI lag to settle (dead zone = mean lag over the last 25%)
KP = 8.0
K_OBS = 0.1
ENCODER_RES_DEG = 1e-4  # ~22-bit encoder on the joint (360/2^22 = 8.6e-5 deg)
PRESLIDING_STEP_NM = 0.1  # well below breakaway, small enough to stay in segment 1 (|v| < 0.045 deg/s)

# label -> (scheme, optimiser) of the identified models the paper compares
MODELS = {
    "PSO whole": ("whole", "pso"),
    "GA whole": ("whole", "ga"),
    "GA-PSO whole": ("whole", "gapso"),
    "GA-PSO piecewise": ("piecewise", "gapso"),
}
PAPER_EDGES = (0.05, 1.2)


def default_data_path() -> Path:
    """The shipped synthetic Stribeck data, ``data/stribeck_paper_like.csv`` at the project root."""
    return Path(__file__).resolve().parents[2] / "data" / "stribeck_paper_like.csv"


@dataclasses.dataclass
class Setup:
    """Plant, identified observer models and gains shared by all reproduced figures."""

    plant: AbstractFrictionModel
    J: float
    kp: float
    ki: float
    kpp: float
    k_obs: float
    observers: dict  # label -> LuGre or Segmented (identified)
    static_params: dict  # label -> list of segment dicts (Fc, Fs, vs, sigma2, sigma0, sigma1, v_range)
    presliding: dict  # eq. 17 test: sigma0, step, displacement
    ki_grid: dict  # calibration: grid of ki and the resulting dead zones
    quick: bool = False
    notes: list = dataclasses.field(default_factory=list)
    runs: dict = dataclasses.field(default_factory=dict, repr=False)  # memo of simulated traces

    # ---- controllers -------------------------------------------------------------------------
    def velocity_pid(self) -> VelocityPID:
        return VelocityPID(kp=self.kp, ki=self.ki)

    def position_pid(self) -> PositionPID:
        return PositionPID(kpp=self.kpp, kp=self.kp, ki=self.ki)

    def compensated(self, label: str, position: bool = False) -> LuGreCompensated:
        inner = self.position_pid() if position else self.velocity_pid()
        return LuGreCompensated(inner=inner, observer=self.observers[label], k_obs=self.k_obs, J_ff=self.J)

    def system(self, controller, reference) -> System:
        return System(friction=self.plant, joint=Joint(J=self.J), controller=controller, reference=reference)

    def as_dict(self) -> dict:
        return dict(
            plant="paper Tables 1-2 (Segmented LuGre, edges 0.05 and 1.2 deg/s, blended)", J=self.J,
            gains=dict(kp=self.kp, ki=self.ki, kpp=self.kpp, k_obs=self.k_obs, J_ff=self.J,
                       units=dict(kp="N*m*s/deg", ki="N*m/deg", kpp="1/s", k_obs="1", J_ff="N*m*s^2/deg")),
            gain_choice=dict(
                kp="assumed: kp/J = 62 rad/s (~10 Hz velocity loop)",
                ki=f"vmapped grid: uncompensated velocity PI dead zone at {STEP_V} deg/s = {PAPER_DEAD_ZONE_S} s (paper Fig. 9c)",
                kpp="cascade rule kpp = (kp/J)/4", k_obs="0.1 (eq. 19 needs k > 0)",
                grid=self.ki_grid),
            observers=self.static_params, presliding=self.presliding, quick=self.quick, notes=self.notes,
        )


# ------------------------------------------------------------------------------------------------
# identified models
# ------------------------------------------------------------------------------------------------

def _segment_dicts(model) -> list[dict]:
    segs = model.segments if isinstance(model, Segmented) else (model,)
    edges = [0.0] + ([float(e) for e in np.asarray(model.edges)] if isinstance(model, Segmented) else []) + [np.inf]
    out = []
    for k, s in enumerate(segs):
        out.append(dict(Fc=float(s.Fc), Fs=float(s.Fs), vs=float(s.vs), sigma2=float(s.sigma2),
                        sigma0=float(s.sigma0), sigma1=float(s.sigma1), v_range=[edges[k], edges[k + 1]]))
    return out


def model_from_dicts(segs: list[dict]) -> AbstractFrictionModel:
    """Rebuild an observer model from :func:`_segment_dicts` output (JSON cache)."""
    ms = [LuGre(Fc=jnp.asarray(s["Fc"]), Fs=jnp.asarray(s["Fs"]), vs=jnp.asarray(s["vs"]), sigma2=jnp.asarray(s["sigma2"]),
                sigma0=jnp.asarray(s["sigma0"]), sigma1=jnp.asarray(s["sigma1"]), require_passive=False)
          for s in segs]
    if len(ms) == 1:
        return ms[0]
    return Segmented(tuple(ms), jnp.asarray([s["v_range"][1] for s in segs[:-1]]))


def identify_observers(data_path, sigma0: float, J: float, *, quick: bool = False, key=None, progress=None) -> dict:
    """Identify the four static models of :data:`MODELS` from the Stribeck CSV and give them dynamics
    (``sigma0`` shared, ``sigma1`` per segment by eq. 18). Returns label -> (model, Identification).

    ``quick``: smaller swarms/populations (PSO 20x20, GA 20x5; the GA-PSO composition of those),
    for tests; the default uses each optimiser's paper settings (section 4.2.3).
    """
    from ..identify import identify
    from ..io import load_stribeck_csv

    data = load_stribeck_csv(data_path)
    # The observers use the accelerating branch only (Identification.friction_model); fitting the
    # decelerating branch too would cost a segment fit and change nothing downstream.
    data = data.select(data.branch == "accel")
    key = jax.random.key(284) if key is None else key
    out = {}
    for i, (label, (scheme, method)) in enumerate(MODELS.items()):
        settings = {}
        if quick:
            settings = {"pso": dict(n_particles=20, max_steps=20), "ga": dict(max_steps=5),
                        "gapso": dict(pso=dict(n_particles=20, max_steps=20), ga=dict(max_steps=5))}[method]
        kw = dict(edges=PAPER_EDGES) if scheme == "piecewise" else {}
        res = identify(data, scheme, method, key=jax.random.fold_in(key, i), **kw, **settings)
        static = res.friction_model()
        if isinstance(static, Segmented):
            s2 = np.array([float(s.sigma2) for s in static.segments])
        else:
            s2 = float(static.sigma2)
        s1 = np.maximum(sigma1_eq18(J, sigma0, s2), 0.0)
        # eq. (18)'s damping on the identified Stribeck curve is the paper's route, passive or not
        out[label] = (lugre_from_static(static, sigma0, s1, require_passive=False), res)
        if progress is not None:
            progress.update(1)
    return out


# ------------------------------------------------------------------------------------------------
# gain calibration
# ------------------------------------------------------------------------------------------------

def calibrate_ki(plant, J: float, kp: float, *, target_s: float = PAPER_DEAD_ZONE_S, v: float = STEP_V,
                 duration_s: float = STEP_DURATION_S, grid=None) -> tuple[float, dict]:
    """Integral gain ki [N*m/deg] of the velocity PI whose uncompensated dead zone (mean lag over the
    last 25% of a ``duration_s`` step at ``v`` deg/s) equals ``target_s``: one batched simulation over a
    log grid, then log-log interpolation of dead zone vs ki."""
    grid = np.geomspace(100.0, 3000.0, 12) if grid is None else np.asarray(grid, dtype=np.float64)
    systems = [System(friction=plant, joint=Joint(J=J), controller=VelocityPID(kp=kp, ki=float(k)),
                      reference=VelocitySteps([v])) for k in grid]
    sol = simulate(stack_systems(systems), duration_s, 20.0, batched=True, stepping=FixedStep())
    if np.any(np.asarray(sol.result) != 0):
        raise RuntimeError(f"ki calibration: lanes failed {np.asarray(sol.result)}")
    dz = dead_zone_lag(np.asarray(sol.ts), np.asarray(sol.theta), v)
    order = np.argsort(dz)
    ki = float(np.exp(np.interp(np.log(target_s), np.log(dz[order]), np.log(grid[order]))))
    return ki, dict(ki=grid.tolist(), dead_zone_s=dz.tolist(), target_s=target_s, v_deg_s=v, duration_s=duration_s)


def build_setup(data_path=None, *, quick: bool = False, key=None, progress=None, cache: str | os.PathLike | None = None) -> Setup:
    """Everything the figures share (see module docstring). With ``cache`` (a JSON path), a previous
    set-up is loaded if present and written otherwise (identification is the slow part)."""
    if cache is not None and Path(cache).exists():
        return load_setup(cache)
    data_path = default_data_path() if data_path is None else Path(data_path)
    if not data_path.exists():
        raise ValueError(f"Stribeck data {data_path} not found; pass --data PATH to a steady-state CSV "
                         "(e.g. the shipped data/stribeck_paper_like.csv)")
    plant, J = paper_friction(), PAPER_J
    pre = presliding_step(plant, J, PRESLIDING_STEP_NM, encoder_res_deg=ENCODER_RES_DEG)
    if progress is not None:
        progress.update(1)
    ki, grid = calibrate_ki(plant, J, KP)
    if progress is not None:
        progress.update(1)
    obs = identify_observers(data_path, pre.sigma0, J, quick=quick, key=key, progress=progress)
    setup = Setup(
        plant=plant, J=J, kp=KP, ki=ki, kpp=(KP / J) / 4.0, k_obs=K_OBS,
        observers={k: m for k, (m, _) in obs.items()},
        static_params={k: dict(segments=_segment_dicts(m), rms_nm=r.rms(), scheme=r.scheme, method=r.method)
                       for k, (m, r) in obs.items()},
        presliding=dict(pre.as_dict(), encoder_res_deg=ENCODER_RES_DEG, truth_sigma0_segment1=float(plant.segments[0].sigma0)),
        ki_grid=grid, quick=quick,
        notes=[f"identified from {data_path.name}"] + (["quick mode: reduced optimiser settings"] if quick else []),
    )
    if cache is not None:
        save_setup(setup, cache)
    return setup


def save_setup(setup: Setup, path) -> None:
    from ..io import write_json

    write_json(path, setup.as_dict())


def load_setup(path) -> Setup:
    """Rebuild a :class:`Setup` from :func:`save_setup` JSON."""
    d = json.loads(Path(path).read_text())
    g = d["gains"]
    return Setup(
        plant=paper_friction(), J=float(d["J"]), kp=float(g["kp"]), ki=float(g["ki"]), kpp=float(g["kpp"]),
        k_obs=float(g["k_obs"]), observers={k: model_from_dicts(v["segments"]) for k, v in d["observers"].items()},
        static_params=d["observers"], presliding=d["presliding"], ki_grid=d["gain_choice"]["grid"],
        quick=bool(d.get("quick", False)), notes=list(d.get("notes", [])) + [f"loaded from {path}"],
    )
