"""``diagnose`` on recordings it did not make: the independent scipy generator of
:mod:`lugre_jax.testing` (closed-loop LuGre joint under a velocity PI, ``solve_ivp`` LSODA at
rtol 1e-9), issue #20.

Studies (``--study``), each job appends one JSON line to ``<out>/runs.jsonl`` (resumable;
``--shard i/n`` splits the jobs across processes):

* ``null``: effect-free recordings spanning the generator's settings (two plants, four excitations
  (144-s staircases, smooth or sharp; 60-120-s sine sweeps and multisines),
  100-1,000 Hz, torque noise 0.02-0.2 N*m, velocity noise 0-0.01 deg/s, quantisation 0-0.005 deg,
  velocity column present or absent, four velocity-only recordings, and six with coloured torque
  noise, low-passed at 2-40 Hz); the claim: ``none`` in >= 95 % and the baseline's validation
  RMSE within 10 % of the estimated noise floor in every one;
* ``issue``: the recording kind of issue #20 (its plant, PI, 288-s staircase, 200 Hz, its noise) for
  the null case and gravity, asymmetry, ripple, drift and ripple + asymmetry at the issue's sizes;
* ``proof``: each candidate (and two pairs) at the concealed level -- peak effect torque below the
  per-sample torque noise -- on a 144-s staircase of the issue's kind, at strengths 1 and 0.5;
* ``heldout``: settings no threshold was calibrated on (:func:`heldout_settings`): two further
  plants, off-grid rates, noise and excitation parameters, the paper's sine tracking, effects on
  the new plants, and the issue's kind on seeds 21 and 22 (``<out>`` ``results/heldout``);
* ``fresh``: a second held-out set (:func:`fresh_settings`), fixed and committed before its
  first run: two more plants, 10-s and 2.5-s dwells, 100-1,000 Hz, and one recording per candidate plus a pair
  (``<out>`` ``results/fresh``).

    python experiments/diagnose_independent/run.py --study null --shard 0/2
    python experiments/diagnose_independent/run.py --study issue
    python experiments/diagnose_independent/run.py --study proof --shard 0/2
    python experiments/diagnose_independent/plot.py

Studies of the rebuilt diagnosis (issues #30 and #31; ``<out>`` ``results/<study>``), their settings
fixed and committed before their first run, under a velocity PI or a position PID (:func:`controller_of`),
every recording <= 60 s and <= 60,000 samples; each row holds the recording's TRUE torque noise std
and the floor's ratio to it, and the expected verdict:

* ``calib``: 48 effect-free recordings (:func:`calib_settings`): six excitations x both loops x
  three sensor sets, three plants, 100-1,000 Hz, white and AR(1) torque noise;
* ``fresh3``: each in-library effect at the concealed level (peak effect torque below the
  per-sample torque noise std) on three recordings, and eight effect-free ones, on three plants no
  earlier study used (:func:`fresh3_settings`); expected: the effect's id exactly;
* ``outside``: the generator's four effects outside the candidates at the concealed level, two
  recordings each (:func:`outside_settings`); expected ``unexplained`` and the dependence.

    python experiments/diagnose_independent/run.py --study calib --shard 0/2   # and 1/2
    python experiments/diagnose_independent/run.py --study fresh3 --shard 0/2  # and 1/2
    python experiments/diagnose_independent/run.py --study outside --shard 0/2 # and 1/2
    python experiments/diagnose_independent/plot.py --new

Held-out sets of the current diagnosis (calib, fresh3 and outside are not held out for it), fixed
and committed before their first run: ``calib2`` (40 effect-free rows: :func:`calib2_settings`) and
``fresh4`` (fresh3's effects at other rates and seeds, nulls on other plants: :func:`fresh4_settings`).

    python experiments/diagnose_independent/run.py --study calib2 --shard 0/2  # and 1/2
    python experiments/diagnose_independent/run.py --study fresh4 --shard 0/2  # and 1/2

``--generate-only`` generates and caches a study's recordings and writes what generation shows
(tracking, the effect's peak against the noise) to ``<out>/design_<study>.jsonl``, without diagnosis.

Generated recordings are cached (``--cache``, default ``<out>/cache``; keyed by the job's settings
and the generator's source), so a study re-run on changed diagnosis code only diagnoses.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import inspect
import json
import pickle
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

import lugre_jax
from lugre_jax import testing as T

lugre_jax.configure()

PAPER_LIKE = T.Plant(J=0.128, Fc=1.0, Fs=1.6, vs=0.2, sigma2=0.5, sigma0=100.0, sigma1=2.0)
# plants of the held-out study only (never used to calibrate anything): a light joint with a sharp,
# low Stribeck speed and a heavy one with a broad Stribeck dip
LIGHT = T.Plant(J=0.04, Fc=0.5, Fs=0.9, vs=0.03, sigma2=2.0, sigma0=150.0, sigma1=0.8)
HEAVY = T.Plant(J=0.4, Fc=2.0, Fs=3.0, vs=0.15, sigma2=0.8, sigma0=40.0, sigma1=3.0)
# the fresh set's plants: stiff bristles with little damping and a low Stribeck speed; a nearly flat
# Stribeck curve (Fs 1.13 Fc) with a high Stribeck speed
MEDIUM = T.Plant(J=0.2, Fc=0.8, Fs=1.5, vs=0.05, sigma2=1.5, sigma0=300.0, sigma1=0.5)
FLAT = T.Plant(J=0.08, Fc=1.5, Fs=1.7, vs=0.3, sigma2=0.3, sigma0=80.0, sigma1=2.0)
# plants of the fresh3 and outside studies only (no earlier study used them; all three passive,
# sigma2*Fc >= sigma1*(Fs - Fc)): a nimble joint with stiff bristles, a sluggish one with a low
# Stribeck speed and strong viscous friction, and a middle one
NIMBLE = T.Plant(J=0.06, Fc=0.9, Fs=1.4, vs=0.1, sigma2=0.6, sigma0=200.0, sigma1=1.0)
SLUGGISH = T.Plant(J=0.25, Fc=1.8, Fs=2.4, vs=0.04, sigma2=1.8, sigma0=50.0, sigma1=2.5)
MIDDLE = T.Plant(J=0.15, Fc=1.1, Fs=1.9, vs=0.12, sigma2=0.9, sigma0=120.0, sigma1=1.2)
# plants of the calib3 study only (no earlier study used them; all passive): a stiff joint, a soft
# one with a broad Stribeck dip, a tiny one with low friction
STIFF = T.Plant(J=0.1, Fc=0.7, Fs=1.0, vs=0.08, sigma2=1.0, sigma0=250.0, sigma1=1.5)
SOFT = T.Plant(J=0.3, Fc=1.2, Fs=2.0, vs=0.2, sigma2=0.4, sigma0=30.0, sigma1=0.5)
TINY = T.Plant(J=0.02, Fc=0.3, Fs=0.45, vs=0.05, sigma2=0.5, sigma0=100.0, sigma1=0.5)
# plants of the calib4 study only (no earlier study used them; all passive): a mid-size joint with a
# sharp Stribeck dip, a massive one with stiff bristles, a light one with strong damping
SHARP = T.Plant(J=0.12, Fc=0.6, Fs=1.1, vs=0.04, sigma2=1.5, sigma0=180.0, sigma1=1.2)
MASSIVE = T.Plant(J=0.6, Fc=2.5, Fs=3.2, vs=0.1, sigma2=1.0, sigma0=400.0, sigma1=3.0)
DAMPED = T.Plant(J=0.05, Fc=0.4, Fs=0.55, vs=0.15, sigma2=2.5, sigma0=60.0, sigma1=4.0)
# plants of the calib5 and outside2 studies only (no earlier study used them; all passive): a light
# joint with a moderate dip, a heavy one with slow bristles, a small one with a deep dip
BRISK = T.Plant(J=0.08, Fc=0.5, Fs=0.8, vs=0.06, sigma2=0.8, sigma0=150.0, sigma1=0.8)
HEFTY = T.Plant(J=0.45, Fc=1.8, Fs=2.4, vs=0.12, sigma2=2.0, sigma0=120.0, sigma1=2.0)
DAINTY = T.Plant(J=0.03, Fc=0.35, Fs=0.6, vs=0.07, sigma2=0.6, sigma0=90.0, sigma1=0.6)
# plants of the calib6 study only (no earlier study used them; all passive): a heavy joint with a
# mid dip, a slender one with a narrow dip, a stiff-bristled one with a deep dip
STOUT = T.Plant(J=0.3, Fc=1.2, Fs=1.7, vs=0.09, sigma2=1.4, sigma0=200.0, sigma1=1.6)
SLENDER = T.Plant(J=0.06, Fc=0.45, Fs=0.65, vs=0.05, sigma2=0.9, sigma0=110.0, sigma1=0.9)
KEEN = T.Plant(J=0.18, Fc=0.8, Fs=1.3, vs=0.08, sigma2=1.8, sigma0=250.0, sigma1=1.5)
# plants of the calib7 study only (no earlier study used them; all passive): a mid-weight joint with a
# shallow dip, a very light one with soft bristles, a heavy one with a wide dip
MODEST = T.Plant(J=0.15, Fc=0.7, Fs=0.95, vs=0.1, sigma2=1.2, sigma0=140.0, sigma1=1.0)
FEATHER = T.Plant(J=0.025, Fc=0.3, Fs=0.45, vs=0.06, sigma2=0.5, sigma0=70.0, sigma1=0.5)
BULKY = T.Plant(J=0.5, Fc=2.0, Fs=2.9, vs=0.14, sigma2=2.2, sigma0=300.0, sigma1=2.2)
# plants of the calib8 study only (no earlier study used them; all passive): a mid-weight joint with a
# deep, narrow dip, a light one with stiff bristles, a heavy one with a shallow, wide dip
TAUT = T.Plant(J=0.2, Fc=0.9, Fs=1.5, vs=0.05, sigma2=1.6, sigma0=220.0, sigma1=1.4)
WIRY = T.Plant(J=0.04, Fc=0.4, Fs=0.6, vs=0.08, sigma2=0.7, sigma0=260.0, sigma1=0.7)
PORTLY = T.Plant(J=0.4, Fc=1.6, Fs=2.0, vs=0.16, sigma2=1.9, sigma0=170.0, sigma1=1.9)
# plants of the calib9 and outside4 studies only (no earlier study used them; all passive): a heavy
# joint with a mid dip, a light one with stiff bristles, a mid-weight one with a deep dip
BRAWNY = T.Plant(J=0.35, Fc=1.4, Fs=1.9, vs=0.11, sigma2=1.7, sigma0=190.0, sigma1=1.3)
SPRY = T.Plant(J=0.05, Fc=0.38, Fs=0.58, vs=0.065, sigma2=0.75, sigma0=200.0, sigma1=0.65)
STURDY = T.Plant(J=0.22, Fc=1.0, Fs=1.45, vs=0.075, sigma2=1.5, sigma0=280.0, sigma1=1.7)
# plants of the calib10 and outside5 studies only (no earlier study used them; all passive): a
# light joint with a wide dip, a heavy one with stiff bristles, a mid-weight one with a shallow dip
LITHE = T.Plant(J=0.07, Fc=0.42, Fs=0.62, vs=0.12, sigma2=0.85, sigma0=130.0, sigma1=0.75)
HULKING = T.Plant(J=0.55, Fc=2.2, Fs=2.8, vs=0.09, sigma2=2.4, sigma0=320.0, sigma1=2.4)
STEADY = T.Plant(J=0.16, Fc=0.75, Fs=1.0, vs=0.07, sigma2=1.3, sigma0=160.0, sigma1=1.1)
# plants of the calib11 study only (no earlier study used them; all passive): a light joint with a
# deep dip and soft bristles, a heavy one with a narrow dip, a mid-weight one with stiff bristles
NIPPY = T.Plant(J=0.09, Fc=0.5, Fs=0.8, vs=0.055, sigma2=0.9, sigma0=150.0, sigma1=0.8)
BURLY = T.Plant(J=0.48, Fc=1.9, Fs=2.3, vs=0.045, sigma2=2.1, sigma0=240.0, sigma1=2.0)
EVEN = T.Plant(J=0.19, Fc=0.85, Fs=1.2, vs=0.1, sigma2=1.4, sigma0=300.0, sigma1=1.5)
# calib12's plants
CRISP = T.Plant(J=0.11, Fc=0.55, Fs=0.9, vs=0.065, sigma2=1.1, sigma0=210.0, sigma1=1.0)
STOCKY = T.Plant(J=0.38, Fc=1.5, Fs=2.1, vs=0.085, sigma2=1.8, sigma0=260.0, sigma1=1.8)
SUPPLE = T.Plant(J=0.06, Fc=0.45, Fs=0.7, vs=0.07, sigma2=0.8, sigma0=110.0, sigma1=0.7)
# calib13's plants
LANKY = T.Plant(J=0.07, Fc=0.48, Fs=0.78, vs=0.075, sigma2=0.95, sigma0=190.0, sigma1=0.85)
CHUNKY = T.Plant(J=0.42, Fc=1.7, Fs=2.25, vs=0.06, sigma2=1.9, sigma0=230.0, sigma1=1.9)
POISED = T.Plant(J=0.14, Fc=0.65, Fs=1.0, vs=0.09, sigma2=1.25, sigma0=170.0, sigma1=1.15)
# calib14's plants (named apart from calib7's BULKY and calib8's WIRY, which they had replaced in
# PLANTS and PIDS)
WIRY14 = T.Plant(J=0.08, Fc=0.52, Fs=0.85, vs=0.068, sigma2=1.0, sigma0=175.0, sigma1=0.9)
BULKY14 = T.Plant(J=0.45, Fc=1.8, Fs=2.4, vs=0.07, sigma2=2.0, sigma0=250.0, sigma1=2.1)
TRIM = T.Plant(J=0.17, Fc=0.7, Fs=1.05, vs=0.08, sigma2=1.2, sigma0=200.0, sigma1=1.2)
# calib15's plants
SPARE = T.Plant(J=0.065, Fc=0.47, Fs=0.74, vs=0.072, sigma2=0.88, sigma0=165.0, sigma1=0.82)
HUSKY = T.Plant(J=0.4, Fc=1.65, Fs=2.2, vs=0.082, sigma2=1.85, sigma0=270.0, sigma1=1.95)
TIDY = T.Plant(J=0.15, Fc=0.68, Fs=0.98, vs=0.058, sigma2=1.15, sigma0=215.0, sigma1=1.25)
PLANTS = {"issue": (T.Plant(), T.VelocityPIController()), "paper_like": (PAPER_LIKE, T.VelocityPIController(kp=4.0, ki=20.0)),
          "light": (LIGHT, T.VelocityPIController(kp=2.5, ki=15.0)), "heavy": (HEAVY, T.VelocityPIController(kp=25.0, ki=150.0)),
          "medium": (MEDIUM, T.VelocityPIController(kp=12.0, ki=80.0)), "flat": (FLAT, T.VelocityPIController(kp=5.0, ki=30.0)),
          "nimble": (NIMBLE, T.VelocityPIController(kp=3.0, ki=20.0)), "sluggish": (SLUGGISH, T.VelocityPIController(kp=15.0, ki=100.0)),
          "middle": (MIDDLE, T.VelocityPIController(kp=8.0, ki=50.0)),
          "stiff": (STIFF, T.VelocityPIController(kp=6.0, ki=36.0)), "soft": (SOFT, T.VelocityPIController(kp=18.0, ki=110.0)),
          "tiny": (TINY, T.VelocityPIController(kp=1.3, ki=8.0)),
          "sharp": (SHARP, T.VelocityPIController(kp=7.5, ki=45.0)), "massive": (MASSIVE, T.VelocityPIController(kp=37.0, ki=220.0)),
          "damped": (DAMPED, T.VelocityPIController(kp=3.0, ki=18.0)),
          "brisk": (BRISK, T.VelocityPIController(kp=5.0, ki=30.0)),
          "hefty": (HEFTY, T.VelocityPIController(kp=28.0, ki=165.0)),
          "dainty": (DAINTY, T.VelocityPIController(kp=1.9, ki=11.0)),
          "stout": (STOUT, T.VelocityPIController(kp=19.0, ki=110.0)),
          "slender": (SLENDER, T.VelocityPIController(kp=3.8, ki=22.0)),
          "keen": (KEEN, T.VelocityPIController(kp=11.0, ki=67.0)),
          "modest": (MODEST, T.VelocityPIController(kp=9.0, ki=55.0)),
          "feather": (FEATHER, T.VelocityPIController(kp=1.6, ki=9.5)),
          "bulky": (BULKY, T.VelocityPIController(kp=31.0, ki=185.0)),
          "taut": (TAUT, T.VelocityPIController(kp=12.5, ki=75.0)),
          "wiry": (WIRY, T.VelocityPIController(kp=2.5, ki=15.0)),
          "portly": (PORTLY, T.VelocityPIController(kp=25.0, ki=150.0)),
          "brawny": (BRAWNY, T.VelocityPIController(kp=22.0, ki=130.0)),
          "spry": (SPRY, T.VelocityPIController(kp=3.1, ki=19.0)),
          "sturdy": (STURDY, T.VelocityPIController(kp=13.7, ki=82.0)),
          "lithe": (LITHE, T.VelocityPIController(kp=4.3, ki=26.0)),
          "hulking": (HULKING, T.VelocityPIController(kp=34.0, ki=205.0)),
          "steady": (STEADY, T.VelocityPIController(kp=10.0, ki=60.0)),
          "nippy": (NIPPY, T.VelocityPIController(kp=5.5, ki=33.0)),
          "burly": (BURLY, T.VelocityPIController(kp=29.0, ki=175.0)),
          "even": (EVEN, T.VelocityPIController(kp=12.0, ki=72.0)),
          "crisp": (CRISP, T.VelocityPIController(kp=6.6, ki=40.0)),
          "stocky": (STOCKY, T.VelocityPIController(kp=23.0, ki=138.0)),
          "supple": (SUPPLE, T.VelocityPIController(kp=3.7, ki=22.0)),
          "lanky": (LANKY, T.VelocityPIController(kp=4.3, ki=26.0)),
          "chunky": (CHUNKY, T.VelocityPIController(kp=25.0, ki=152.0)),
          "poised": (POISED, T.VelocityPIController(kp=8.5, ki=51.0)),
          "wiry14": (WIRY14, T.VelocityPIController(kp=4.8, ki=29.0)),
          "bulky14": (BULKY14, T.VelocityPIController(kp=27.0, ki=160.0)),
          "trim": (TRIM, T.VelocityPIController(kp=10.0, ki=60.0)),
          "spare": (SPARE, T.VelocityPIController(kp=3.9, ki=23.5)),
          "husky": (HUSKY, T.VelocityPIController(kp=24.0, ki=145.0)),
          "tidy": (TIDY, T.VelocityPIController(kp=9.0, ki=54.0))}


class PidTuning(NamedTuple):
    """A position PID's tuning for its plant: ``T.PositionPIDController.tuned(plant.J, bandwidth_hz,
    tf=tf)`` (the gains follow the plant's inertia, so it is not repeated here)."""
    bandwidth_hz: float
    tf: float


# position PIDs (job key "controller": "pid"; "pid_nff": without the velocity feedforward): the rigid
# joint's poles placed at 2.5-3.5 Hz, damping 0.8, derivative filter 2-5 ms
PIDS = {"issue": PidTuning(3.0, 0.002), "paper_like": PidTuning(2.5, 0.004),
        "medium": PidTuning(3.0, 0.003), "nimble": PidTuning(3.5, 0.002),
        "sluggish": PidTuning(2.5, 0.005), "middle": PidTuning(3.0, 0.003),
        "light": PidTuning(3.5, 0.002), "heavy": PidTuning(2.5, 0.005),
        "flat": PidTuning(3.0, 0.003),
        "stiff": PidTuning(3.0, 0.003), "soft": PidTuning(2.5, 0.005),
        "tiny": PidTuning(3.5, 0.002),
        "sharp": PidTuning(3.0, 0.003), "massive": PidTuning(2.5, 0.005),
        "damped": PidTuning(3.5, 0.002),
        "brisk": PidTuning(3.0, 0.003),
        "hefty": PidTuning(2.5, 0.005),
        "dainty": PidTuning(3.5, 0.002),
        "stout": PidTuning(2.5, 0.005),
        "slender": PidTuning(3.5, 0.002),
        "keen": PidTuning(3.0, 0.003),
        "modest": PidTuning(3.0, 0.003),
        "feather": PidTuning(3.5, 0.002),
        "bulky": PidTuning(2.5, 0.005),
        "taut": PidTuning(3.0, 0.003),
        "wiry": PidTuning(3.5, 0.002),
        "portly": PidTuning(2.5, 0.005),
        "brawny": PidTuning(2.5, 0.005),
        "spry": PidTuning(3.5, 0.002),
        "sturdy": PidTuning(3.0, 0.003),
        "lithe": PidTuning(3.5, 0.002),
        "hulking": PidTuning(2.5, 0.005),
        "steady": PidTuning(3.0, 0.003),
        "nippy": PidTuning(3.5, 0.002),
        "burly": PidTuning(2.5, 0.005),
        "even": PidTuning(3.0, 0.003),
        "crisp": PidTuning(3.0, 0.003),
        "stocky": PidTuning(2.5, 0.005),
        "supple": PidTuning(3.5, 0.002),
        "lanky": PidTuning(3.5, 0.002),
        "chunky": PidTuning(2.5, 0.005),
        "poised": PidTuning(3.0, 0.003),
        "wiry14": PidTuning(3.5, 0.002),
        "bulky14": PidTuning(2.5, 0.005),
        "trim": PidTuning(3.0, 0.003),
        "spare": PidTuning(3.5, 0.002),
        "husky": PidTuning(2.5, 0.005),
        "tidy": PidTuning(3.0, 0.003)}


def controller_of(job):
    plant, pi = PLANTS[job["plant"]]
    kind = job.get("controller", "pi")
    if kind == "pi":
        return plant, pi
    tuning = PIDS[job["plant"]]
    pid = T.PositionPIDController.tuned(plant.J, tuning.bandwidth_hz, tf=tuning.tf)
    if kind == "pid_nff":
        pid = dataclasses.replace(pid, kff=0.0)
    return plant, pid


def true_kinematics(g, z0_sign=0.0):
    """The generator's exact motion of the generated recording ``g`` as the diagnosis's
    ``Kinematics`` (the bristles along the true path; ``z0_sign`` their initial deflection's
    direction)."""
    import jax.numpy as jnp

    from lugre_jax.diagnose import Kinematics

    t, th = np.asarray(g.time, float), np.asarray(g.true["theta"], float)
    return Kinematics(jnp.asarray(t), jnp.asarray(th), jnp.asarray(g.true["omega"]),
                      jnp.asarray(g.true["acceleration"]), jnp.asarray(np.diff(t)), jnp.asarray(np.diff(th)),
                      jnp.asarray(z0_sign))


def true_params(job) -> dict:
    """The generator plant's parameters of ``job`` as a ``params`` dict for ``diagnose`` (no offset)."""
    plant, _ = controller_of(job)
    return {k: float(getattr(plant, k)) for k in ("J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "delta")}


def study_cli(doc: str, *more) -> tuple[argparse.Namespace, Path, Path]:
    """The per-study analysis scripts' options (``--study``, ``--cache``, ``--out``, and ``more``:
    ``(flag, add_argument keywords)`` pairs), parsed, with lugre_jax configured; returns (args, the
    study's results folder, the output folder, made)."""
    import lugre_jax

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--study", choices=sorted(SETTINGS), required=True)
    for flag, kw in more:
        ap.add_argument(flag, **kw)
    ap.add_argument("--cache", default=None, help="generated-recording cache (default <results>/<study>/cache)")
    ap.add_argument("--out", default=None, help="output folder (default <results>/<study>)")
    a = ap.parse_args()
    lugre_jax.configure()
    res = Path(__file__).resolve().with_name("results") / a.study
    out = Path(a.out) if a.out else res
    out.mkdir(parents=True, exist_ok=True)
    return a, res, out


def effect_rows(doc: str, name: str) -> tuple[list, Path, Path]:
    """The per-row analysis scripts' options (:func:`study_cli` with ``--only``, comma-separated job
    keys): the study's effect rows (those keys alone where given), its generated-recording cache and
    the output file ``<out>/<name>_<study>.jsonl``."""
    args, res, out_dir = study_cli(doc, ("--only", {"default": "", "help": "comma-separated job keys"}))
    keys = [k for k in args.only.split(",") if k]
    rows = [job for job in jobs(args.study, [11], [1.0, 0.5])
            if job["expected"] != "none" and (not keys or job["key"] in keys)]
    return rows, Path(args.cache) if args.cache else res / "cache", out_dir / f"{name}_{args.study}.jsonl"


def run_effect_rows(doc: str, name: str, evidence, line) -> None:
    """The per-row analysis scripts' loop over :func:`effect_rows`: ``evidence(job, cache)`` per row,
    appended as JSON to the output file and printed as ``line(row)``."""
    rows, cache, out = effect_rows(doc, name)
    for job in rows:
        row = evidence(job, cache)
        with open(out, "a") as fh:
            fh.write(json.dumps(row) + "\n")
        print(line(row), flush=True)


def null_settings(n: int = 32):
    """``n`` effect-free settings: a deterministic walk through the grid, so that every value of
    every setting appears (not the full product)."""
    fs = [100.0, 200.0, 500.0, 1000.0]
    tn = [0.02, 0.08, 0.2]
    vn = [0.0, 0.003, 0.01]
    qs = [0.0, 0.0005, 0.005]
    exc = ["staircase", "staircase_sharp", "sine_sweep", "multisine"]
    out = []
    for i in range(n):
        out.append({"key": f"null{i:02d}", "plant": "issue" if i % 2 == 0 else "paper_like",
                    "excitation": exc[i % 4], "fs": fs[(i // 4) % 4], "torque_noise": tn[i % 3],
                    "velocity_noise": vn[(i // 3) % 3], "quantisation": qs[(i // 2) % 3],
                    "velocity_column": (i // 5) % 2 == 0, "effects": [], "seed": 1000 + i,
                    "short": True})
    # a tachometer without an encoder: velocity only (the position is its integral)
    for k, (plant, exc, fs, tn, vn) in enumerate([("issue", "staircase", 200.0, 0.08, 0.003),
                                                  ("paper_like", "staircase_sharp", 500.0, 0.02, 0.01),
                                                  ("issue", "multisine", 1000.0, 0.2, 0.0),
                                                  ("paper_like", "sine_sweep", 100.0, 0.08, 0.003)]):
        out.append({"key": f"null{n + k:02d}", "plant": plant, "excitation": exc, "fs": fs, "torque_noise": tn,
                    "velocity_noise": vn, "quantisation": 0.0, "velocity_column": True, "position_column": False,
                    "effects": [], "seed": 1000 + n + k, "short": True})
    # coloured torque noise (a drive's filtered or averaged current): first-order low-pass corners
    # from 2 to 40 Hz, the std as above; every excitation, 100-500 Hz
    for k, (plant, exc, fs, hz, tn) in enumerate([("issue", "staircase", 200.0, 10.0, 0.08),
                                                  ("paper_like", "staircase_sharp", 100.0, 2.0, 0.08),
                                                  ("issue", "sine_sweep", 500.0, 40.0, 0.2),
                                                  ("paper_like", "multisine", 200.0, 5.0, 0.02),
                                                  ("issue", "staircase", 500.0, 2.0, 0.08),
                                                  ("paper_like", "sine_sweep", 100.0, 10.0, 0.08)]):
        out.append({"key": f"null{n + 4 + k:02d}", "plant": plant, "excitation": exc, "fs": fs, "torque_noise": tn,
                    "torque_noise_hz": hz, "velocity_noise": 0.003, "quantisation": 0.0005 if k % 2 else 0.0,
                    "velocity_column": True, "effects": [], "seed": 1100 + k, "short": True})
    return out


def heldout_settings():
    """A null set and issue-kind recordings that no threshold was calibrated on:
    two further plants and controllers, sample rates, noise levels and excitation parameters off
    the null study's grid, the paper's sine tracking, and issue #20's recording kind on two
    further seeds (another level order and noise draw)."""
    out = []
    for k, (plant, exc, kw, fs, tn, vn, q, vcol) in enumerate([
            ("light", "staircase", {"speeds": (0.005, 0.02, 0.08, 0.3, 1.2, 5.0), "dwell": 6.0}, 150.0, 0.04, 0.002, 0.0005, True),
            ("light", "sine_sweep", {"amplitude": 1.0, "f0": 0.1, "f1": 3.0, "duration": 80.0}, 400.0, 0.12, 0.005, 0.001, False),
            ("light", "multisine", {"amplitude": 3.0, "duration": 80.0}, 250.0, 0.3, 0.0, 0.002, True),
            ("light", "staircase_sharp", {"dwell": 5.0}, 800.0, 0.05, 0.005, 0.0, False),
            ("heavy", "staircase", {"speeds": (0.02, 0.05, 0.2, 0.6, 2.0, 6.0), "dwell": 7.0, "transition": 1.5}, 250.0, 0.12, 0.0, 0.001, True),
            ("heavy", "sine_sweep", {"amplitude": 4.0, "f0": 0.03, "f1": 1.0, "duration": 90.0, "bias": 0.8}, 150.0, 0.04, 0.005, 0.0, True),
            ("heavy", "multisine", {"amplitude": 1.5, "f0": 0.05, "f1": 2.5, "n": 8, "duration": 70.0}, 400.0, 0.3, 0.002, 0.0005, False),
            ("heavy", "staircase_sharp", {"dwell": 5.0}, 150.0, 0.05, 0.0, 0.002, False),
            ("issue", "position_sine", {"duration": 40.0}, 300.0, 0.08, 0.003, 0.0005, True),
            ("paper_like", "position_sine", {"amplitude": 5.0, "frequency": 0.2, "duration": 60.0}, 120.0, 0.05, 0.0, 0.001, False),
            ("issue", "staircase", {"dwell": 6.0}, 300.0, 0.15, 0.005, 0.0, True),
            ("paper_like", "staircase", {"dwell": 6.0, "transition": 1.0}, 600.0, 0.06, 0.002, 0.0005, False)]):
        out.append({"key": f"held_null{k:02d}", "plant": plant, "excitation": exc, "excitation_kw": kw, "fs": fs,
                    "torque_noise": tn, "velocity_noise": vn, "quantisation": q, "velocity_column": vcol,
                    "effects": [], "seed": 3000 + k})
    # effects on the new plants, about the issue's sizes relative to the noise (peak/noise ~1)
    for k, (plant, exc, kw, fs, tn, vn, q, vcol, effect) in enumerate([
            ("light", "staircase", {"speeds": (0.005, 0.02, 0.08, 0.3, 1.2, 5.0), "dwell": 6.0}, 150.0, 0.04, 0.002, 0.0005, True, "asymmetry"),
            ("light", "sine_sweep", {"amplitude": 1.0, "f0": 0.1, "f1": 3.0, "duration": 80.0, "bias": 2.0}, 400.0, 0.05, 0.005, 0.001, False, "position_ripple"),
            ("heavy", "staircase", {"speeds": (0.02, 0.05, 0.2, 0.6, 2.0, 6.0), "dwell": 7.0, "transition": 1.5}, 250.0, 0.12, 0.0, 0.001, True, "position_ripple"),
            ("heavy", "multisine", {"amplitude": 1.5, "f0": 0.05, "f1": 2.5, "n": 8, "duration": 70.0}, 400.0, 0.1, 0.002, 0.0005, False, "asymmetry"),
            ("heavy", "staircase_sharp", {"dwell": 5.0}, 150.0, 0.05, 0.0, 0.002, False, "stribeck_shape"),
            ("paper_like", "staircase", {"dwell": 6.0, "transition": 1.0}, 600.0, 0.06, 0.002, 0.0005, False, "thermal_drift"),
            ("light", "sine_sweep", {"amplitude": 1.0, "f0": 0.05, "f1": 1.0, "duration": 100.0, "bias": 3.0}, 300.0, 0.04, 0.002, 0.0, True, "gravity")]):
        out.append({"key": f"held_effect{k:02d}_{effect}", "plant": plant, "excitation": exc, "excitation_kw": kw,
                    "fs": fs, "torque_noise": tn, "velocity_noise": vn, "quantisation": q, "velocity_column": vcol,
                    "effects": effect, "seed": 3100 + k})
    for sd in (21, 22):
        out += [{"key": f"held_issue_{k}_{sd}", "plant": "issue", "excitation": "staircase", "fs": 200.0,
                 "torque_noise": 0.08, "velocity_noise": 0.003, "quantisation": 0.0005,
                 "velocity_column": True, "effects": k, "seed": sd} for k in ISSUE_EFFECTS]
    return out


def fresh_settings():
    """The second held-out set, fixed before its first run: eight effect-free
    recordings and nine with effects at the issue's and the slow tests' sizes (one per candidate,
    plus ripple + asymmetry), on two further plants (MEDIUM, FLAT), staircases with 10-s and 2.5-s
    dwells (periods of whole multiples and halves of the five held-out blocks), 100-1,000 Hz."""
    stair10 = {"speeds": (0.01, 0.04, 0.15, 0.6, 2.5), "dwell": 10.0}
    sweep = {"amplitude": 2.0, "f0": 0.05, "f1": 1.5, "duration": 90.0, "bias": 0.5}
    flat_sweep = {"amplitude": 3.0, "f0": 0.02, "f1": 0.8, "duration": 100.0, "bias": 1.0}
    multi = {"amplitude": 1.0, "f0": 0.1, "f1": 2.0, "n": 6, "duration": 60.0}
    sharp = {"speeds": (0.02, 0.1, 0.4, 1.5, 5.0), "dwell": 2.5}
    issue10 = {"dwell": 10.0}
    nulls = [
        ("medium", "staircase", stair10, 180.0, 0.06, 0.002, 0.0005, True),
        ("medium", "sine_sweep", sweep, 700.0, 0.1, 0.004, 0.001, False),
        ("medium", "multisine", {"amplitude": 2.5, "f0": 0.03, "f1": 1.2, "n": 10, "duration": 90.0},
         333.0, 0.04, 0.003, 0.0, True),
        ("medium", "position_sine", {"amplitude": 8.0, "frequency": 0.1, "duration": 60.0}, 250.0, 0.05, 0.0,
         0.0005, False),
        ("flat", "staircase_sharp", sharp, 1000.0, 0.1, 0.003, 0.0005, True),
        ("flat", "sine_sweep", flat_sweep, 180.0, 0.15, 0.0, 0.002, False),
        ("flat", "multisine", multi, 500.0, 0.08, 0.005, 0.0005, True),
        ("issue", "staircase", issue10, 100.0, 0.08, 0.003, 0.0005, True)]
    effects = [
        ("medium", "staircase", stair10, 180.0, 0.06, 0.002, 0.0005, True, "asymmetry"),
        ("flat", "sine_sweep", flat_sweep, 180.0, 0.08, 0.0, 0.002, False, "gravity"),
        ("issue", "staircase", issue10, 100.0, 0.08, 0.003, 0.0005, True, "position_ripple"),
        ("flat", "staircase_sharp", sharp, 1000.0, 0.1, 0.003, 0.0005, True, "thermal_drift"),
        ("medium", "staircase", stair10, 180.0, 0.06, 0.002, 0.0005, True, "stribeck_shape"),
        ("flat", "multisine", multi, 500.0, 0.08, 0.005, 0.0005, True, "load_dependent"),
        ("medium", "sine_sweep", sweep, 700.0, 0.1, 0.004, 0.001, False, "compliance"),
        ("flat", "staircase", {**sharp, "transition": 0.5}, 180.0, 0.05, 0.002, 0.0005, True, "backlash"),
        ("issue", "staircase", issue10, 100.0, 0.08, 0.003, 0.0005, True, "position_ripple+asymmetry")]
    out = []
    for kind, rows in (("null", [r + ("",) for r in nulls]), ("effect", effects)):
        for k, (plant, exc, kw, fs, tn, vn, q, vcol, effect) in enumerate(rows):
            out.append({"key": f"fresh_{kind}{k:02d}" + (f"_{effect}" if effect else ""), "plant": plant,
                        "excitation": exc, "excitation_kw": kw, "fs": fs, "torque_noise": tn,
                        "velocity_noise": vn, "quantisation": q, "velocity_column": vcol,
                        "effects": effect or [], "seed": (4000 if kind == "null" else 4100) + k})
    return out


# ---------------------------------------------------------------------------------------------
# Studies of the rebuilt diagnosis (issues #30, #31): calib, fresh3, outside. Their settings were
# fixed and committed before their first run; only generation (tracking, effect peaks) was looked at.

# excitation kinds of the calibration set, each < 60 s (60,000 samples at 1 kHz)
CALIB_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.01, 0.04, 0.15, 0.6, 2.0, 4.0), "dwell": 4.5 if i % 2 else 4.0,
                            "transition": 0.5, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.0 + 0.5 * (i % 3), "f0": 0.05, "f1": 2.0, "duration": 59.0,
                             "bias": 0.3 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0, "f0": 0.02, "f1": 1.0 + 0.5 * (i % 3), "n": 10 + 2 * (i % 2),
                            "duration": 59.0},
    "position_sine": lambda i: {"amplitude": 4.0 + 2.0 * (i % 3), "frequency": 0.15 + 0.1 * (i % 2), "duration": 50.0},
    "point_to_point": lambda i: {"amplitudes": (2.0, -2.0, 4.0, 0.0, -4.0, 1.0) if i % 2 else (3.0, 0.5, -3.0, 5.0, -1.0, 0.0),
                                 "move_time": 1.5 + 0.5 * (i % 2), "dwell": 2.9, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.02, 0.1, 0.5, 2.0, 5.0), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib_settings(n: int = 48):
    """``n`` effect-free recordings for calibrating the rebuilt diagnosis (issue #30): a
    deterministic walk over six excitations (staircase with dwells, sine sweep, multisine, position
    sine, point-to-point moves with dwells, fast sharp steps) x two loops (velocity PI, position
    PID) x three sensor sets (encoder and tachometer, encoder only, tachometer only) -- all 36
    combinations in the first 36 rows -- on three plants (issue, paper_like, medium), 100-1,000 Hz,
    torque noise 0.03-0.12 N*m, white in half the rows and AR(1) of coefficient 0.3, 0.6 or 0.85 in
    the other half; velocity noise 0-0.01 deg/s, quantisation 0.0002-0.002 deg."""
    exc = list(CALIB_EXCITATIONS)
    sensors = [(True, True), (True, False), (False, True)]  # (position, velocity) columns
    plants = ["issue", "paper_like", "medium"]
    fs = [100.0, 200.0, 250.0, 500.0, 1000.0]
    tn = [0.03, 0.06, 0.08, 0.12]
    ar = [0.0, 0.3, 0.0, 0.6, 0.0, 0.85]
    out = []
    for i in range(n):
        e, c, (pcol, vcol) = exc[i % 6], ("pi", "pid")[(i // 6) % 2], sensors[(i // 12) % 3]
        ctrl = "pid_nff" if c == "pid" and i % 4 == 3 else c
        out.append({"key": f"calib{i:02d}_{e}_{ctrl}", "plant": plants[(i + i // 6) % 3], "controller": ctrl,
                    "excitation": e, "excitation_kw": CALIB_EXCITATIONS[e](i), "fs": fs[(3 * i + i // 6) % 5],
                    "torque_noise": tn[(i + i // 4) % 4], "torque_noise_ar": ar[(i + i // 12) % 6],
                    "velocity_noise": [0.0, 0.003, 0.01][(i // 2) % 3] if vcol else 0.0,
                    "quantisation": [0.0002, 0.0005, 0.001, 0.002][(i // 3) % 4] if pcol else 0.0,
                    "position_column": pcol, "velocity_column": vcol, "effects": [], "seed": 6000 + i,
                    "expected": "none"})
    return out


# fresh3's excitations (parameters no earlier study used)
F3_STAIR = {"speeds": (0.015, 0.05, 0.2, 0.8, 3.0), "dwell": 5.0, "transition": 0.4, "repeats": 1}
F3_SHARP = {"speeds": (0.03, 0.15, 0.6, 2.5, 6.0), "dwell": 3.0, "transition": 0.0, "repeats": 2}
F3_SWEEP = {"amplitude": 2.5, "f0": 0.04, "f1": 1.8, "duration": 55.0, "bias": 0.6}
F3_MULTI = {"amplitude": 1.8, "f0": 0.03, "f1": 1.8, "n": 9, "duration": 50.0}
F3_PSINE = {"amplitude": 12.0, "frequency": 0.15, "duration": 50.0}
F3_P2P = {"amplitudes": (3.0, -3.0, 6.0, -1.0, -6.0, 2.0), "move_time": 2.5, "dwell": 2.5, "repeats": 2}
# wide position spans (gravity: a sine of the angle must differ from a line)
F3_PSINE_WIDE = {"amplitude": 35.0, "frequency": 0.05, "duration": 50.0}
F3_P2P_WIDE = {"amplitudes": (25.0, -25.0, 40.0, -40.0, 0.0), "move_time": 6.0, "dwell": 4.0, "repeats": 1}
F3_SWEEP_WIDE = {"amplitude": 3.0, "f0": 0.03, "f1": 1.0, "duration": 60.0, "bias": 4.0}

# (plant, controller, excitation, kw, fs, torque noise, AR(1), velocity noise, quantisation,
#  position column, velocity column)
_F3_RECIPES = {
    "a": ("nimble", "pi", "staircase", F3_STAIR, 240.0, 0.06, 0.0, 0.002, 0.0005, True, True),
    "b": ("sluggish", "pid", "point_to_point", F3_P2P, 450.0, 0.1, 0.0, 0.0, 0.0005, True, False),
    "c": ("middle", "pi", "sine_sweep", F3_SWEEP, 160.0, 0.08, 0.4, 0.004, 0.001, True, True),
    "d": ("nimble", "pid", "multisine", F3_MULTI, 900.0, 0.05, 0.0, 0.003, 0.0, False, True),
    "e": ("middle", "pid_nff", "sharp_steps", F3_SHARP, 600.0, 0.12, 0.0, 0.005, 0.0005, True, True),
    "f": ("sluggish", "pi", "position_sine", F3_PSINE, 300.0, 0.07, 0.5, 0.0, 0.001, True, False),
    "g": ("middle", "pid", "position_sine", F3_PSINE_WIDE, 240.0, 0.06, 0.0, 0.003, 0.0005, True, True),
    "h": ("nimble", "pi", "point_to_point", F3_P2P_WIDE, 160.0, 0.08, 0.0, 0.0, 0.0005, True, False),
    "i": ("sluggish", "pi", "sine_sweep", F3_SWEEP_WIDE, 300.0, 0.1, 0.3, 0.004, 0.001, True, True),
}

# each in-library effect at the concealed level on three of the recipes: (recipe, effect id,
# parameters); the parameters put the effect's peak torque at 0.6-0.9 of the recording's per-sample
# torque noise std (measured on the generated recordings: run.py --study fresh3 --generate-only)
FRESH3_EFFECTS = [
    ("g", "gravity", {"amplitude": 0.05, "phase": 0.7}),
    ("h", "gravity", {"amplitude": 0.065, "phase": -1.2}),
    ("i", "gravity", {"amplitude": 0.08, "phase": 2.0}),
    ("a", "asymmetry", {"offset": 0.048}),
    ("d", "asymmetry", {"offset": -0.04}),
    ("f", "asymmetry", {"offset": 0.056}),
    ("b", "position_ripple", {"amplitude": 0.08, "period": 3.0, "phase": 0.5}),
    ("c", "position_ripple", {"amplitude": 0.065, "period": 4.0, "phase": -1.0}),
    ("e", "position_ripple", {"amplitude": 0.095, "period": 2.5, "phase": 2.2}),
    ("a", "thermal_drift", {"rate": -0.0007}),
    ("b", "thermal_drift", {"rate": 0.00024}),
    ("e", "thermal_drift", {"rate": -0.00065}),
    ("c", "stribeck_shape", {"delta": 1.25}),
    ("d", "stribeck_shape", {"delta": 3.3}),
    ("h", "stribeck_shape", {"delta": 0.95}),
    ("b", "load_dependent", {"mu": 0.035, "v_eps": 0.02}),
    ("d", "load_dependent", {"mu": 0.0625, "v_eps": 0.02}),
    ("e", "load_dependent", {"mu": 0.0062, "v_eps": 0.02}),
    ("b", "compliance", {"fn": 5.0, "zeta": 0.1, "J_load": 0.0625}),
    ("c", "compliance", {"fn": 4.0, "zeta": 0.08, "J_load": 0.0048}),
    ("d", "compliance", {"fn": 6.0, "zeta": 0.1, "J_load": 0.0045}),
    ("a", "backlash", {"width": 0.02, "share": 0.0195}),
    ("e", "backlash", {"width": 0.03, "share": 0.03}),
    ("f", "backlash", {"width": 0.02, "share": 0.0067}),
]
FRESH3_NULL_RECIPES = ("a", "b", "c", "d", "e", "f", "g", "i")


def _recipe_job(key, recipe, seed, spec, expected, recipes=None):
    plant, ctrl, exc, kw, fs, tn, ar, vn, q, pcol, vcol = (recipes or _F3_RECIPES)[recipe]
    return {"key": key, "recipe": recipe, "plant": plant, "controller": ctrl, "excitation": exc,
            "excitation_kw": kw, "fs": fs, "torque_noise": tn, "torque_noise_ar": ar, "velocity_noise": vn,
            "quantisation": q, "position_column": pcol, "velocity_column": vcol,
            "effects": [e for e, _ in spec], "effect_spec": spec, "seed": seed, "expected": expected}


def _varied(gravity_phase: float, ripple_period: float, ripple_phase: float) -> dict:
    """A fresh set's changes to fresh3's effects: the gravity's phase moved by ``gravity_phase``, the
    asymmetry's sign flipped, the ripple's period scaled by ``ripple_period`` and its phase moved by
    ``ripple_phase`` (sizes unchanged, so the concealed level carries over)."""
    return {"gravity": lambda kw: kw | {"phase": kw["phase"] + gravity_phase},
            "asymmetry": lambda kw: kw | {"offset": -kw["offset"]},
            "position_ripple": lambda kw: kw | {"period": ripple_period * kw["period"],
                                                "phase": kw["phase"] + ripple_phase}}


def _refreshed(prefix, fs, varied, seed0):
    """fresh3's 24 effect rows (FRESH3_EFFECTS) at the recipes' rates ``fs`` (by recipe) and seeds
    ``seed0 + k``, each effect's parameters passed through ``varied[effect id]`` where it has one."""
    recipes = {k: r[:4] + (fs[k],) + r[5:] for k, r in _F3_RECIPES.items()}
    return [_recipe_job(f"{prefix}_effect{k:02d}_{eid}_{r}", r, seed0 + k,
                        [(eid, varied.get(eid, dict)(dict(kw)))], eid, recipes)
            for k, (r, eid, kw) in enumerate(FRESH3_EFFECTS)]


def fresh3_settings():
    """A fresh set for the rebuilt diagnosis (issue #30), fixed and committed before its first run:
    each in-library effect at the concealed level on three recordings (24 rows) and eight
    effect-free ones, on three plants no earlier study used (NIMBLE, SLUGGISH, MIDDLE), both loops,
    160-900 Hz, white and AR(1) torque noise. ``expected``: the exact verdict (the effect's id)."""
    out = [_recipe_job(f"fresh3_null{k:02d}_{r}", r, 5000 + k, [], "none")
           for k, r in enumerate(FRESH3_NULL_RECIPES)]
    out += [_recipe_job(f"fresh3_effect{k:02d}_{eid}_{r}", r, 5100 + k, [(eid, kw)], eid)
            for k, (r, eid, kw) in enumerate(FRESH3_EFFECTS)]
    return out


# calib2's excitations: the six kinds of calib with other parameters
CALIB2_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.02, 0.07, 0.3, 1.0, 3.0), "dwell": 5.0 if i % 2 else 5.5,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.5 + 0.7 * (i % 3), "f0": 0.04, "f1": 1.6, "duration": 55.0,
                             "bias": 0.5 + 0.4 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.5, "f0": 0.03, "f1": 1.2 + 0.4 * (i % 3), "n": 9 + 3 * (i % 2),
                            "duration": 55.0},
    "position_sine": lambda i: {"amplitude": 3.0 + 3.0 * (i % 3), "frequency": 0.12 + 0.08 * (i % 2),
                                "duration": 45.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -1.5, 5.0, -0.5, -3.5, 0.0) if i % 2 else (4.0, -2.0, 1.0, -4.0, 2.0),
                                 "move_time": 1.2 + 0.6 * (i % 2), "dwell": 2.4, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.03, 0.12, 0.6, 2.5, 6.0), "dwell": 2.2, "transition": 0.0, "repeats": 2},
}


def _effect_free_set(prefix, excitations, plants, sensors, fs, tn, ar, vn, q, seed0, n, *, loops, nff, plant_k,
                     fs_k, tn_rule):
    """The effect-free sets' design (calib2-4): row i cycles the six excitations, then the loops
    (``loops``, with ``pid_nff`` where ``i % 4 == nff``), then the sensor sets every 12 rows; the
    plant is ``plants[(i + plant_k*(i//6)) % 3]``, the rate ``fs[(fs_k*i + i//6) % 5]``, the torque
    noise ``tn[(i + m*(i//d)) % 3]`` (``tn_rule = (m, d)``), its AR coefficient
    ``ar[(i + i//6) % 4]``, velocity noise ``vn[(i//2) % 2]`` and quantisation
    ``q[(i//3) % len(q)]`` where the column exists; seed ``seed0 + i``."""
    exc = list(excitations)
    m, d = tn_rule
    out = []
    for i in range(n):
        e, c, (pcol, vcol) = exc[i % 6], loops[(i // 6) % 2], sensors[(i // 12) % 3]
        ctrl = "pid_nff" if c == "pid" and i % 4 == nff else c
        out.append({"key": f"{prefix}_{i:02d}_{e}_{ctrl}", "plant": plants[(i + plant_k * (i // 6)) % 3],
                    "controller": ctrl, "excitation": e, "excitation_kw": excitations[e](i),
                    "fs": fs[(fs_k * i + i // 6) % 5], "torque_noise": tn[(i + m * (i // d)) % 3],
                    "torque_noise_ar": ar[(i + i // 6) % 4], "velocity_noise": vn[(i // 2) % 2] if vcol else 0.0,
                    "quantisation": q[(i // 3) % len(q)] if pcol else 0.0,
                    "position_column": pcol, "velocity_column": vcol, "effects": [], "seed": seed0 + i,
                    "expected": "none"})
    return out


def calib2_settings(n: int = 40):
    """A second effect-free set (issues #30 and #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    calib does not use (LIGHT, HEAVY, FLAT), 120-800 Hz, torque noise 0.04-0.1 N*m, white in half the rows and
    AR(1) of coefficient 0.45 or 0.7 in the other half, velocity noise 0.002-0.006 deg/s,
    quantisation 0.0003-0.0015 deg; seeds 7000 + i."""
    return _effect_free_set("calib2", CALIB2_EXCITATIONS, ["light", "heavy", "flat"],
                            [(True, False), (False, True), (True, True)], [120.0, 300.0, 400.0, 600.0, 800.0],
                            [0.04, 0.07, 0.1], [0.0, 0.45, 0.0, 0.7], [0.002, 0.006], [0.0003, 0.0008, 0.0015],
                            7000, n, loops=("pid", "pi"), nff=1, plant_k=2, fs_k=2, tn_rule=(1, 5))


# fresh4: fresh3's recipes at other sampling rates and seeds; the effect-free rows also on other
# plants. The effect rows keep each recipe's plant, excitation and noise, so the concealed level
# (peak effect torque 0.6-0.9 of the noise std) carries over from fresh3's design; the effects'
# phases, periods and signs are changed where that leaves their size alone.
_F4_PLANT = {"a": "middle", "b": "nimble", "c": "sluggish", "d": "sluggish", "e": "nimble", "f": "middle",
             "g": "sluggish", "h": "middle", "i": "nimble"}
_F4_FS = {"a": 200.0, "b": 500.0, "c": 180.0, "d": 800.0, "e": 700.0, "f": 250.0, "g": 300.0, "h": 200.0, "i": 350.0}
_F4_RECIPES = {k: r[:4] + (_F4_FS[k],) + r[5:] for k, r in _F3_RECIPES.items()}
_F4_NULL_RECIPES = {k: (_F4_PLANT[k],) + r[1:] for k, r in _F4_RECIPES.items()}
_F4_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] + 1.0},
              "asymmetry": lambda kw: kw | {"offset": -kw["offset"]},
              "position_ripple": lambda kw: kw | {"period": 1.3 * kw["period"], "phase": kw["phase"] - 0.8},
              "thermal_drift": lambda kw: kw | {"rate": -kw["rate"]}}


def fresh4_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows
    at other sampling rates and seeds (8100 + k), with the gravity's phase, the asymmetry's and
    drift's sign and the ripple's period and phase changed; eight effect-free rows on other plants
    and rates (seeds 8000 + k)."""
    out = [_recipe_job(f"fresh4_null{k:02d}_{r}", r, 8000 + k, [], "none", _F4_NULL_RECIPES)
           for k, r in enumerate(FRESH3_NULL_RECIPES)]
    out += [_recipe_job(f"fresh4_effect{k:02d}_{eid}_{r}", r, 8100 + k,
                        [(eid, _F4_VARIED.get(eid, dict)(dict(kw)))], eid, _F4_RECIPES)
            for k, (r, eid, kw) in enumerate(FRESH3_EFFECTS)]
    return out


# calib3's excitations: the six kinds with parameters neither calib nor calib2 used
CALIB3_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.015, 0.05, 0.2, 0.8, 2.5, 7.0), "dwell": 4.5 if i % 2 else 5.0,
                            "transition": 0.5, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.2 + 0.9 * (i % 3), "f0": 0.05, "f1": 2.0, "duration": 50.0,
                             "bias": 0.3 + 0.5 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 1.0 * (i % 2), "f0": 0.04, "f1": 1.0 + 0.5 * (i % 3),
                            "n": 8 + 4 * (i % 2), "duration": 50.0},
    "position_sine": lambda i: {"amplitude": 2.0 + 4.0 * (i % 3), "frequency": 0.1 + 0.1 * (i % 2),
                                "duration": 40.0},
    "point_to_point": lambda i: {"amplitudes": (3.0, -1.0, 4.5, -2.5, 0.5) if i % 2 else (-3.0, 2.0, -0.5, 4.0, -4.0, 1.0),
                                 "move_time": 1.0 + 0.8 * (i % 2), "dwell": 2.0, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.02, 0.1, 0.5, 2.0, 5.0), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib3_settings(n: int = 40):
    """A third effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier study used (STIFF, SOFT, TINY), 150-700 Hz, torque noise 0.03-0.09 N*m, white in half
    the rows and AR(1) of coefficient 0.3 or 0.6 in the other half, velocity noise 0.003-0.005
    deg/s, quantisation 0.0004-0.001 deg; seeds 9000 + i."""
    return _effect_free_set("calib3", CALIB3_EXCITATIONS, ["stiff", "soft", "tiny"],
                            [(True, True), (True, False), (False, True)], [150.0, 250.0, 350.0, 500.0, 700.0],
                            [0.03, 0.06, 0.09], [0.3, 0.0, 0.6, 0.0], [0.003, 0.005], [0.0004, 0.001],
                            9000, n, loops=("pi", "pid"), nff=3, plant_k=1, fs_k=3, tn_rule=(2, 5))


# calib4's excitations: the six kinds with parameters no earlier set used
CALIB4_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.03, 0.1, 0.4, 1.5, 4.0), "dwell": 5.0 if i % 2 else 4.0,
                            "transition": 0.4, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.0 + 1.0 * (i % 3), "f0": 0.03, "f1": 1.8, "duration": 50.0,
                             "bias": 0.4 + 0.6 * (i % 2)},
    "multisine": lambda i: {"amplitude": 1.5 + 1.5 * (i % 2), "f0": 0.05, "f1": 0.8 + 0.6 * (i % 3),
                            "n": 7 + 5 * (i % 2), "duration": 50.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 3.5 * (i % 3), "frequency": 0.08 + 0.12 * (i % 2),
                                "duration": 40.0},
    "point_to_point": lambda i: {"amplitudes": (2.0, -3.0, 3.5, -0.5, 1.5) if i % 2 else (-2.5, 3.0, 0.0, -4.5, 2.5, -1.0),
                                 "move_time": 0.9 + 0.9 * (i % 2), "dwell": 2.2, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.025, 0.15, 0.7, 3.0, 5.5), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib4_settings(n: int = 40):
    """A fourth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (SHARP, MASSIVE, DAMPED), 130-650 Hz, torque noise 0.04-0.08 N*m, white in half
    the rows and AR(1) of coefficient 0.4 or 0.65 in the other half, velocity noise 0.002-0.004
    deg/s, quantisation 0.0005-0.0012 deg; seeds 9500 + i."""
    return _effect_free_set("calib4", CALIB4_EXCITATIONS, ["sharp", "massive", "damped"],
                            [(False, True), (True, True), (True, False)], [130.0, 220.0, 330.0, 450.0, 650.0],
                            [0.05, 0.08, 0.04], [0.0, 0.4, 0.65, 0.0], [0.004, 0.002], [0.0012, 0.0005],
                            9500, n, loops=("pid", "pi"), nff=2, plant_k=2, fs_k=2, tn_rule=(1, 4))


# calib5's excitations: the six kinds with parameters no earlier set used
CALIB5_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.04, 0.15, 0.5, 2.0, 5.0), "dwell": 4.5 if i % 2 else 3.5,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.5 + 0.8 * (i % 3), "f0": 0.04, "f1": 1.5, "duration": 45.0,
                             "bias": 0.5 + 0.5 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 1.0 * (i % 2), "f0": 0.06, "f1": 1.0 + 0.5 * (i % 3),
                            "n": 8 + 4 * (i % 2), "duration": 45.0},
    "position_sine": lambda i: {"amplitude": 3.0 + 3.0 * (i % 3), "frequency": 0.1 + 0.1 * (i % 2),
                                "duration": 36.0},
    "point_to_point": lambda i: {"amplitudes": (3.0, -2.0, 4.0, -1.5, 2.0) if i % 2 else (-3.5, 2.5, -0.5, 4.0, -2.0, 1.0),
                                 "move_time": 1.0 + 0.8 * (i % 2), "dwell": 2.0, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.035, 0.2, 0.8, 2.5, 5.0), "dwell": 2.6, "transition": 0.0, "repeats": 2},
}


def calib5_settings(n: int = 40):
    """A fifth effect-free set (issues #30 and #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (BRISK, HEFTY, DAINTY), 160-750 Hz, torque noise 0.045-0.09 N*m, white in
    half the rows and AR(1) of coefficient 0.5 or 0.7 in the other half, velocity noise 0.003-0.005
    deg/s, quantisation 0.0008-0.0015 deg; seeds 9800 + i."""
    return _effect_free_set("calib5", CALIB5_EXCITATIONS, ["brisk", "hefty", "dainty"],
                            [(True, True), (True, False), (False, True)], [160.0, 240.0, 380.0, 520.0, 750.0],
                            [0.06, 0.045, 0.09], [0.0, 0.5, 0.0, 0.7], [0.003, 0.005], [0.0008, 0.0015],
                            9800, n, loops=("pi", "pid"), nff=1, plant_k=2, fs_k=1, tn_rule=(2, 3))


# calib6's excitations: the six kinds with parameters no earlier set used
CALIB6_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.03, 0.12, 0.6, 1.8, 4.5), "dwell": 4.0 if i % 2 else 3.2,
                            "transition": 0.25, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.6 * (i % 3), "f0": 0.05, "f1": 1.3, "duration": 40.0,
                             "bias": 0.4 + 0.6 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.5 + 0.8 * (i % 2), "f0": 0.05, "f1": 0.9 + 0.4 * (i % 3),
                            "n": 10 + 2 * (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.5 * (i % 3), "frequency": 0.12 + 0.08 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -3.0, 3.5, -1.0, 1.5) if i % 2 else (-2.5, 3.0, -1.5, 3.5, -2.5, 0.5),
                                 "move_time": 1.2 + 0.6 * (i % 2), "dwell": 1.8, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.04, 0.25, 0.7, 2.2, 4.5), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib6_settings(n: int = 40):
    """A sixth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (STOUT, SLENDER, KEEN), 180-880 Hz, torque noise 0.04-0.08 N*m, white in half
    the rows and AR(1) of coefficient 0.4 or 0.6 in the other half, velocity noise 0.002-0.004
    deg/s, quantisation 0.0006-0.0012 deg; seeds 10200 + i."""
    return _effect_free_set("calib6", CALIB6_EXCITATIONS, ["stout", "slender", "keen"],
                            [(True, True), (True, False), (False, True)], [180.0, 280.0, 440.0, 640.0, 880.0],
                            [0.05, 0.08, 0.04], [0.0, 0.4, 0.0, 0.6], [0.002, 0.004], [0.0006, 0.0012],
                            10200, n, loops=("pi", "pid"), nff=2, plant_k=1, fs_k=2, tn_rule=(1, 4))


# fresh7: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases and ripple periods changed again where that leaves their size alone
_F7_FS = {"a": 340.0, "b": 310.0, "c": 290.0, "d": 560.0, "e": 460.0, "f": 230.0, "g": 410.0, "h": 270.0, "i": 330.0}
_F7_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] - 2.9},
              "position_ripple": lambda kw: kw | {"period": 0.9 * kw["period"], "phase": kw["phase"] + 0.6}}


def fresh7_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (10400 + k), with the gravity's phase and the ripple's period and
    phase changed."""
    return _refreshed("fresh7", _F7_FS, _F7_VARIED, 10400)


# calib7's excitations: the six kinds with parameters no earlier set used
CALIB7_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.05, 0.18, 0.7, 2.4, 4.0), "dwell": 3.8 if i % 2 else 3.0,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.6 + 0.7 * (i % 3), "f0": 0.06, "f1": 1.2, "duration": 42.0,
                             "bias": 0.3 + 0.7 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.9 * (i % 2), "f0": 0.07, "f1": 0.8 + 0.45 * (i % 3),
                            "n": 9 + 3 * (i % 2), "duration": 42.0},
    "position_sine": lambda i: {"amplitude": 2.0 + 3.0 * (i % 3), "frequency": 0.15 + 0.07 * (i % 2),
                                "duration": 32.0},
    "point_to_point": lambda i: {"amplitudes": (3.0, -1.5, 2.5, -3.0, 1.0) if i % 2 else (-2.0, 3.5, -2.5, 1.5, -1.0, 2.5),
                                 "move_time": 1.1 + 0.7 * (i % 2), "dwell": 2.2, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.045, 0.22, 0.9, 2.0, 4.2), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib7_settings(n: int = 40):
    """A seventh effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (MODEST, FEATHER, BULKY), 200-820 Hz, torque noise 0.04-0.08 N*m, white in
    half the rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise
    0.0025-0.0045 deg/s, quantisation 0.0007-0.0013 deg; seeds 10600 + i."""
    return _effect_free_set("calib7", CALIB7_EXCITATIONS, ["modest", "feather", "bulky"],
                            [(True, True), (True, False), (False, True)], [200.0, 300.0, 470.0, 610.0, 820.0],
                            [0.06, 0.04, 0.08], [0.0, 0.5, 0.0, 0.65], [0.0025, 0.0045], [0.0007, 0.0013],
                            10600, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=3, tn_rule=(2, 5))


# fresh8: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F8_FS = {"a": 300.0, "b": 330.0, "c": 270.0, "d": 520.0, "e": 440.0, "f": 250.0, "g": 350.0, "h": 290.0, "i": 310.0}
_F8_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] + 1.3},
              "asymmetry": lambda kw: kw | {"offset": -kw["offset"]},
              "position_ripple": lambda kw: kw | {"period": 1.1 * kw["period"], "phase": kw["phase"] - 1.2},
              "thermal_drift": lambda kw: kw | {"rate": -kw["rate"]}}


def fresh8_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (10800 + k), with the gravity's phase, the asymmetry's and
    drift's sign and the ripple's period and phase changed."""
    return _refreshed("fresh8", _F8_FS, _F8_VARIED, 10800)


# calib8's excitations: the six kinds with parameters no earlier set used
CALIB8_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.04, 0.15, 0.55, 2.0, 3.6), "dwell": 3.5 if i % 2 else 2.8,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.7 + 0.5 * (i % 3), "f0": 0.05, "f1": 1.1, "duration": 40.0,
                             "bias": 0.35 + 0.5 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.4 + 0.7 * (i % 2), "f0": 0.06, "f1": 0.85 + 0.35 * (i % 3),
                            "n": 10 + 2 * (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.2 + 2.6 * (i % 3), "frequency": 0.13 + 0.06 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.0, -3.5, 1.5, -2.5, 3.0) if i % 2 else (-3.0, 2.0, -1.5, 3.0, -2.0, 1.5),
                                 "move_time": 1.3 + 0.5 * (i % 2), "dwell": 2.0, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.2, 0.75, 2.3, 4.4), "dwell": 2.3, "transition": 0.0, "repeats": 2},
}


def calib8_settings(n: int = 40):
    """An eighth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds with other parameters x both loops x the three sensor sets, on three
    plants no earlier set used (TAUT, WIRY, PORTLY), 190-850 Hz, torque noise 0.045-0.085 N*m, white
    in half the rows and AR(1) of coefficient 0.45 or 0.6 in the other half, velocity noise
    0.002-0.004 deg/s, quantisation 0.0007-0.0014 deg; seeds 11000 + i."""
    return _effect_free_set("calib8", CALIB8_EXCITATIONS, ["taut", "wiry", "portly"],
                            [(True, True), (True, False), (False, True)], [190.0, 310.0, 450.0, 630.0, 850.0],
                            [0.065, 0.045, 0.085], [0.0, 0.45, 0.0, 0.6], [0.002, 0.004], [0.0007, 0.0014],
                            11000, n, loops=("pi", "pid"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 3))


# fresh9: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F9_FS = {"a": 280.0, "b": 350.0, "c": 310.0, "d": 540.0, "e": 400.0, "f": 260.0, "g": 370.0, "h": 320.0, "i": 290.0}
_F9_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] - 0.7},
              "position_ripple": lambda kw: kw | {"period": 0.95 * kw["period"], "phase": kw["phase"] + 1.5},
              "thermal_drift": lambda kw: kw | {"rate": -kw["rate"]}}


def fresh9_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (11200 + k), with the gravity's phase, the drift's sign and the
    ripple's period and phase changed."""
    return _refreshed("fresh9", _F9_FS, _F9_VARIED, 11200)


# fresh6: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F6_FS = {"a": 320.0, "b": 360.0, "c": 260.0, "d": 600.0, "e": 420.0, "f": 200.0, "g": 380.0, "h": 300.0, "i": 240.0}
_F6_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] + 2.3},
              "asymmetry": lambda kw: kw | {"offset": -kw["offset"]},
              "position_ripple": lambda kw: kw | {"period": 1.15 * kw["period"], "phase": kw["phase"] + 2.0},
              "thermal_drift": lambda kw: kw | {"rate": -kw["rate"]}}


def fresh6_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (9600 + k), with the gravity's phase, the asymmetry's and drift's
    sign and the ripple's period and phase changed."""
    return _refreshed("fresh6", _F6_FS, _F6_VARIED, 9600)


# fresh5: fresh3's effect recipes at yet other sampling rates and seeds, the effects' phases, signs
# and ripple periods changed again where that leaves their size alone
_F5_FS = {"a": 280.0, "b": 400.0, "c": 220.0, "d": 700.0, "e": 500.0, "f": 350.0, "g": 260.0, "h": 240.0, "i": 450.0}
_F5_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] - 1.4},
              "asymmetry": lambda kw: kw | {"offset": -kw["offset"]},
              "position_ripple": lambda kw: kw | {"period": 0.8 * kw["period"], "phase": kw["phase"] + 1.1},
              "thermal_drift": lambda kw: kw | {"rate": -kw["rate"]}}


def fresh5_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (9100 + k), with the gravity's phase, the asymmetry's and drift's
    sign and the ripple's period and phase changed."""
    return _refreshed("fresh5", _F5_FS, _F5_VARIED, 9100)


# the outside study's recordings (the same plants, other excitations, rates and loops)
_OUT_RECIPES = {
    "p": ("nimble", "pid", "point_to_point", {"amplitudes": (4.0, -2.0, 5.0, 0.0, -5.0, 1.0), "move_time": 1.5,
                                             "dwell": 2.5, "repeats": 2}, 800.0, 0.06, 0.0, 0.003, 0.0005, True, True),
    # smooth: behind a lag a velocity step's torque jump is felt whole for a moment, at any T
    "q": ("middle", "pi", "multisine", {"amplitude": 3.0, "f0": 0.05, "f1": 2.5, "n": 10, "duration": 55.0},
          500.0, 0.08, 0.0, 0.004, 0.0005, True, True),
    "r": ("sluggish", "pi", "staircase", {"speeds": (0.02, 0.1, 0.5, 2.0, 5.0, 9.0), "dwell": 4.5,
                                         "transition": 0.6, "repeats": 1}, 200.0, 0.1, 0.0, 0.003, 0.001, True, True),
    "s": ("middle", "pid", "sine_sweep", {"amplitude": 4.0, "f0": 0.05, "f1": 1.5, "duration": 60.0, "bias": 0.8},
          350.0, 0.07, 0.4, 0.0, 0.0005, True, False),
    "t": ("nimble", "pi", "multisine", {"amplitude": 2.5, "f0": 0.04, "f1": 2.0, "n": 8, "duration": 55.0},
          700.0, 0.05, 0.0, 0.003, 0.0, False, True),
    "u": ("sluggish", "pid", "point_to_point", {"amplitudes": (3.0, -3.0, 6.0, -1.0, -6.0, 2.0), "move_time": 1.2,
                                               "dwell": 3.0, "repeats": 2}, 400.0, 0.1, 0.0, 0.0, 0.0005, True, False),
    "v": ("middle", "pid_nff", "point_to_point", {"amplitudes": (5.0, -5.0, 2.0, -3.0, 4.0, 0.0), "move_time": 2.0,
                                                 "dwell": 3.0, "repeats": 2}, 250.0, 0.08, 0.0, 0.003, 0.0005, True, True),
    "w": ("nimble", "pi", "staircase", {"speeds": (0.02, 0.08, 0.3, 1.2, 4.0), "dwell": 5.5, "transition": 0.5,
                                       "repeats": 1}, 150.0, 0.06, 0.3, 0.002, 0.0005, True, True),
}
# (recipe, effect id, parameters, expected dependence): peak effect torque below the per-sample noise
OUTSIDE_ROWS = [
    ("p", "actuator_lag", {"T": 0.0015}, "torque_rate"),
    ("q", "actuator_lag", {"T": 0.0013}, "torque_rate"),
    ("r", "quadratic_drag", {"c": 0.001}, "v|v|"),
    ("s", "quadratic_drag", {"c": 0.002}, "v|v|"),
    ("t", "torque_dependent_friction", {"mu": 0.016, "rotor_share": 0.5, "v_eps": 0.02}, "transmitted torque"),
    ("u", "torque_dependent_friction", {"mu": 0.0026, "rotor_share": 0.4, "v_eps": 0.02}, "transmitted torque"),
    ("v", "time_disturbance", {"amplitude": 0.06, "frequency": 0.08, "phase": 0.4}, "time"),
    ("w", "time_disturbance", {"amplitude": 0.045, "frequency": 0.25, "phase": -1.3}, "time"),
]


# outside2: the outside study's four effects again, on the calib5 plants and the calib4 ones, at
# other excitations, rates, loops and seeds, each at the concealed level
_OUT2_RECIPES = {
    "a": ("brisk", "pi", "multisine", {"amplitude": 2.5, "f0": 0.05, "f1": 2.0, "n": 9, "duration": 50.0},
          600.0, 0.06, 0.0, 0.003, 0.0008, True, True),
    "b": ("hefty", "pid", "point_to_point", {"amplitudes": (3.5, -2.5, 5.0, -1.0, -4.0, 1.5), "move_time": 1.4,
                                            "dwell": 2.5, "repeats": 2}, 450.0, 0.09, 0.0, 0.004, 0.0008, True, True),
    "c": ("dainty", "pi", "staircase", {"speeds": (0.03, 0.12, 0.6, 2.5, 6.0, 10.0), "dwell": 4.0,
                                       "transition": 0.5, "repeats": 1}, 300.0, 0.05, 0.0, 0.003, 0.001, True, True),
    "d": ("sharp", "pid", "sine_sweep", {"amplitude": 3.5, "f0": 0.05, "f1": 1.6, "duration": 55.0, "bias": 0.6},
          400.0, 0.06, 0.5, 0.0, 0.0008, True, False),
    "e": ("massive", "pi", "multisine", {"amplitude": 2.0, "f0": 0.04, "f1": 1.8, "n": 8, "duration": 50.0},
          550.0, 0.09, 0.0, 0.004, 0.0, False, True),
    "f": ("brisk", "pid", "point_to_point", {"amplitudes": (-3.0, 4.0, -5.0, 1.0, 5.5, -2.0), "move_time": 1.1,
                                            "dwell": 3.0, "repeats": 2}, 350.0, 0.06, 0.0, 0.0, 0.0008, True, False),
    "g": ("hefty", "pid_nff", "point_to_point", {"amplitudes": (4.5, -4.0, 1.5, -3.5, 3.0, 0.5), "move_time": 1.8,
                                                "dwell": 3.0, "repeats": 2}, 280.0, 0.09, 0.0, 0.004, 0.0008, True, True),
    "h": ("damped", "pi", "staircase", {"speeds": (0.025, 0.1, 0.4, 1.5, 4.5), "dwell": 5.0, "transition": 0.5,
                                       "repeats": 1}, 180.0, 0.05, 0.4, 0.003, 0.0008, True, True),
}
OUTSIDE2_ROWS = [
    ("a", "actuator_lag", {"T": 0.002}, "torque_rate"),
    ("b", "actuator_lag", {"T": 0.001}, "torque_rate"),
    ("c", "quadratic_drag", {"c": 0.0004}, "v|v|"),
    ("d", "quadratic_drag", {"c": 0.0025}, "v|v|"),
    ("e", "torque_dependent_friction", {"mu": 0.012, "rotor_share": 0.5, "v_eps": 0.02}, "transmitted torque"),
    ("f", "torque_dependent_friction", {"mu": 0.0034, "rotor_share": 0.4, "v_eps": 0.02}, "transmitted torque"),
    ("g", "time_disturbance", {"amplitude": 0.07, "frequency": 0.15, "phase": 1.1}, "time"),
    ("h", "time_disturbance", {"amplitude": 0.04, "frequency": 0.4, "phase": -0.6}, "time"),
]


def _outside_set(prefix, rows, recipes, seed0):
    """One recording per row ``(recipe, effect id, parameters, expected dependence)``: ``expected``
    is ``unexplained``, ``expected_dependence`` what the residual follows; seeds ``seed0 + k``."""
    return [_recipe_job(f"{prefix}{k:02d}_{eid}_{r}", r, seed0 + k, [(eid, kw)], "unexplained", recipes)
            | {"expected_dependence": dep} for k, (r, eid, kw, dep) in enumerate(rows)]


def outside2_settings():
    """A second outside set (issue #31), fixed and committed before its first run: the four effects
    outside the candidates, two recordings each, on plants, excitations, rates, loops and seeds
    (5300 + k) the outside study did not use, each at the concealed level."""
    return _outside_set("outside2_", OUTSIDE2_ROWS, _OUT2_RECIPES, 5300)


# outside3: the outside study's four effects at outside2's sizes, on calib8's plants, at other
# excitations, rates, loops and seeds
_OUT3_RECIPES = {
    "a": ("wiry", "pi", "multisine", {"amplitude": 2.2, "f0": 0.06, "f1": 1.9, "n": 10, "duration": 48.0},
          560.0, 0.06, 0.0, 0.003, 0.0009, True, True),
    "b": ("portly", "pid", "point_to_point", {"amplitudes": (3.0, -3.5, 4.5, -1.5, -3.0, 2.0), "move_time": 1.5,
                                             "dwell": 2.4, "repeats": 2}, 420.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("wiry", "pi", "staircase", {"speeds": (0.035, 0.14, 0.7, 2.8, 6.5, 9.0), "dwell": 3.8,
                                     "transition": 0.45, "repeats": 1}, 320.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("taut", "pid", "sine_sweep", {"amplitude": 3.2, "f0": 0.06, "f1": 1.5, "duration": 52.0, "bias": 0.5},
          380.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("portly", "pi", "multisine", {"amplitude": 2.1, "f0": 0.05, "f1": 1.7, "n": 9, "duration": 48.0},
          520.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("taut", "pid", "point_to_point", {"amplitudes": (-2.5, 4.5, -4.0, 1.5, 5.0, -2.5), "move_time": 1.2,
                                           "dwell": 2.8, "repeats": 2}, 330.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("portly", "pid_nff", "point_to_point", {"amplitudes": (4.0, -3.5, 2.0, -4.0, 2.5, 1.0), "move_time": 1.7,
                                                 "dwell": 2.9, "repeats": 2}, 300.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("wiry", "pi", "staircase", {"speeds": (0.03, 0.12, 0.45, 1.6, 4.0), "dwell": 4.6, "transition": 0.45,
                                     "repeats": 1}, 200.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


# outside2's rows; the torque-dependent friction of row f smaller, so that on TAUT its peak stays
# below the per-sample noise (0.0034 gives 1.35 of it)
def _resized(rows, changes):
    """``rows`` with the effect parameters of the rows named in ``changes`` (recipe -> parameters) replaced."""
    return [(r[0], r[1], r[2] | changes.get(r[0], {}), r[3]) for r in rows]


OUTSIDE3_ROWS = _resized(OUTSIDE2_ROWS, {"f": {"mu": 0.0022}})


def outside3_settings():
    """A third outside set (issue #31), fixed and committed before its first run: outside2's rows (the
    four effects outside the candidates, two recordings each, at their sizes but row f's) on calib8's plants, at
    excitations, rates, loops and seeds (11300 + k) no earlier set used."""
    return _outside_set("outside3_", OUTSIDE3_ROWS, _OUT3_RECIPES, 11300)


# calib9's excitations: the six kinds with parameters no earlier set used
CALIB9_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.045, 0.17, 0.6, 1.8, 3.9), "dwell": 3.2 if i % 2 else 2.6,
                            "transition": 0.25, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.6 * (i % 3), "f0": 0.055, "f1": 1.15, "duration": 41.0,
                             "bias": 0.4 + 0.6 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.3 + 0.8 * (i % 2), "f0": 0.065, "f1": 0.9 + 0.4 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 41.0},
    "position_sine": lambda i: {"amplitude": 2.4 + 2.8 * (i % 3), "frequency": 0.14 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -3.0, 1.0, -2.0, 3.5) if i % 2 else (-2.5, 3.0, -2.0, 2.5, -1.5, 1.0),
                                 "move_time": 1.2 + 0.6 * (i % 2), "dwell": 2.1, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.055, 0.18, 0.8, 2.1, 4.0), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib9_settings(n: int = 40):
    """A ninth effect-free set (issues #30 and #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three
    plants no earlier set used (BRAWNY, SPRY, STURDY), 200-870 Hz, torque noise 0.05-0.09 N*m, white
    in half the rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise
    0.0025-0.0045 deg/s, quantisation 0.0008-0.0012 deg; seeds 11400 + i."""
    return _effect_free_set("calib9", CALIB9_EXCITATIONS, ["brawny", "spry", "sturdy"],
                            [(True, True), (True, False), (False, True)], [200.0, 330.0, 470.0, 660.0, 870.0],
                            [0.07, 0.05, 0.09], [0.0, 0.5, 0.0, 0.65], [0.0025, 0.0045], [0.0008, 0.0012],
                            11400, n, loops=("pi", "pid"), nff=2, plant_k=2, fs_k=3, tn_rule=(2, 4))


# fresh10: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F10_FS = {"a": 295.0, "b": 365.0, "c": 285.0, "d": 505.0, "e": 415.0, "f": 245.0, "g": 385.0, "h": 335.0,
           "i": 275.0}
_F10_VARIED = _varied(0.4, 1.05, -0.6)


def fresh10_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (11500 + k), with the gravity's phase, the asymmetry's sign and
    the ripple's period and phase changed."""
    return _refreshed("fresh10", _F10_FS, _F10_VARIED, 11500)


# outside4: outside3's rows on calib9's plants, at other excitations, rates, loops and seeds
_OUT4_RECIPES = {
    "a": ("spry", "pi", "multisine", {"amplitude": 2.3, "f0": 0.055, "f1": 1.8, "n": 11, "duration": 46.0},
          540.0, 0.055, 0.0, 0.003, 0.0009, True, True),
    "b": ("brawny", "pid", "point_to_point", {"amplitudes": (3.5, -3.0, 4.0, -2.0, -2.5, 2.5), "move_time": 1.4,
                                             "dwell": 2.5, "repeats": 2}, 430.0, 0.08, 0.0, 0.004, 0.0009, True, True),
    "c": ("spry", "pi", "staircase", {"speeds": (0.04, 0.15, 0.75, 2.6, 6.0, 8.5), "dwell": 3.6,
                                     "transition": 0.4, "repeats": 1}, 340.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("sturdy", "pid", "sine_sweep", {"amplitude": 3.0, "f0": 0.055, "f1": 1.45, "duration": 50.0, "bias": 0.6},
          390.0, 0.06, 0.5, 0.0, 0.0009, True, False),
    "e": ("brawny", "pi", "multisine", {"amplitude": 2.0, "f0": 0.05, "f1": 1.6, "n": 10, "duration": 46.0},
          500.0, 0.08, 0.0, 0.004, 0.0, False, True),
    "f": ("sturdy", "pid", "point_to_point", {"amplitudes": (-3.0, 4.0, -4.5, 2.0, 4.5, -2.0), "move_time": 1.3,
                                             "dwell": 2.7, "repeats": 2}, 350.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("brawny", "pid_nff", "point_to_point", {"amplitudes": (3.5, -4.0, 2.5, -3.5, 2.0, 1.5), "move_time": 1.6,
                                                 "dwell": 2.8, "repeats": 2}, 310.0, 0.08, 0.0, 0.004, 0.0009, True, True),
    "h": ("spry", "pi", "staircase", {"speeds": (0.035, 0.13, 0.5, 1.7, 4.2), "dwell": 4.4, "transition": 0.4,
                                     "repeats": 1}, 210.0, 0.05, 0.5, 0.003, 0.0009, True, True),
}


def outside4_settings():
    """A fourth outside set (issue #31), fixed and committed before its first run: outside3's rows
    (the four effects outside the candidates, two recordings each) on calib9's plants, at
    excitations, rates, loops and seeds (11600 + k) no earlier set used."""
    return _outside_set("outside4_", OUTSIDE3_ROWS, _OUT4_RECIPES, 11600)


# calib10's excitations: the six kinds with parameters no earlier set used
CALIB10_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.035, 0.13, 0.5, 1.9, 3.3), "dwell": 3.0 if i % 2 else 2.7,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.55 * (i % 3), "f0": 0.05, "f1": 1.25, "duration": 43.0,
                             "bias": 0.45 + 0.55 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.5 + 0.6 * (i % 2), "f0": 0.06, "f1": 0.95 + 0.35 * (i % 3),
                            "n": 10 + 3 * (i % 2), "duration": 43.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.5 * (i % 3), "frequency": 0.12 + 0.06 * (i % 2),
                                "duration": 35.0},
    "point_to_point": lambda i: {"amplitudes": (3.0, -2.0, 1.5, -3.5, 2.0) if i % 2 else (-2.0, 2.5, -3.0, 1.5, -1.0, 2.0),
                                 "move_time": 1.25 + 0.55 * (i % 2), "dwell": 2.3, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.06, 0.21, 0.7, 2.2, 4.1), "dwell": 2.6, "transition": 0.0, "repeats": 2},
}


def calib10_settings(n: int = 40):
    """A tenth effect-free set (issues #30 and #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three
    plants no earlier set used (LITHE, HULKING, STEADY), 210-880 Hz, torque noise 0.045-0.085 N*m,
    white in half the rows and AR(1) of coefficient 0.45 or 0.6 in the other half, velocity noise
    0.002-0.004 deg/s, quantisation 0.0007-0.0013 deg; seeds 11700 + i."""
    return _effect_free_set("calib10", CALIB10_EXCITATIONS, ["lithe", "hulking", "steady"],
                            [(True, True), (True, False), (False, True)], [210.0, 340.0, 490.0, 640.0, 880.0],
                            [0.065, 0.045, 0.085], [0.0, 0.45, 0.0, 0.6], [0.002, 0.004], [0.0007, 0.0013],
                            11700, n, loops=("pi", "pid"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 5))


# fresh11: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F11_FS = {"a": 265.0, "b": 385.0, "c": 305.0, "d": 560.0, "e": 425.0, "f": 275.0, "g": 355.0, "h": 305.0,
           "i": 315.0}
_F11_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] - 1.1},
               "position_ripple": lambda kw: kw | {"period": 0.9 * kw["period"], "phase": kw["phase"] + 0.9},
               "thermal_drift": lambda kw: kw | {"rate": -kw["rate"]}}


def fresh11_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (11800 + k), with the gravity's phase, the drift's sign and the
    ripple's period and phase changed."""
    return _refreshed("fresh11", _F11_FS, _F11_VARIED, 11800)


# outside5: outside3's rows on calib10's plants, at other excitations, rates, loops and seeds
_OUT5_RECIPES = {
    "a": ("lithe", "pi", "multisine", {"amplitude": 2.4, "f0": 0.05, "f1": 1.85, "n": 12, "duration": 47.0},
          580.0, 0.06, 0.0, 0.003, 0.0009, True, True),
    "b": ("hulking", "pid", "point_to_point", {"amplitudes": (2.5, -3.5, 4.0, -2.5, -2.0, 3.0), "move_time": 1.45,
                                              "dwell": 2.6, "repeats": 2}, 410.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("lithe", "pi", "staircase", {"speeds": (0.04, 0.16, 0.8, 2.7, 6.2, 8.8), "dwell": 3.7,
                                      "transition": 0.4, "repeats": 1}, 330.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("steady", "pid", "sine_sweep", {"amplitude": 3.1, "f0": 0.05, "f1": 1.4, "duration": 51.0, "bias": 0.55},
          400.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("hulking", "pi", "multisine", {"amplitude": 2.2, "f0": 0.055, "f1": 1.65, "n": 11, "duration": 47.0},
          510.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("steady", "pid", "point_to_point", {"amplitudes": (-2.0, 4.5, -3.5, 2.5, 4.0, -3.0), "move_time": 1.35,
                                             "dwell": 2.6, "repeats": 2}, 360.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("hulking", "pid_nff", "point_to_point", {"amplitudes": (3.0, -4.5, 2.0, -3.0, 2.5, 1.5), "move_time": 1.65,
                                                  "dwell": 2.7, "repeats": 2}, 320.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("lithe", "pi", "staircase", {"speeds": (0.04, 0.14, 0.55, 1.8, 4.4), "dwell": 4.2, "transition": 0.4,
                                      "repeats": 1}, 220.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


# outside3's rows; the lag of row b and the torque-dependent friction of row e smaller, so that on
# HULKING their peaks stay below the per-sample noise (outside3's sizes give 1.09 and 1.1 of it)
OUTSIDE5_ROWS = _resized(OUTSIDE3_ROWS, {"b": {"T": 0.0008}, "e": {"mu": 0.0095}})


def outside5_settings():
    """A fifth outside set (issue #31), fixed and committed before its first run: outside3's rows
    (the four effects outside the candidates, two recordings each; rows b and e smaller) on calib10's plants, at
    excitations, rates, loops and seeds (11900 + k) no earlier set used."""
    return _outside_set("outside5_", OUTSIDE5_ROWS, _OUT5_RECIPES, 11900)


def outside_settings():
    """Effects outside the eight candidates (issue #31) at the concealed level, two recordings each
    on different plants, loops and excitations; ``expected`` is ``unexplained`` and
    ``expected_dependence`` what the residual follows."""
    return _outside_set("outside", OUTSIDE_ROWS, _OUT_RECIPES, 5200)


def excitation_of(name: str, fs: float, seed: int, short: bool = False, kw=None):
    if kw:  # the held-out study's explicit parameters
        cls = {"staircase": T.Staircase, "staircase_sharp": T.Staircase, "sine_sweep": T.SineSweep,
               "multisine": T.Multisine, "position_sine": T.PositionSineExcitation, "point_to_point": T.PointToPoint,
               "sharp_steps": T.Staircase}[name]
        kw = {k: tuple(v) if isinstance(v, list) else v for k, v in kw.items()}
        kw = dict(kw, **({"transition": 0.0} if name == "staircase_sharp" else {}))
        return cls(**kw, **({"seed": seed} if cls is T.Staircase else {}))
    short = short or fs >= 500  # bound the sample count (and the generator's time)
    if name == "staircase":
        return T.Staircase(dwell=4.5 if short else 9.0, seed=seed)
    if name == "staircase_sharp":
        return T.Staircase(dwell=4.5 if short else 9.0, transition=0.0, seed=seed)
    if name == "staircase_short":
        return T.Staircase(dwell=4.5, seed=seed)
    if name == "sine_sweep":
        return T.SineSweep(duration=60.0 if short else 120.0)
    if name == "multisine":
        return T.Multisine(duration=60.0 if short else 120.0)
    raise ValueError(name)


ISSUE_EFFECTS = {
    "none": [],
    "gravity": [T.GravityEffect(0.15, -0.3)],
    "asymmetry": [T.AsymmetryEffect(0.06)],  # 5 % of Fc
    "position_ripple": [T.PositionRippleEffect(0.07, 7.5, 1.0)],
    "thermal_drift": [T.ThermalDriftEffect(-0.04 / 288.0)],
    "position_ripple+asymmetry": [T.PositionRippleEffect(0.07, 7.5, 1.0), T.AsymmetryEffect(0.06)],
}

# the held-out effects (peak near the per-sample noise of their recordings)
HELD_EFFECTS = {
    "asymmetry": [T.AsymmetryEffect(0.04)],
    "position_ripple": [T.PositionRippleEffect(0.06, 4.0, 0.3)],
    "stribeck_shape": [T.StribeckShapeEffect(1.2)],
    "thermal_drift": [T.ThermalDriftEffect(-0.06 / 192.0)],
    "gravity": [T.GravityEffect(0.05, 0.8)],
}

# the fresh set's effects: the issue's sizes (asymmetry, gravity, ripple) and the slow tests' (the
# others; drift -8 % over the 50-s recording)
FRESH_EFFECTS = {
    "asymmetry": [T.AsymmetryEffect(0.06)],
    "gravity": [T.GravityEffect(0.15, 0.3)],
    "position_ripple": [T.PositionRippleEffect(0.08, 6.0, 2.0)],
    "thermal_drift": [T.ThermalDriftEffect(-0.08 / 50.0)],
    "stribeck_shape": [T.StribeckShapeEffect(1.0)],
    "load_dependent": [T.LoadDependentEffect(0.15, 0.02)],
    "compliance": [T.ComplianceEffect(3.0, 0.05, 0.04)],
    "backlash": [T.BacklashEffect(0.05, 0.3)],
    "position_ripple+asymmetry": [T.PositionRippleEffect(0.08, 6.0, 2.0), T.AsymmetryEffect(0.06)],
}

# concealed level (strength 1): the peak effect torque below the 0.08 N*m per-sample noise (the
# measured peak is recorded with every run)
CONCEALED = {
    "gravity": lambda s: [T.GravityEffect(0.06 * s, -0.3)],
    "asymmetry": lambda s: [T.AsymmetryEffect(0.04 * s, 0.0)],
    "position_ripple": lambda s: [T.PositionRippleEffect(0.05 * s, 7.5, 1.0)],
    "thermal_drift": lambda s: [T.ThermalDriftEffect(-0.0125 * s / 144.0)],
    "stribeck_shape": lambda s: [T.StribeckShapeEffect(2.0 - 0.4 * s)],
    "backlash": lambda s: [T.BacklashEffect(0.02, 0.025 * s)],
    "compliance": lambda s: [T.ComplianceEffect(3.0, 0.05, 0.01 * s)],
    "load_dependent": lambda s: [T.LoadDependentEffect(0.03 * s, 0.02)],
    "gravity+asymmetry": lambda s: [T.GravityEffect(0.06 * s, -0.3), T.AsymmetryEffect(0.04 * s, 0.0)],
    "position_ripple+thermal_drift": lambda s: [T.PositionRippleEffect(0.05 * s, 7.5, 1.0),
                                                T.ThermalDriftEffect(-0.0125 * s / 144.0)],
}


# calib11's excitations: the six kinds with parameters no earlier set used
CALIB11_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.045, 0.15, 0.6, 1.7, 3.9), "dwell": 3.2 if i % 2 else 2.8,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.7 + 0.6 * (i % 3), "f0": 0.045, "f1": 1.4, "duration": 41.0,
                             "bias": 0.5 + 0.5 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.3 + 0.7 * (i % 2), "f0": 0.055, "f1": 1.05 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 41.0},
    "position_sine": lambda i: {"amplitude": 2.9 + 2.2 * (i % 3), "frequency": 0.11 + 0.07 * (i % 2),
                                "duration": 37.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -3.0, 1.8, -2.2, 3.1) if i % 2 else (-2.6, 1.9, -1.4, 3.2, -2.1, 1.7),
                                 "move_time": 1.35 + 0.5 * (i % 2), "dwell": 2.1, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.07, 0.24, 0.8, 2.0, 3.8), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib11_settings(n: int = 40):
    """An eleventh effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (NIPPY, BURLY, EVEN), 230-820 Hz, torque noise 0.05-0.09 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise 0.0025-0.0045 deg/s,
    quantisation 0.0008-0.0014 deg; seeds 12100 + i."""
    return _effect_free_set("calib11", CALIB11_EXCITATIONS, ["nippy", "burly", "even"],
                            [(True, True), (True, False), (False, True)], [230.0, 360.0, 470.0, 610.0, 820.0],
                            [0.07, 0.05, 0.09], [0.0, 0.5, 0.0, 0.65], [0.0025, 0.0045], [0.0008, 0.0014],
                            12100, n, loops=("pi", "pid"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 5))


# fresh12: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F12_FS = {"a": 325.0, "b": 455.0, "c": 275.0, "d": 535.0, "e": 395.0, "f": 345.0, "g": 415.0, "h": 285.0,
           "i": 365.0}
_F12_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] + 1.7},
               "position_ripple": lambda kw: kw | {"period": 1.15 * kw["period"], "phase": kw["phase"] - 1.3},
               "thermal_drift": lambda kw: kw}


def fresh12_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (12300 + k), with the gravity's phase and the ripple's period and
    phase changed."""
    return _refreshed("fresh12", _F12_FS, _F12_VARIED, 12300)


# calib12's excitations: the six kinds with parameters no earlier set used
CALIB12_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.05, 0.16, 0.55, 1.6, 3.6), "dwell": 3.0 if i % 2 else 2.6,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.6 + 0.7 * (i % 3), "f0": 0.05, "f1": 1.3, "duration": 39.0,
                             "bias": 0.6 + 0.4 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.8 * (i % 2), "f0": 0.06, "f1": 1.0 + 0.35 * (i % 3),
                            "n": 10 + 3 * (i % 2), "duration": 39.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.4 * (i % 3), "frequency": 0.12 + 0.06 * (i % 2),
                                "duration": 35.0},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.8, 1.6, -2.4, 3.3) if i % 2 else (-2.9, 2.1, -1.2, 2.8, -1.9, 1.5),
                                 "move_time": 1.25 + 0.55 * (i % 2), "dwell": 2.3, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.065, 0.22, 0.75, 1.9, 3.6), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib12_settings(n: int = 40):
    """A twelfth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (CRISP, STOCKY, SUPPLE), 250-900 Hz, torque noise 0.05-0.09 N*m, white in half
    the rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise 0.0025-0.0045
    deg/s, quantisation 0.0007-0.0013 deg; seeds 12500 + i."""
    return _effect_free_set("calib12", CALIB12_EXCITATIONS, ["crisp", "stocky", "supple"],
                            [(True, True), (True, False), (False, True)], [250.0, 390.0, 520.0, 680.0, 900.0],
                            [0.06, 0.08, 0.05], [0.0, 0.5, 0.0, 0.65], [0.0025, 0.0045], [0.0007, 0.0013],
                            12500, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=3, tn_rule=(2, 5))


# fresh13: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F13_FS = {"a": 315.0, "b": 435.0, "c": 265.0, "d": 555.0, "e": 405.0, "f": 335.0, "g": 445.0, "h": 305.0,
           "i": 375.0}
_F13_VARIED = _varied(2.3, 0.9, 0.8)


def fresh13_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (12700 + k), with the gravity's phase, the asymmetry's sign and
    the ripple's period and phase changed."""
    return _refreshed("fresh13", _F13_FS, _F13_VARIED, 12700)


# calib13's excitations: the six kinds with parameters no earlier set used
CALIB13_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.04, 0.14, 0.5, 1.5, 3.4), "dwell": 2.9 if i % 2 else 2.5,
                            "transition": 0.28, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.042, "f1": 1.25, "duration": 38.0,
                             "bias": 0.45 + 0.5 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.6 * (i % 2), "f0": 0.05, "f1": 0.95 + 0.4 * (i % 3),
                            "n": 12 + 2 * (i % 2), "duration": 38.0},
    "position_sine": lambda i: {"amplitude": 2.7 + 2.3 * (i % 3), "frequency": 0.13 + 0.05 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.7, -2.2, 1.4, -3.0, 2.0) if i % 2 else (-2.3, 2.6, -1.7, 2.2, -2.8, 1.3),
                                 "move_time": 1.3 + 0.45 * (i % 2), "dwell": 2.2, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.06, 0.2, 0.7, 1.8, 3.5), "dwell": 2.3, "transition": 0.0, "repeats": 2},
}


def calib13_settings(n: int = 40):
    """A thirteenth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (LANKY, CHUNKY, POISED), 240-880 Hz, torque noise 0.05-0.09 N*m, white in half
    the rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise 0.0025-0.0045
    deg/s, quantisation 0.0009-0.0015 deg; seeds 12900 + i."""
    return _effect_free_set("calib13", CALIB13_EXCITATIONS, ["lanky", "chunky", "poised"],
                            [(True, True), (True, False), (False, True)], [240.0, 370.0, 500.0, 640.0, 880.0],
                            [0.09, 0.06, 0.07], [0.0, 0.5, 0.0, 0.65], [0.0025, 0.0045], [0.0009, 0.0015],
                            12900, n, loops=("pi", "pid"), nff=0, plant_k=1, fs_k=2, tn_rule=(1, 4))


# fresh14: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F14_FS = {"a": 305.0, "b": 425.0, "c": 255.0, "d": 545.0, "e": 385.0, "f": 325.0, "g": 435.0, "h": 295.0,
           "i": 355.0}
_F14_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] - 1.1},
               "position_ripple": lambda kw: kw | {"period": 1.1 * kw["period"], "phase": kw["phase"] + 1.9}}


def fresh14_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (13100 + k), with the gravity's phase and the ripple's period and
    phase changed."""
    return _refreshed("fresh14", _F14_FS, _F14_VARIED, 13100)


# calib14's excitations: the six kinds with parameters no earlier set used
CALIB14_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.045, 0.15, 0.52, 1.45, 3.3), "dwell": 2.7 if i % 2 else 2.4,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.0 + 0.45 * (i % 3), "f0": 0.045, "f1": 1.2, "duration": 37.0,
                             "bias": 0.5 + 0.45 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.3 + 0.5 * (i % 2), "f0": 0.055, "f1": 0.9 + 0.45 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 37.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.2 * (i % 3), "frequency": 0.14 + 0.045 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -2.0, 1.5, -2.7, 2.2) if i % 2 else (-2.1, 2.7, -1.5, 2.4, -2.6, 1.4),
                                 "move_time": 1.35 + 0.4 * (i % 2), "dwell": 2.1, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.055, 0.21, 0.68, 1.75, 3.4), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib14_settings(n: int = 40):
    """A fourteenth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (WIRY14, BULKY14, TRIM), 260-860 Hz, torque noise 0.05-0.09 N*m, white in half
    the rows and AR(1) of coefficient 0.45 or 0.6 in the other half, velocity noise 0.003-0.004
    deg/s, quantisation 0.0008-0.0014 deg; seeds 13300 + i."""
    return _effect_free_set("calib14", CALIB14_EXCITATIONS, ["wiry14", "bulky14", "trim"],
                            [(True, True), (True, False), (False, True)], [260.0, 410.0, 530.0, 700.0, 860.0],
                            [0.08, 0.05, 0.09], [0.0, 0.45, 0.0, 0.6], [0.003, 0.004], [0.0008, 0.0014],
                            13300, n, loops=("pi", "pid"), nff=2, plant_k=2, fs_k=1, tn_rule=(2, 3))


# fresh15: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F15_FS = {"a": 325.0, "b": 445.0, "c": 275.0, "d": 565.0, "e": 395.0, "f": 345.0, "g": 455.0, "h": 315.0,
           "i": 365.0}
_F15_VARIED = _varied(0.7, 0.95, -1.3)


def fresh15_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (13500 + k), with the gravity's phase, the asymmetry's sign and
    the ripple's period and phase changed."""
    return _refreshed("fresh15", _F15_FS, _F15_VARIED, 13500)


# calib15's excitations: the six kinds with parameters no earlier set used
CALIB15_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.04, 0.13, 0.48, 1.35, 3.1), "dwell": 2.6 if i % 2 else 2.9,
                            "transition": 0.32, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.5 * (i % 3), "f0": 0.048, "f1": 1.3, "duration": 36.0,
                             "bias": 0.55 + 0.4 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.55 * (i % 2), "f0": 0.052, "f1": 1.0 + 0.35 * (i % 3),
                            "n": 12 + 2 * (i % 2), "duration": 36.0},
    "position_sine": lambda i: {"amplitude": 2.4 + 2.4 * (i % 3), "frequency": 0.15 + 0.04 * (i % 2),
                                "duration": 32.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.5, 1.6, -2.9, 2.1) if i % 2 else (-2.4, 2.2, -1.3, 2.8, -2.0, 1.5),
                                 "move_time": 1.25 + 0.5 * (i % 2), "dwell": 2.3, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.19, 0.62, 1.9, 3.6), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib15_settings(n: int = 40):
    """A fifteenth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (SPARE, HUSKY, TIDY), 280-840 Hz, torque noise 0.05-0.085 N*m, white in half
    the rows and AR(1) of coefficient 0.4 or 0.62 in the other half, velocity noise 0.0028-0.0042
    deg/s, quantisation 0.0007-0.0013 deg; seeds 13700 + i."""
    return _effect_free_set("calib15", CALIB15_EXCITATIONS, ["spare", "husky", "tidy"],
                            [(True, False), (False, True), (True, True)], [280.0, 390.0, 560.0, 680.0, 840.0],
                            [0.065, 0.085, 0.05], [0.0, 0.4, 0.0, 0.62], [0.0028, 0.0042], [0.0007, 0.0013],
                            13700, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(1, 5))


# fresh16: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F16_FS = {"a": 335.0, "b": 465.0, "c": 285.0, "d": 585.0, "e": 405.0, "f": 355.0, "g": 475.0, "h": 305.0,
           "i": 375.0}
_F16_VARIED = {"gravity": lambda kw: kw | {"phase": kw["phase"] - 0.5},
               "position_ripple": lambda kw: kw | {"period": 1.05 * kw["period"], "phase": kw["phase"] + 0.8}}


def fresh16_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (13900 + k), with the gravity's phase and the ripple's period and
    phase changed."""
    return _refreshed("fresh16", _F16_FS, _F16_VARIED, 13900)


# outside6: outside5's rows on calib15's plants (SPARE for LITHE, HUSKY for HULKING, TIDY for STEADY),
# at excitation parameters, rates and seeds no earlier set used
_OUT6_RECIPES = {
    "a": ("spare", "pi", "multisine", {"amplitude": 2.3, "f0": 0.052, "f1": 1.75, "n": 12, "duration": 45.0},
          560.0, 0.06, 0.0, 0.003, 0.0009, True, True),
    "b": ("husky", "pid", "point_to_point", {"amplitudes": (2.7, -3.2, 3.8, -2.4, -2.2, 3.1), "move_time": 1.4,
                                            "dwell": 2.5, "repeats": 2}, 430.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("spare", "pi", "staircase", {"speeds": (0.045, 0.17, 0.75, 2.6, 6.0, 8.5), "dwell": 3.6,
                                      "transition": 0.4, "repeats": 1}, 345.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("tidy", "pid", "sine_sweep", {"amplitude": 3.0, "f0": 0.052, "f1": 1.35, "duration": 49.0, "bias": 0.6},
          420.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("husky", "pi", "multisine", {"amplitude": 2.1, "f0": 0.058, "f1": 1.6, "n": 11, "duration": 45.0},
          530.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("tidy", "pid", "point_to_point", {"amplitudes": (-2.2, 4.3, -3.3, 2.6, 3.8, -2.9), "move_time": 1.3,
                                           "dwell": 2.5, "repeats": 2}, 375.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("husky", "pid_nff", "point_to_point", {"amplitudes": (2.9, -4.3, 2.2, -3.1, 2.4, 1.6), "move_time": 1.6,
                                                "dwell": 2.6, "repeats": 2}, 335.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("spare", "pi", "staircase", {"speeds": (0.045, 0.15, 0.52, 1.75, 4.2), "dwell": 4.0, "transition": 0.4,
                                      "repeats": 1}, 235.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside6_settings():
    """A sixth outside set (issue #31), fixed and committed before its first run: outside5's rows
    (the four effects outside the candidates, two recordings each) on calib15's plants, at
    excitation parameters, rates and seeds (14100 + k) no earlier set used."""
    return _outside_set("outside6_", OUTSIDE5_ROWS, _OUT6_RECIPES, 14100)


# fresh17: fresh3's effect recipes at sampling rates and seeds no earlier set used, the effects'
# phases, signs and ripple periods changed again where that leaves their size alone
_F17_FS = {"a": 315.0, "b": 485.0, "c": 295.0, "d": 545.0, "e": 415.0, "f": 365.0, "g": 435.0, "h": 325.0,
           "i": 385.0}
_F17_VARIED = _varied(1.1, 0.9, 2.1)


def fresh17_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows at
    other sampling rates and seeds (14300 + k), with the gravity's phase, the asymmetry's sign and
    the ripple's period and phase changed."""
    return _refreshed("fresh17", _F17_FS, _F17_VARIED, 14300)


# outside7: outside5's rows on calib14's plants (WIRY14 for LITHE, BULKY14 for HULKING, TRIM for STEADY),
# at excitation parameters, rates and seeds no earlier set used
_OUT7_RECIPES = {
    "a": ("wiry14", "pi", "multisine", {"amplitude": 2.4, "f0": 0.055, "f1": 1.65, "n": 13, "duration": 44.0},
          545.0, 0.06, 0.0, 0.003, 0.0009, True, True),
    "b": ("bulky14", "pid", "point_to_point", {"amplitudes": (3.1, -2.6, 3.5, -3.3, -1.9, 2.8), "move_time": 1.45,
                                              "dwell": 2.4, "repeats": 2}, 445.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("wiry14", "pi", "staircase", {"speeds": (0.04, 0.16, 0.8, 2.4, 5.5, 8.0), "dwell": 3.7,
                                       "transition": 0.4, "repeats": 1}, 355.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("trim", "pid", "sine_sweep", {"amplitude": 3.1, "f0": 0.05, "f1": 1.4, "duration": 50.0, "bias": 0.55},
          410.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("bulky14", "pi", "multisine", {"amplitude": 2.2, "f0": 0.056, "f1": 1.55, "n": 10, "duration": 46.0},
          515.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("trim", "pid", "point_to_point", {"amplitudes": (-2.6, 3.9, -3.6, 2.2, 4.1, -2.7), "move_time": 1.35,
                                           "dwell": 2.6, "repeats": 2}, 365.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("bulky14", "pid_nff", "point_to_point", {"amplitudes": (3.3, -4.1, 2.4, -2.9, 2.6, 1.4), "move_time": 1.55,
                                                  "dwell": 2.7, "repeats": 2}, 325.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("wiry14", "pi", "staircase", {"speeds": (0.05, 0.14, 0.55, 1.8, 4.4), "dwell": 4.2, "transition": 0.4,
                                       "repeats": 1}, 245.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside7_settings():
    """A seventh outside set (issue #31), fixed and committed before its first run: outside5's rows
    (the four effects outside the candidates, two recordings each) on calib14's plants, at
    excitation parameters, rates and seeds (14500 + k) no earlier set used."""
    return _outside_set("outside7_", OUTSIDE5_ROWS, _OUT7_RECIPES, 14500)


# calib16's plants
LEAN = T.Plant(J=0.075, Fc=0.5, Fs=0.8, vs=0.066, sigma2=0.92, sigma0=185.0, sigma1=0.88)
BEEFY = T.Plant(J=0.43, Fc=1.75, Fs=2.3, vs=0.076, sigma2=1.95, sigma0=245.0, sigma1=2.0)
NEAT = T.Plant(J=0.16, Fc=0.72, Fs=1.02, vs=0.062, sigma2=1.18, sigma0=205.0, sigma1=1.2)


def _add_plants(plants: dict, pids: dict):
    """New plants and their position PIDs, refused if a name is taken (a repeated key in a dict
    literal silently replaces the earlier plant, and an older set would no longer regenerate)."""
    taken = (set(plants) & set(PLANTS)) | (set(pids) & set(PIDS))
    if taken or set(plants) != set(pids):
        raise ValueError(f"plant names taken or unpaired: {sorted(taken or set(plants) ^ set(pids))}")
    PLANTS.update(plants)
    PIDS.update(pids)


_add_plants({"lean": (LEAN, T.VelocityPIController(kp=3.2, ki=19.0)),
             "beefy": (BEEFY, T.VelocityPIController(kp=30.0, ki=175.0)),
             "neat": (NEAT, T.VelocityPIController(kp=10.5, ki=62.0))},
            {"lean": PidTuning(3.5, 0.002),
             "beefy": PidTuning(2.5, 0.005),
             "neat": PidTuning(3.0, 0.003)})

# calib16's excitations: the six kinds with parameters no earlier set used
CALIB16_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.035, 0.12, 0.52, 1.45, 3.3), "dwell": 2.7 if i % 2 else 3.0,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.7 + 0.55 * (i % 3), "f0": 0.046, "f1": 1.25, "duration": 37.0,
                             "bias": 0.6 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.5 * (i % 2), "f0": 0.054, "f1": 1.05 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 37.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.2 * (i % 3), "frequency": 0.14 + 0.05 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.1, -2.7, 1.7, -2.6, 2.4) if i % 2 else (-2.2, 2.5, -1.4, 2.6, -2.3, 1.3),
                                 "move_time": 1.3 + 0.45 * (i % 2), "dwell": 2.4, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.055, 0.2, 0.66, 1.8, 3.4), "dwell": 2.45, "transition": 0.0, "repeats": 2},
}


def calib16_settings(n: int = 40):
    """A sixteenth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (LEAN, BEEFY, NEAT), 290-820 Hz, torque noise 0.055-0.08 N*m, white in half
    the rows and AR(1) of coefficient 0.42 or 0.58 in the other half, velocity noise 0.003-0.0045
    deg/s, quantisation 0.00075-0.0012 deg; seeds 14700 + i."""
    return _effect_free_set("calib16", CALIB16_EXCITATIONS, ["lean", "beefy", "neat"],
                            [(False, True), (True, True), (True, False)], [290.0, 430.0, 575.0, 705.0, 820.0],
                            [0.08, 0.055, 0.07], [0.0, 0.42, 0.0, 0.58], [0.003, 0.0045], [0.00075, 0.0012],
                            14700, n, loops=("pi", "pid"), nff=2, plant_k=2, fs_k=1, tn_rule=(2, 3))


# calib17 and fresh18: the rates, noise colours and lengths no earlier set reached (100-160 Hz and
# 1.2-2 kHz, AR(1) coefficients 0.8 and 0.9, up to ~100,000 samples)
CALIB17_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.045, 0.15, 0.6, 1.7, 3.9), "dwell": 3.3 if i % 2 else 3.6,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.45 * (i % 3), "f0": 0.052, "f1": 1.35, "duration": 42.0,
                             "bias": 0.5 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.4 + 0.4 * (i % 2), "f0": 0.058, "f1": 1.15 + 0.25 * (i % 3),
                            "n": 10 + 3 * (i % 2), "duration": 42.0},
    "position_sine": lambda i: {"amplitude": 3.1 + 1.8 * (i % 3), "frequency": 0.13 + 0.06 * (i % 2),
                                "duration": 38.0},
    "point_to_point": lambda i: {"amplitudes": (2.6, -2.2, 1.5, -2.9, 2.0) if i % 2 else (-2.5, 2.8, -1.6, 2.3, -2.0, 1.1),
                                 "move_time": 1.4 + 0.4 * (i % 2), "dwell": 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.06, 0.22, 0.7, 1.9, 3.6), "dwell": 2.6, "transition": 0.0, "repeats": 2},
}


def calib17_settings(n: int = 30):
    """A seventeenth effect-free set (issue #30), fixed and committed before its first run, on the
    axes no earlier set reached: 100-160 Hz and 1.2-2 kHz, torque noise white or AR(1) of
    coefficient 0.8 or 0.9, up to ~100,000 samples; the six excitation kinds with other parameters
    x both loops x the three sensor sets (encoder only, velocity only, both), on calib14's plants (WIRY14, BULKY14, TRIM), torque noise
    0.05-0.08 N*m, velocity noise 0.002-0.005 deg/s, quantisation 0.0005-0.0015 deg; seeds 14900 + i."""
    return _effect_free_set("calib17", CALIB17_EXCITATIONS, ["wiry14", "bulky14", "trim"],
                            [(True, False), (False, True), (True, True)], [100.0, 1200.0, 160.0, 2000.0, 1600.0],
                            [0.05, 0.08, 0.065], [0.0, 0.8, 0.0, 0.9], [0.002, 0.005], [0.0005, 0.0015],
                            14900, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(1, 4))


_F18_FS = {"a": 1500.0, "b": 120.0, "c": 1800.0, "d": 110.0, "e": 1300.0, "f": 2000.0, "g": 140.0, "h": 1600.0,
           "i": 100.0}
_F18_VARIED = _varied(-0.9, 1.15, -1.7)


def fresh18_settings():
    """A fresh set (issue #30), fixed and committed before its first run: every second of fresh3's
    24 effect rows (12: each in-library effect once or twice) at rates no earlier set reached (100-140 Hz
    and 1.3-2 kHz, by recipe), seeds 15000 + k, with the gravity's phase, the asymmetry's sign and
    the ripple's period and phase changed."""
    return _refreshed("fresh18", _F18_FS, _F18_VARIED, 15000)[::2]


# calib18 and fresh19: strongly coloured torque noise (AR(1) 0.6-0.92) at 100-400 Hz, where the
# recorded torque's own noise profile cannot tell the noise's colour from the motion's torque
CALIB18_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.03, 0.11, 0.45, 1.3, 3.6), "dwell": 3.1 if i % 2 else 3.4,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.6 + 0.6 * (i % 3), "f0": 0.048, "f1": 1.45, "duration": 40.0,
                             "bias": 0.45 + 0.4 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.6 * (i % 2), "f0": 0.05, "f1": 1.1 + 0.35 * (i % 3),
                            "n": 9 + 4 * (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.8 + 2.0 * (i % 3), "frequency": 0.15 + 0.04 * (i % 2),
                                "duration": 36.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.5, 1.9, -2.8, 2.2) if i % 2 else (-2.4, 2.6, -1.8, 2.1, -2.6, 1.2),
                                 "move_time": 1.35 + 0.5 * (i % 2), "dwell": 2.3, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.18, 0.62, 1.7, 3.2), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib18_settings(n: int = 30):
    """An eighteenth effect-free set (issue #30), fixed and committed before its first run: strongly
    coloured torque noise (AR(1) of coefficient 0.6, 0.85 or 0.92 in three rows of four, white in
    the fourth) at 100-400 Hz; the six excitation kinds with other parameters x both loops x the
    three sensor sets (encoder only, velocity only, both), on calib2's plants (LIGHT, HEAVY, FLAT),
    torque noise 0.045-0.09 N*m, velocity noise 0.0025-0.0045 deg/s, quantisation 0.0006-0.0012
    deg; seeds 15100 + i."""
    return _effect_free_set("calib18", CALIB18_EXCITATIONS, ["light", "heavy", "flat"],
                            [(True, False), (False, True), (True, True)], [130.0, 250.0, 100.0, 400.0, 180.0],
                            [0.09, 0.045, 0.065], [0.85, 0.0, 0.92, 0.6], [0.0025, 0.0045], [0.0006, 0.0012],
                            15100, n, loops=("pi", "pid"), nff=0, plant_k=2, fs_k=3, tn_rule=(2, 5))


_F19_FS = {"a": 180.0, "b": 260.0, "c": 140.0, "d": 380.0, "e": 300.0, "f": 150.0, "g": 200.0, "h": 120.0,
           "i": 220.0}
_F19_AR = {"a": 0.85, "b": 0.7, "c": 0.9, "d": 0.6, "e": 0.8, "f": 0.88, "g": 0.75, "h": 0.92, "i": 0.65}
_F19_VARIED = _varied(0.6, 0.85, 1.3)


def fresh19_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's 24 effect rows
    with strongly coloured torque noise (AR(1) 0.6-0.92, by recipe) at 120-380 Hz, seeds
    15200 + k, with the gravity's phase, the asymmetry's sign and the ripple's period and phase
    changed."""
    recipes = {k: r[:4] + (_F19_FS[k], r[5], _F19_AR[k]) + r[7:] for k, r in _F3_RECIPES.items()}
    return [_recipe_job(f"fresh19_effect{k:02d}_{eid}_{r}", r, 15200 + k,
                        [(eid, _F19_VARIED.get(eid, dict)(dict(kw)))], eid, recipes)
            for k, (r, eid, kw) in enumerate(FRESH3_EFFECTS)]


# calib19: after the blended acceleration's noise and memory were corrected (the fix for calib17's
# false names at 1.2-1.6 kHz): rates across the range, most rows blended, other excitation parameters
CALIB19_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.035, 0.13, 0.5, 1.5, 4.2), "dwell": 3.0 if i % 2 else 3.5,
                            "transition": 0.25, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.7 + 0.5 * (i % 3), "f0": 0.045, "f1": 1.55, "duration": 40.0,
                             "bias": 0.4 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.5 * (i % 2), "f0": 0.055, "f1": 1.05 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.2 * (i % 3), "frequency": 0.14 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.1, -2.7, 1.8, -2.3, 2.6) if i % 2 else (-2.2, 2.9, -1.4, 2.4, -2.7, 1.0),
                                 "move_time": 1.3 + 0.45 * (i % 2), "dwell": 2.4, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.04, 0.2, 0.65, 2.1, 4.0), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib19_settings(n: int = 30):
    """A nineteenth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets (encoder only,
    velocity only, both), on fresh3's plants (NIMBLE, SLUGGISH, MIDDLE), 150-1400 Hz, torque noise
    0.05-0.09 N*m, white in half the rows and AR(1) of coefficient 0.5 or 0.75 in the other half,
    velocity noise 0.0025-0.0045 deg/s, quantisation 0.0006-0.0014 deg; seeds 15300 + i."""
    return _effect_free_set("calib19", CALIB19_EXCITATIONS, ["nimble", "sluggish", "middle"],
                            [(True, False), (False, True), (True, True)], [150.0, 800.0, 250.0, 1400.0, 500.0],
                            [0.07, 0.05, 0.09], [0.0, 0.5, 0.0, 0.75], [0.0025, 0.0045], [0.0006, 0.0014],
                            15300, n, loops=("pi", "pid"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# calib20 and fresh20: after the baseline fit's further starts (sigma0 and the Stribeck hump decades
# from the data-driven values; the fix for calib19's four false names, all baseline fits in a wrong basin)
CALIB20_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.04, 0.16, 0.55, 1.6, 3.8), "dwell": 3.2 if i % 2 else 3.7,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.55 * (i % 3), "f0": 0.05, "f1": 1.5, "duration": 40.0,
                             "bias": 0.45 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.3 + 0.45 * (i % 2), "f0": 0.06, "f1": 1.1 + 0.3 * (i % 3),
                            "n": 10 + 3 * (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.7 + 2.1 * (i % 3), "frequency": 0.13 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.4, -2.6, 1.7, -2.2, 2.5) if i % 2 else (-2.1, 2.7, -1.5, 2.5, -2.6, 1.3),
                                 "move_time": 1.25 + 0.5 * (i % 2), "dwell": 2.35, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.21, 0.6, 2.0, 3.9), "dwell": 2.45, "transition": 0.0, "repeats": 2},
}


def calib20_settings(n: int = 30):
    """A twentieth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets (encoder only,
    velocity only, both), on calib3's plants (SHARP, MASSIVE, DAMPED), 220-900 Hz, torque noise
    0.05-0.085 N*m, white in half the rows and AR(1) of coefficient 0.45 or 0.7 in the other half,
    velocity noise 0.003-0.005 deg/s, quantisation 0.0005-0.0013 deg; seeds 15400 + i."""
    return _effect_free_set("calib20", CALIB20_EXCITATIONS, ["sharp", "massive", "damped"],
                            [(True, False), (False, True), (True, True)], [220.0, 600.0, 350.0, 900.0, 450.0],
                            [0.085, 0.05, 0.065], [0.0, 0.45, 0.0, 0.7], [0.003, 0.005], [0.0005, 0.0013],
                            15400, n, loops=("pid", "pi"), nff=2, plant_k=2, fs_k=3, tn_rule=(2, 5))


_F20_FS = {"a": 260.0, "b": 430.0, "c": 310.0, "d": 520.0, "e": 240.0, "f": 470.0, "g": 380.0, "h": 290.0,
           "i": 340.0}
_F20_VARIED = _varied(1.1, 0.9, -0.6)


def fresh20_settings():
    """A fresh set (issue #30), fixed and committed before its first run: the other half of fresh3's
    24 effect rows (those fresh18 leaves out: each in-library effect once or twice) at 240-520 Hz
    (by recipe), seeds 15500 + k, with the gravity's phase, the asymmetry's sign and the ripple's
    period and phase changed."""
    return _refreshed("fresh20", _F20_FS, _F20_VARIED, 15500)[1::2]



# calib21, outside8 and fresh21: after the conditioned acceleration's bandwidth is computed from its
# filter (blend included) for compliance's plausibility; three plants no earlier set used
ZIPPY = T.Plant(J=0.09, Fc=0.55, Fs=0.95, vs=0.05, sigma2=1.05, sigma0=160.0, sigma1=0.9)
WEIGHTY = T.Plant(J=0.36, Fc=1.6, Fs=2.05, vs=0.07, sigma2=1.7, sigma0=300.0, sigma1=2.6)
ORDINARY = T.Plant(J=0.2, Fc=0.85, Fs=1.25, vs=0.058, sigma2=1.3, sigma0=220.0, sigma1=1.5)
_add_plants({"zippy": (ZIPPY, T.VelocityPIController(kp=4.0, ki=24.0)),
             "weighty": (WEIGHTY, T.VelocityPIController(kp=25.0, ki=150.0)),
             "ordinary": (ORDINARY, T.VelocityPIController(kp=12.0, ki=75.0))},
            {"zippy": PidTuning(3.2, 0.002),
             "weighty": PidTuning(2.6, 0.005),
             "ordinary": PidTuning(3.0, 0.003)})

CALIB21_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.045, 0.15, 0.6, 1.7, 3.6), "dwell": 3.1 if i % 2 else 3.6,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.048, "f1": 1.45, "duration": 38.0,
                             "bias": 0.5 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.5 * (i % 2), "f0": 0.058, "f1": 1.15 + 0.25 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 38.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.3 * (i % 3), "frequency": 0.15 + 0.04 * (i % 2),
                                "duration": 32.0},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.8, 1.6, -2.4, 2.7) if i % 2 else (-2.3, 2.6, -1.6, 2.3, -2.5, 1.2),
                                 "move_time": 1.35 + 0.4 * (i % 2), "dwell": 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.045, 0.19, 0.7, 1.9, 3.7), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib21_settings(n: int = 30):
    """A twenty-first effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets (encoder only,
    velocity only, both), on three plants no earlier set used (ZIPPY, WEIGHTY, ORDINARY), 180-1100 Hz,
    torque noise 0.045-0.08 N*m, white in half the rows and AR(1) of coefficient 0.5 or 0.65 in the
    other half, velocity noise 0.0035-0.005 deg/s, quantisation 0.0007-0.0011 deg; seeds 15600 + i."""
    return _effect_free_set("calib21", CALIB21_EXCITATIONS, ["zippy", "weighty", "ordinary"],
                            [(True, True), (True, False), (False, True)], [180.0, 700.0, 300.0, 1100.0, 420.0],
                            [0.06, 0.08, 0.045], [0.0, 0.5, 0.0, 0.65], [0.0035, 0.005], [0.0007, 0.0011],
                            15600, n, loops=("pi", "pid"), nff=3, plant_k=1, fs_k=2, tn_rule=(2, 4))


# outside8: outside5's rows on ZIPPY (for LITHE), WEIGHTY (for HULKING) and ORDINARY (for STEADY), at
# excitation parameters, rates and seeds no earlier set used
_OUT8_RECIPES = {
    "a": ("zippy", "pi", "multisine", {"amplitude": 2.3, "f0": 0.052, "f1": 1.6, "n": 12, "duration": 46.0},
          505.0, 0.06, 0.0, 0.003, 0.0009, True, True),
    "b": ("weighty", "pid", "point_to_point", {"amplitudes": (2.9, -3.4, 3.2, -2.1, -2.4, 3.0), "move_time": 1.5,
                                            "dwell": 2.5, "repeats": 2}, 395.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("zippy", "pi", "staircase", {"speeds": (0.045, 0.17, 0.75, 2.2, 5.0, 7.5), "dwell": 3.6,
                                      "transition": 0.4, "repeats": 1}, 335.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("ordinary", "pid", "sine_sweep", {"amplitude": 2.9, "f0": 0.052, "f1": 1.35, "duration": 48.0, "bias": 0.6},
          430.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("weighty", "pi", "multisine", {"amplitude": 2.3, "f0": 0.058, "f1": 1.5, "n": 11, "duration": 44.0},
          480.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("ordinary", "pid", "point_to_point", {"amplitudes": (-2.8, 3.6, -3.3, 2.4, 3.8, -2.9), "move_time": 1.4,
                                           "dwell": 2.7, "repeats": 2}, 345.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("weighty", "pid_nff", "point_to_point", {"amplitudes": (3.1, -3.9, 2.6, -3.1, 2.4, 1.6), "move_time": 1.6,
                                                "dwell": 2.6, "repeats": 2}, 310.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("zippy", "pi", "staircase", {"speeds": (0.055, 0.15, 0.6, 1.9, 4.6), "dwell": 4.0, "transition": 0.4,
                                      "repeats": 1}, 265.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside8_settings():
    """An eighth outside set (issue #31), fixed and committed before its first run: outside5's rows
    (the four effects outside the candidates, two recordings each) on ZIPPY, WEIGHTY and ORDINARY, at
    excitation parameters, rates and seeds (15700 + k) no earlier set used."""
    return _outside_set("outside8_", OUTSIDE5_ROWS, _OUT8_RECIPES, 15700)


_F21_FS = {"a": 280.0, "b": 410.0, "c": 230.0, "d": 560.0, "e": 330.0, "f": 495.0, "g": 360.0, "h": 305.0,
           "i": 450.0}
_F21_VARIED = _varied(-0.8, 1.1, 0.9)


def fresh21_settings():
    """A fresh set (issue #30), fixed and committed before its first run: the half of fresh3's 24
    effect rows fresh18 used (each in-library effect once or twice) at 230-560 Hz (by recipe), seeds
    15800 + k, with the gravity's phase, the asymmetry's sign and the ripple's period and phase
    changed."""
    return _refreshed("fresh21", _F21_FS, _F21_VARIED, 15800)[0::2]



# calib22 and fresh22: after held-out samples the training blocks do not determine leave the
# validation (leverage past the kinematics' criterion); calib14's plants, other excitations
CALIB22_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.038, 0.14, 0.58, 1.55, 3.5), "dwell": 3.3 if i % 2 else 3.8,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.75 + 0.5 * (i % 3), "f0": 0.052, "f1": 1.4, "duration": 39.0,
                             "bias": 0.55 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.45 * (i % 2), "f0": 0.057, "f1": 1.2 + 0.25 * (i % 3),
                            "n": 10 + 3 * (i % 2), "duration": 39.0},
    "position_sine": lambda i: {"amplitude": 2.8 + 2.0 * (i % 3), "frequency": 0.145 + 0.045 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.5, 1.9, -2.6, 2.2) if i % 2 else (-2.4, 2.8, -1.7, 2.2, -2.4, 1.5),
                                 "move_time": 1.3 + 0.45 * (i % 2), "dwell": 2.45, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.18, 0.62, 2.05, 3.6), "dwell": 2.55, "transition": 0.0, "repeats": 2},
}


def calib22_settings(n: int = 30):
    """A twenty-second effect-free set (issue #30), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on calib14's
    plants (WIRY14, BULKY14, TRIM), 160-950 Hz, torque noise 0.05-0.075 N*m, white in half the rows
    and AR(1) of coefficient 0.4 or 0.6 in the other half, velocity noise 0.003-0.0045 deg/s,
    quantisation 0.0006-0.0012 deg; seeds 15900 + i."""
    return _effect_free_set("calib22", CALIB22_EXCITATIONS, ["wiry14", "bulky14", "trim"],
                            [(False, True), (True, True), (True, False)], [160.0, 520.0, 260.0, 950.0, 380.0],
                            [0.05, 0.075, 0.062], [0.0, 0.4, 0.0, 0.6], [0.003, 0.0045], [0.0006, 0.0012],
                            15900, n, loops=("pid", "pi"), nff=0, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F22_FS = {"a": 300.0, "b": 440.0, "c": 250.0, "d": 510.0, "e": 270.0, "f": 460.0, "g": 350.0, "h": 320.0,
           "i": 400.0}
_F22_VARIED = _varied(0.4, 0.95, -1.4)


def fresh22_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh20's half of fresh3's
    24 effect rows at 250-510 Hz (by recipe), seeds 16000 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed."""
    return _refreshed("fresh22", _F22_FS, _F22_VARIED, 16000)[1::2]


# calib23 and fresh23: the design of calib22 (cc9a54a; later commits change no diagnosis), measured
# again on three plants no earlier set used, so that one design is measured on more than 40
# effect-free recordings
AGILE = T.Plant(J=0.11, Fc=0.62, Fs=1.02, vs=0.047, sigma2=1.1, sigma0=175.0, sigma1=1.05)
PONDEROUS = T.Plant(J=0.4, Fc=1.75, Fs=2.25, vs=0.072, sigma2=1.85, sigma0=320.0, sigma1=2.9)
AVERAGE = T.Plant(J=0.22, Fc=0.95, Fs=1.32, vs=0.061, sigma2=1.4, sigma0=235.0, sigma1=1.65)
_add_plants({"agile": (AGILE, T.VelocityPIController(kp=4.6, ki=27.0)),
             "ponderous": (PONDEROUS, T.VelocityPIController(kp=27.0, ki=160.0)),
             "average": (AVERAGE, T.VelocityPIController(kp=13.0, ki=80.0))},
            {"agile": PidTuning(3.1, 0.002),
             "ponderous": PidTuning(2.5, 0.005),
             "average": PidTuning(2.9, 0.003)})

CALIB23_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.042, 0.16, 0.55, 1.8, 3.9), "dwell": 3.4 if i % 2 else 3.9,
                            "transition": 0.32, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.85 + 0.45 * (i % 3), "f0": 0.05, "f1": 1.5, "duration": 40.0,
                             "bias": 0.45 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.5 * (i % 2), "f0": 0.055, "f1": 1.1 + 0.3 * (i % 3),
                            "n": 12 + 2 * (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.2 * (i % 3), "frequency": 0.14 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -2.2, 1.8, -2.7, 2.4) if i % 2 else (-2.2, 2.9, -1.9, 2.1, -2.6, 1.4),
                                 "move_time": 1.4 + 0.35 * (i % 2), "dwell": 2.6, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.048, 0.2, 0.66, 1.95, 3.8), "dwell": 2.6, "transition": 0.0, "repeats": 2},
}


def calib23_settings(n: int = 30):
    """A twenty-third effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (AGILE, PONDEROUS, AVERAGE), 170-1000 Hz, torque noise 0.048-0.078 N*m, white
    in half the rows and AR(1) of coefficient 0.45 or 0.7 in the other half, velocity noise
    0.0032-0.0048 deg/s, quantisation 0.00065-0.00115 deg; seeds 16100 + i."""
    return _effect_free_set("calib23", CALIB23_EXCITATIONS, ["agile", "ponderous", "average"],
                            [(True, False), (False, True), (True, True)], [170.0, 610.0, 240.0, 1000.0, 400.0],
                            [0.078, 0.048, 0.064], [0.0, 0.45, 0.0, 0.7], [0.0032, 0.0048], [0.00065, 0.00115],
                            16100, n, loops=("pi", "pid"), nff=3, plant_k=1, fs_k=2, tn_rule=(2, 4))


_F23_FS = {"a": 290.0, "b": 470.0, "c": 240.0, "d": 530.0, "e": 310.0, "f": 480.0, "g": 340.0, "h": 295.0,
           "i": 430.0}
_F23_VARIED = _varied(-0.5, 1.05, 1.2)


def fresh23_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh21's half of fresh3's
    24 effect rows at 240-530 Hz (by recipe), seeds 16200 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed."""
    return _refreshed("fresh23", _F23_FS, _F23_VARIED, 16200)[0::2]


# calib24 and fresh24: after compliance is plausible up to the acceleration's bandwidth (not 0.7
# of it); three plants no earlier set used
BRISKER = T.Plant(J=0.1, Fc=0.58, Fs=0.98, vs=0.052, sigma2=1.08, sigma0=165.0, sigma1=0.95)
HEAVYSET = T.Plant(J=0.38, Fc=1.68, Fs=2.15, vs=0.069, sigma2=1.78, sigma0=310.0, sigma1=2.75)
MIDSIZE = T.Plant(J=0.21, Fc=0.9, Fs=1.28, vs=0.06, sigma2=1.35, sigma0=228.0, sigma1=1.58)
_add_plants({"brisker": (BRISKER, T.VelocityPIController(kp=4.3, ki=25.0)),
             "heavyset": (HEAVYSET, T.VelocityPIController(kp=26.0, ki=155.0)),
             "midsize": (MIDSIZE, T.VelocityPIController(kp=12.5, ki=78.0))},
            {"brisker": PidTuning(3.15, 0.002),
             "heavyset": PidTuning(2.55, 0.005),
             "midsize": PidTuning(2.95, 0.003)})

CALIB24_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.04, 0.15, 0.57, 1.75, 3.7), "dwell": 3.5 if i % 2 else 3.7,
                            "transition": 0.33, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.5 * (i % 3), "f0": 0.049, "f1": 1.45, "duration": 38.5,
                             "bias": 0.5 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.45 * (i % 2), "f0": 0.056, "f1": 1.15 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 38.5},
    "position_sine": lambda i: {"amplitude": 2.7 + 2.1 * (i % 3), "frequency": 0.15 + 0.045 * (i % 2),
                                "duration": 33.5},
    "point_to_point": lambda i: {"amplitudes": (2.4, -2.3, 1.7, -2.5, 2.3) if i % 2 else (-2.3, 2.7, -1.8, 2.2, -2.5, 1.3),
                                 "move_time": 1.35 + 0.4 * (i % 2), "dwell": 2.55, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.046, 0.19, 0.64, 2.0, 3.75), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib24_settings(n: int = 30):
    """A twenty-fourth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (BRISKER, HEAVYSET, MIDSIZE), 190-900 Hz, torque noise 0.05-0.076 N*m, white
    in half the rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise
    0.0034-0.0046 deg/s, quantisation 0.0007-0.0012 deg; seeds 16300 + i."""
    return _effect_free_set("calib24", CALIB24_EXCITATIONS, ["brisker", "heavyset", "midsize"],
                            [(False, True), (True, True), (True, False)], [190.0, 560.0, 280.0, 900.0, 360.0],
                            [0.05, 0.076, 0.063], [0.0, 0.5, 0.0, 0.65], [0.0034, 0.0046], [0.0007, 0.0012],
                            16300, n, loops=("pid", "pi"), nff=0, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F24_FS = {"a": 310.0, "b": 455.0, "c": 260.0, "d": 545.0, "e": 300.0, "f": 470.0, "g": 355.0, "h": 285.0,
           "i": 415.0}
_F24_VARIED = _varied(0.7, 0.92, -0.6)


def fresh24_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh23's half of fresh3's
    24 effect rows (compliance b and d among them) at 260-545 Hz (by recipe), seeds 16400 + k, with
    the gravity's phase, the asymmetry's sign and the ripple's period and phase changed."""
    return _refreshed("fresh24", _F24_FS, _F24_VARIED, 16400)[0::2]


# calib25 and fresh25: after the time line is searched and fitted off the motion's own spectral
# lines; three plants no earlier set used
SVELTE = T.Plant(J=0.12, Fc=0.62, Fs=1.02, vs=0.048, sigma2=1.12, sigma0=172.0, sigma1=1.02)
THICKSET = T.Plant(J=0.41, Fc=1.74, Fs=2.22, vs=0.072, sigma2=1.84, sigma0=322.0, sigma1=2.9)
MODERATE = T.Plant(J=0.23, Fc=0.95, Fs=1.33, vs=0.057, sigma2=1.41, sigma0=236.0, sigma1=1.66)
_add_plants({"svelte": (SVELTE, T.VelocityPIController(kp=4.8, ki=28.0)),
             "thickset": (THICKSET, T.VelocityPIController(kp=28.0, ki=165.0)),
             "moderate": (MODERATE, T.VelocityPIController(kp=13.5, ki=82.0))},
            {"svelte": PidTuning(3.1, 0.002),
             "thickset": PidTuning(2.5, 0.005),
             "moderate": PidTuning(2.9, 0.003)})

CALIB25_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.038, 0.14, 0.6, 1.7, 3.9), "dwell": 3.3 if i % 2 else 3.9,
                            "transition": 0.36, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.45 * (i % 3), "f0": 0.051, "f1": 1.55, "duration": 39.5,
                             "bias": 0.45 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.5 * (i % 2), "f0": 0.053, "f1": 1.2 + 0.35 * (i % 3),
                            "n": 10 + 3 * (i % 2), "duration": 39.5},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.3 * (i % 3), "frequency": 0.16 + 0.04 * (i % 2),
                                "duration": 34.5},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.5, 1.6, -2.4, 2.6) if i % 2 else (-2.4, 2.6, -1.7, 2.3, -2.2, 1.4),
                                 "move_time": 1.4 + 0.35 * (i % 2), "dwell": 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.18, 0.7, 2.1, 3.6), "dwell": 2.6, "transition": 0.0, "repeats": 2},
}


def calib25_settings(n: int = 30):
    """A twenty-fifth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (SVELTE, THICKSET, MODERATE), 210-850 Hz, torque noise 0.055-0.08 N*m, white
    in half the rows and AR(1) of coefficient 0.55 or 0.7 in the other half, velocity noise
    0.0031-0.0049 deg/s, quantisation 0.0006-0.0013 deg; seeds 16500 + i."""
    return _effect_free_set("calib25", CALIB25_EXCITATIONS, ["svelte", "thickset", "moderate"],
                            [(False, True), (True, True), (True, False)], [210.0, 620.0, 330.0, 850.0, 240.0],
                            [0.055, 0.08, 0.066], [0.0, 0.55, 0.0, 0.7], [0.0031, 0.0049], [0.0006, 0.0013],
                            16500, n, loops=("pid", "pi"), nff=1, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F25_FS = {"a": 290.0, "b": 430.0, "c": 275.0, "d": 520.0, "e": 320.0, "f": 445.0, "g": 340.0, "h": 300.0,
           "i": 395.0}
_F25_VARIED = _varied(-0.5, 1.08, 0.9)


def fresh25_settings():
    """A fresh set (issue #30), fixed and committed before its first run: the other half of fresh3's
    24 effect rows than fresh24's (backlash, thermal drift, load-dependent and compliance c among
    them) at 275-520 Hz (by recipe), seeds 16600 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh25", _F25_FS, _F25_VARIED, 16600)[1::2]

# calib26 and fresh26: after the smoothing-bias rule reads the fitted model's whole torque; three
# plants no earlier set used
COMPACT = T.Plant(J=0.14, Fc=0.7, Fs=1.08, vs=0.05, sigma2=1.18, sigma0=185.0, sigma1=1.1)
ROBUST = T.Plant(J=0.36, Fc=1.6, Fs=2.05, vs=0.066, sigma2=1.7, sigma0=300.0, sigma1=2.6)
GANGLY = T.Plant(J=0.2, Fc=0.88, Fs=1.3, vs=0.062, sigma2=1.3, sigma0=220.0, sigma1=1.5)
_add_plants({"compact": (COMPACT, T.VelocityPIController(kp=5.5, ki=32.0)),
             "robust": (ROBUST, T.VelocityPIController(kp=25.0, ki=150.0)),
             "gangly": (GANGLY, T.VelocityPIController(kp=12.0, ki=74.0))},
            {"compact": PidTuning(3.05, 0.002),
             "robust": PidTuning(2.6, 0.005),
             "gangly": PidTuning(2.95, 0.003)})

CALIB26_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.042, 0.16, 0.55, 1.8, 3.6), "dwell": 3.4 if i % 2 else 3.8,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.85 + 0.5 * (i % 3), "f0": 0.047, "f1": 1.5, "duration": 37.5,
                             "bias": 0.55 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.05 + 0.45 * (i % 2), "f0": 0.055, "f1": 1.1 + 0.35 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 37.5},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.2 * (i % 3), "frequency": 0.155 + 0.045 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.4, 1.8, -2.6, 2.2) if i % 2 else (-2.2, 2.8, -1.6, 2.4, -2.4, 1.2),
                                 "move_time": 1.3 + 0.4 * (i % 2), "dwell": 2.6, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.048, 0.2, 0.62, 1.9, 3.8), "dwell": 2.55, "transition": 0.0, "repeats": 2},
}


def calib26_settings(n: int = 30):
    """A twenty-sixth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops x the three sensor sets, on three plants no
    earlier set used (COMPACT, ROBUST, GANGLY), 200-880 Hz, torque noise 0.058-0.078 N*m, white
    in half the rows and AR(1) of coefficient 0.6 or 0.45 in the other half, velocity noise
    0.0033-0.0052 deg/s, quantisation 0.0005-0.0011 deg; seeds 16700 + i."""
    return _effect_free_set("calib26", CALIB26_EXCITATIONS, ["compact", "robust", "gangly"],
                            [(False, True), (True, True), (True, False)], [230.0, 640.0, 300.0, 880.0, 200.0],
                            [0.058, 0.078, 0.062], [0.0, 0.6, 0.0, 0.45], [0.0033, 0.0052], [0.0005, 0.0011],
                            16700, n, loops=("pid", "pi"), nff=2, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F26_FS = {"a": 330.0, "b": 470.0, "c": 250.0, "d": 500.0, "e": 285.0, "f": 430.0, "g": 365.0, "h": 275.0,
           "i": 405.0}
_F26_VARIED = _varied(1.1, 0.95, -1.0)


def fresh26_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's effect rows k
    with k % 4 in (1, 2), half from each of fresh24's and fresh25's halves (Stribeck shape d and h,
    load-dependent e, compliance b, backlash a and e among them), at 250-500 Hz (by recipe), seeds
    16800 + k, with the gravity's phase, the asymmetry's sign and the ripple's period and phase
    changed."""
    rows = _refreshed("fresh26", _F26_FS, _F26_VARIED, 16800)
    return [r for k, r in enumerate(rows) if k % 4 in (1, 2)]

# calib27 and fresh27: after the smoothing-bias rule reads the fitted model's whole torque except on
# a quantised position's derivatives; three plants no earlier set used
LISSOM = T.Plant(J=0.16, Fc=0.74, Fs=1.12, vs=0.053, sigma2=1.22, sigma0=195.0, sigma1=1.2)
SQUAT = T.Plant(J=0.33, Fc=1.52, Fs=1.98, vs=0.069, sigma2=1.62, sigma0=288.0, sigma1=2.45)
RANGY = T.Plant(J=0.25, Fc=1.02, Fs=1.41, vs=0.059, sigma2=1.46, sigma0=245.0, sigma1=1.75)
_add_plants({"lissom": (LISSOM, T.VelocityPIController(kp=6.2, ki=36.0)),
             "squat": (SQUAT, T.VelocityPIController(kp=23.0, ki=138.0)),
             "rangy": (RANGY, T.VelocityPIController(kp=14.5, ki=88.0))},
            {"lissom": PidTuning(3.0, 0.002),
             "squat": PidTuning(2.65, 0.005),
             "rangy": PidTuning(2.85, 0.003)})

CALIB27_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.045, 0.15, 0.58, 1.65, 3.7), "dwell": 3.2 if i % 2 else 3.7,
                            "transition": 0.33, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.55 * (i % 3), "f0": 0.049, "f1": 1.45, "duration": 38.5,
                             "bias": 0.5 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.4 * (i % 2), "f0": 0.052, "f1": 1.15 + 0.3 * (i % 3),
                            "n": 10 + 2 * (i % 2), "duration": 38.5},
    "position_sine": lambda i: {"amplitude": 2.7 + 2.1 * (i % 3), "frequency": 0.15 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.4, -2.3, 1.7, -2.5, 2.3) if i % 2 else (-2.3, 2.7, -1.5, 2.5, -2.3, 1.3),
                                 "move_time": 1.35 + 0.4 * (i % 2), "dwell": 2.55, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.052, 0.19, 0.66, 2.0, 3.7), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib27_settings(n: int = 30):
    """A twenty-seventh effect-free set (issue #30), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (LISSOM, SQUAT, RANGY), 205-870 Hz, torque noise 0.057-0.079 N*m, white in
    half the rows and AR(1) of coefficient 0.5 or 0.65 in the other half, velocity noise
    0.0032-0.005 deg/s, quantisation 0.0006-0.0012 deg; seeds 17000 + i."""
    return _effect_free_set("calib27", CALIB27_EXCITATIONS, ["lissom", "squat", "rangy"],
                            [(False, True), (True, True), (True, False)], [205.0, 610.0, 310.0, 870.0, 235.0],
                            [0.057, 0.079, 0.064], [0.0, 0.5, 0.0, 0.65], [0.0032, 0.005], [0.0006, 0.0012],
                            17000, n, loops=("pid", "pi"), nff=3, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F27_FS = {"a": 310.0, "b": 450.0, "c": 265.0, "d": 510.0, "e": 295.0, "f": 420.0, "g": 355.0, "h": 285.0,
           "i": 385.0}
_F27_VARIED = _varied(0.6, 1.04, 1.7)


def fresh27_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's effect rows k
    with k % 4 in (0, 3), half from each of fresh24's and fresh25's halves, at 265-510 Hz (by
    recipe), seeds 17100 + k, with the gravity's phase, the asymmetry's sign and the ripple's period
    and phase changed."""
    rows = _refreshed("fresh27", _F27_FS, _F27_VARIED, 17100)
    return [r for k, r in enumerate(rows) if k % 4 in (0, 3)]

# calib28 and fresh28: after a compliance refused above the acceleration's bandwidth stays in the
# model for the rest of its selection step, and a compliance is identifiable only against the
# kinematic error's lines of the motion; three plants no earlier set used
SINEWY = T.Plant(J=0.18, Fc=0.78, Fs=1.17, vs=0.056, sigma2=1.26, sigma0=205.0, sigma1=1.3)
DUMPY = T.Plant(J=0.31, Fc=1.45, Fs=1.92, vs=0.067, sigma2=1.58, sigma0=280.0, sigma1=2.35)
GAUNT = T.Plant(J=0.23, Fc=0.97, Fs=1.36, vs=0.061, sigma2=1.41, sigma0=238.0, sigma1=1.65)
_add_plants({"sinewy": (SINEWY, T.VelocityPIController(kp=7.0, ki=40.0)),
             "dumpy": (DUMPY, T.VelocityPIController(kp=21.5, ki=130.0)),
             "gaunt": (GAUNT, T.VelocityPIController(kp=13.5, ki=82.0))},
            {"sinewy": PidTuning(3.0, 0.002),
             "dumpy": PidTuning(2.7, 0.005),
             "gaunt": PidTuning(2.9, 0.003)})

CALIB28_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.047, 0.17, 0.6, 1.75, 3.55), "dwell": 3.3 if i % 2 else 3.9,
                            "transition": 0.31, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.051, "f1": 1.55, "duration": 37.0,
                             "bias": 0.6 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.45 * (i % 2), "f0": 0.05, "f1": 1.2 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 37.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.3 * (i % 3), "frequency": 0.16 + 0.04 * (i % 2),
                                "duration": 33.5},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.5, 1.9, -2.4, 2.1) if i % 2 else (-2.4, 2.6, -1.7, 2.3, -2.5, 1.4),
                                 "move_time": 1.25 + 0.45 * (i % 2), "dwell": 2.65, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.21, 0.64, 1.85, 3.9), "dwell": 2.45, "transition": 0.0, "repeats": 2},
}


def calib28_settings(n: int = 30):
    """A twenty-eighth effect-free set (issue #30), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (SINEWY, DUMPY, GAUNT), 215-860 Hz, torque noise 0.059-0.077 N*m, white in
    half the rows and AR(1) of coefficient 0.55 or 0.4 in the other half, velocity noise
    0.0034-0.0049 deg/s, quantisation 0.0005-0.0010 deg; seeds 17200 + i."""
    return _effect_free_set("calib28", CALIB28_EXCITATIONS, ["sinewy", "dumpy", "gaunt"],
                            [(False, True), (True, True), (True, False)], [215.0, 620.0, 320.0, 860.0, 245.0],
                            [0.059, 0.077, 0.066], [0.0, 0.55, 0.0, 0.4], [0.0034, 0.0049], [0.0005, 0.001],
                            17200, n, loops=("pid", "pi"), nff=0, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F28_FS = {"a": 320.0, "b": 440.0, "c": 270.0, "d": 505.0, "e": 300.0, "f": 425.0, "g": 350.0, "h": 290.0,
           "i": 390.0}
_F28_VARIED = _varied(-0.9, 0.97, 2.3)


def fresh28_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's effect rows k
    with k % 4 in (1, 2), at 270-505 Hz (by recipe), seeds 17300 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed."""
    rows = _refreshed("fresh28", _F28_FS, _F28_VARIED, 17300)
    return [r for k, r in enumerate(rows) if k % 4 in (1, 2)]

# calib29 and fresh29: after the torque noise is estimated again through the fitted baseline (the
# differences the model's torque sets left out of the noise profile); three plants no earlier set used
WILLOWY = T.Plant(J=0.2, Fc=0.84, Fs=1.24, vs=0.058, sigma2=1.31, sigma0=218.0, sigma1=1.45)
SPINDLY = T.Plant(J=0.27, Fc=1.21, Fs=1.66, vs=0.064, sigma2=1.49, sigma0=256.0, sigma1=2.0)
LEGGY = T.Plant(J=0.34, Fc=1.52, Fs=2.02, vs=0.07, sigma2=1.66, sigma0=292.0, sigma1=2.5)
_add_plants({"willowy": (WILLOWY, T.VelocityPIController(kp=9.0, ki=52.0)),
             "spindly": (SPINDLY, T.VelocityPIController(kp=16.5, ki=100.0)),
             "leggy": (LEGGY, T.VelocityPIController(kp=24.0, ki=145.0))},
            {"willowy": PidTuning(2.95, 0.002),
             "spindly": PidTuning(2.8, 0.004),
             "leggy": PidTuning(2.65, 0.005)})

CALIB29_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.043, 0.16, 0.62, 1.7, 3.65), "dwell": 3.4 if i % 2 else 3.8,
                            "transition": 0.29, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.0 + 0.45 * (i % 3), "f0": 0.053, "f1": 1.5, "duration": 37.5,
                             "bias": 0.55 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.5 * (i % 2), "f0": 0.048, "f1": 1.25 + 0.3 * (i % 3),
                            "n": 10 + 2 * (i % 2), "duration": 37.5},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.2 * (i % 3), "frequency": 0.155 + 0.045 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.4, 1.8, -2.6, 2.0) if i % 2 else (-2.5, 2.5, -1.6, 2.4, -2.2, 1.5),
                                 "move_time": 1.3 + 0.4 * (i % 2), "dwell": 2.6, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.048, 0.2, 0.63, 1.9, 3.8), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib29_settings(n: int = 30):
    """A twenty-ninth effect-free set (issue #30), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (WILLOWY, SPINDLY, LEGGY), 195-890 Hz, torque noise 0.061-0.075 N*m, white in
    half the rows and AR(1) of coefficient 0.6 or 0.7 in the other half, velocity noise
    0.0036-0.0047 deg/s, quantisation 0.0007-0.0011 deg; seeds 17400 + i."""
    return _effect_free_set("calib29", CALIB29_EXCITATIONS, ["willowy", "spindly", "leggy"],
                            [(False, True), (True, True), (True, False)], [195.0, 640.0, 305.0, 890.0, 225.0],
                            [0.061, 0.075, 0.068], [0.0, 0.6, 0.0, 0.7], [0.0036, 0.0047], [0.0007, 0.0011],
                            17400, n, loops=("pid", "pi"), nff=2, plant_k=2, fs_k=1, tn_rule=(1, 3))


_F29_FS = {"a": 300.0, "b": 455.0, "c": 260.0, "d": 495.0, "e": 310.0, "f": 415.0, "g": 345.0, "h": 280.0,
           "i": 395.0}
_F29_VARIED = _varied(1.3, 1.03, -1.1)


def fresh29_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 260-495 Hz (by recipe), seeds 17500 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh29", _F29_FS, _F29_VARIED, 17500)


# calib30 and outside9: first run on 2c7cded, whose attribution decided by its calibrated tests alone
# (no margin on the size of a term's held-out gain; the margin is back since 5722a70); three plants no
# earlier set used
WISPY = T.Plant(J=0.17, Fc=0.78, Fs=1.12, vs=0.052, sigma2=1.22, sigma0=204.0, sigma1=1.3)
REEDY = T.Plant(J=0.24, Fc=1.08, Fs=1.47, vs=0.061, sigma2=1.43, sigma0=241.0, sigma1=1.8)
PLUMP = T.Plant(J=0.37, Fc=1.63, Fs=2.18, vs=0.073, sigma2=1.74, sigma0=305.0, sigma1=2.7)
_add_plants({"wispy": (WISPY, T.VelocityPIController(kp=8.0, ki=46.0)),
             "reedy": (REEDY, T.VelocityPIController(kp=14.5, ki=88.0)),
             "plump": (PLUMP, T.VelocityPIController(kp=26.0, ki=155.0))},
            {"wispy": PidTuning(3.0, 0.002),
             "reedy": PidTuning(2.85, 0.003),
             "plump": PidTuning(2.6, 0.005)})

CALIB30_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.038, 0.14, 0.57, 1.55, 3.45), "dwell": 3.3 if i % 2 else 3.7,
                            "transition": 0.33, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.049, "f1": 1.4, "duration": 38.5,
                             "bias": 0.5 + 0.4 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.55 * (i % 2), "f0": 0.051, "f1": 1.15 + 0.35 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 38.5},
    "position_sine": lambda i: {"amplitude": 2.4 + 2.3 * (i % 3), "frequency": 0.145 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.6, 1.9, -2.3, 2.1) if i % 2 else (-2.4, 2.3, -1.7, 2.6, -2.0, 1.4),
                                 "move_time": 1.25 + 0.45 * (i % 2), "dwell": 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.052, 0.19, 0.6, 1.75, 3.6), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib30_settings(n: int = 30):
    """A thirtieth effect-free set (issues #30 and #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (WISPY, REEDY, PLUMP), 185-910 Hz, torque noise 0.055-0.078 N*m, white in half
    the rows and AR(1) of coefficient 0.55 or 0.65 in the other half, velocity noise
    0.0033-0.0049 deg/s, quantisation 0.0008-0.0012 deg; seeds 17800 + i."""
    return _effect_free_set("calib30", CALIB30_EXCITATIONS, ["wispy", "reedy", "plump"],
                            [(True, True), (False, True), (True, False)], [185.0, 470.0, 910.0, 265.0, 640.0],
                            [0.055, 0.078, 0.066], [0.0, 0.55, 0.0, 0.65], [0.0033, 0.0049], [0.0008, 0.0012],
                            17800, n, loops=("pi", "pid"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# outside9: outside5's rows (the four effects outside the candidates, two each) on calib30's plants,
# at excitation parameters, rates and seeds no earlier set used
_OUT9_RECIPES = {
    "a": ("wispy", "pi", "multisine", {"amplitude": 2.4, "f0": 0.05, "f1": 1.7, "n": 11, "duration": 45.0},
          490.0, 0.06, 0.0, 0.003, 0.0009, True, True),
    "b": ("plump", "pid", "point_to_point", {"amplitudes": (3.0, -3.2, 3.4, -2.2, -2.6, 2.8), "move_time": 1.45,
                                           "dwell": 2.6, "repeats": 2}, 410.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("wispy", "pi", "staircase", {"speeds": (0.04, 0.16, 0.7, 2.3, 5.2, 7.8), "dwell": 3.5,
                                      "transition": 0.42, "repeats": 1}, 350.0, 0.05, 0.0, 0.003, 0.0011, True, True),
    "d": ("reedy", "pid", "sine_sweep", {"amplitude": 3.0, "f0": 0.05, "f1": 1.3, "duration": 47.0, "bias": 0.65},
          445.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("plump", "pi", "multisine", {"amplitude": 2.2, "f0": 0.056, "f1": 1.55, "n": 10, "duration": 45.0},
          470.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("reedy", "pid", "point_to_point", {"amplitudes": (-2.7, 3.5, -3.1, 2.5, 3.6, -3.0), "move_time": 1.35,
                                           "dwell": 2.8, "repeats": 2}, 355.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("plump", "pid_nff", "point_to_point", {"amplitudes": (3.2, -3.7, 2.7, -3.0, 2.3, 1.7), "move_time": 1.55,
                                               "dwell": 2.7, "repeats": 2}, 320.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("wispy", "pi", "staircase", {"speeds": (0.05, 0.14, 0.58, 2.0, 4.4), "dwell": 4.1, "transition": 0.42,
                                      "repeats": 1}, 275.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


# outside5's rows with the lag a shortened to 1.4 ms (outside9 and every outside set after it)
OUTSIDE9_ROWS = _resized(OUTSIDE5_ROWS, {"a": {"T": 0.0014}})


def outside9_settings():
    """A ninth outside set (issue #31), fixed and committed before its first run: outside5's rows
    (the four effects outside the candidates, two recordings each) on WISPY, REEDY and PLUMP, at
    excitation parameters, rates and seeds (17900 + k) no earlier set used; the lag a shortened to 1.4 ms,
    so that on WISPY its peak stays below the per-sample noise (2 ms gives 1.26 of it)."""
    return _outside_set("outside9_", OUTSIDE9_ROWS, _OUT9_RECIPES, 17900)


# calib31 and fresh30: the design of 5722a70 (the attribution's margin back), unchanged since; three
# plants no earlier set used
BONY = T.Plant(J=0.19, Fc=0.88, Fs=1.29, vs=0.056, sigma2=1.27, sigma0=212.0, sigma1=1.4)
GAWKY = T.Plant(J=0.26, Fc=1.15, Fs=1.58, vs=0.066, sigma2=1.52, sigma0=249.0, sigma1=1.95)
CHUBBY = T.Plant(J=0.35, Fc=1.57, Fs=2.09, vs=0.069, sigma2=1.69, sigma0=298.0, sigma1=2.55)
_add_plants({"bony": (BONY, T.VelocityPIController(kp=8.5, ki=49.0)),
             "gawky": (GAWKY, T.VelocityPIController(kp=15.5, ki=94.0)),
             "chubby": (CHUBBY, T.VelocityPIController(kp=25.0, ki=150.0))},
            {"bony": PidTuning(2.9, 0.002),
             "gawky": PidTuning(2.75, 0.004),
             "chubby": PidTuning(2.7, 0.005)})

CALIB31_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.041, 0.15, 0.59, 1.65, 3.5), "dwell": 3.2 if i % 2 else 3.6,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.55 * (i % 3), "f0": 0.052, "f1": 1.45, "duration": 38.0,
                             "bias": 0.45 + 0.4 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.05 + 0.5 * (i % 2), "f0": 0.047, "f1": 1.1 + 0.35 * (i % 3),
                            "n": 12 + 2 * (i % 2), "duration": 38.0},
    "position_sine": lambda i: {"amplitude": 2.3 + 2.4 * (i % 3), "frequency": 0.15 + 0.05 * (i % 2),
                                "duration": 34.5},
    "point_to_point": lambda i: {"amplitudes": (2.1, -2.5, 2.0, -2.2, 2.4) if i % 2 else (-2.3, 2.4, -1.8, 2.5, -2.1, 1.5),
                                 "move_time": 1.2 + 0.5 * (i % 2), "dwell": 2.55, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.18, 0.61, 1.8, 3.7), "dwell": 2.55, "transition": 0.0, "repeats": 2},
}


def calib31_settings(n: int = 30):
    """A thirty-first effect-free set (issues #30 and #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops x the three sensor sets, on three plants
    no earlier set used (BONY, GAWKY, CHUBBY), 205-880 Hz, torque noise 0.057-0.076 N*m, white in half
    the rows and AR(1) of coefficient 0.5 or 0.75 in the other half, velocity noise
    0.0035-0.0048 deg/s, quantisation 0.0006-0.0011 deg; seeds 18000 + i."""
    return _effect_free_set("calib31", CALIB31_EXCITATIONS, ["bony", "gawky", "chubby"],
                            [(True, False), (True, True), (False, True)], [205.0, 560.0, 880.0, 290.0, 415.0],
                            [0.057, 0.076, 0.064], [0.0, 0.5, 0.0, 0.75], [0.0035, 0.0048], [0.0006, 0.0011],
                            18000, n, loops=("pid", "pi"), nff=3, plant_k=2, fs_k=2, tn_rule=(1, 5))


_F30_FS = {"a": 310.0, "b": 465.0, "c": 255.0, "d": 480.0, "e": 330.0, "f": 405.0, "g": 360.0, "h": 285.0,
           "i": 375.0}
_F30_VARIED = _varied(-1.7, 0.95, 0.8)


def fresh30_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 255-480 Hz (by recipe), seeds 18100 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh30", _F30_FS, _F30_VARIED, 18100)


def _cell(row: dict, prefix: str, seeds) -> list[dict]:
    """``row``'s design cell: the row again on each of ``seeds``, everything else as it is, keyed
    ``<prefix>_<row number>_<k>_<excitation and loop>``."""
    _, i, rest = row["key"].split("_", 2)
    return [row | {"key": f"{prefix}_{i}_{k}_{rest}", "seed": seed} for k, seed in enumerate(seeds)]


def calib31_cells_settings():
    """calib31's two false names with the fitted baseline (rows 02 and 04: encoder-only, position PID)
    repeated on six new seeds each (18300 + 10*row + k), everything else as the row: the false-alarm
    rate of those two design cells, not of the rows' one noise realisation. Fixed and committed before
    its first run."""
    rows = calib31_settings()
    return [r for i in (2, 4) for r in _cell(rows[i], "calib31cells", [18300 + 10 * i + k for k in range(6)])]


def calib30_cells_settings():
    """calib30_09's design cell (REEDY, position sine under the position PID without feedforward,
    encoder and velocity sensor; its false term without the attribution's margin came with a baseline
    far from the generator's parameters) on six new seeds (18400 + k), everything else as the row: the
    cell's false-alarm rate on the current design. Fixed and committed before its first run."""
    return _cell(calib30_settings()[9], "calib30cells", [18400 + k for k in range(6)])


# calib32pid: the position loop alone. Over the held-out effect-free sets, the false names fell on
# position-PID rows; this set measures that loop's false-alarm rate on the current design. Three
# plants no earlier set used.
GRACILE = T.Plant(J=0.15, Fc=0.80, Fs=1.18, vs=0.050, sigma2=1.20, sigma0=200.0, sigma1=1.3)
MEATY = T.Plant(J=0.30, Fc=1.30, Fs=1.80, vs=0.063, sigma2=1.60, sigma0=270.0, sigma1=2.1)
HEFTIER = T.Plant(J=0.40, Fc=1.70, Fs=2.30, vs=0.072, sigma2=1.80, sigma0=320.0, sigma1=2.7)
_add_plants({"gracile": (GRACILE, T.VelocityPIController(kp=7.0, ki=41.0)),
             "meaty": (MEATY, T.VelocityPIController(kp=18.0, ki=108.0)),
             "heftier": (HEFTIER, T.VelocityPIController(kp=28.0, ki=168.0))},
            {"gracile": PidTuning(3.1, 0.002),
             "meaty": PidTuning(2.8, 0.004),
             "heftier": PidTuning(2.6, 0.005)})

CALIB32_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.038, 0.14, 0.55, 1.55, 3.4), "dwell": 3.1 if i % 2 else 3.5,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.049, "f1": 1.5, "duration": 37.0,
                             "bias": 0.5 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.15 + 0.45 * (i % 2), "f0": 0.051, "f1": 1.15 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 37.0},
    "position_sine": lambda i: {"amplitude": 2.2 + 2.3 * (i % 3), "frequency": 0.16 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.4, 1.9, -2.1, 2.5) if i % 2 else (-2.2, 2.5, -1.9, 2.3, -2.0, 1.6),
                                 "move_time": 1.25 + 0.45 * (i % 2), "dwell": 2.6, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.055, 0.19, 0.63, 1.75, 3.6), "dwell": 2.6, "transition": 0.0, "repeats": 2},
}


def calib32pid_settings(n: int = 36):
    """An effect-free set of the position loop alone (issue #30), fixed and committed before its first
    run: the six excitation kinds with other parameters x the position PID (without feedforward in
    every fourth row) x the three sensor sets, on three plants no earlier set used (GRACILE, MEATY,
    HEFTIER), 230-760 Hz, torque noise 0.055-0.072 N*m, white in half the rows and AR(1) of
    coefficient 0.6 or 0.8 in the other half, velocity noise 0.0038-0.0052 deg/s, quantisation
    0.0007-0.0012 deg; seeds 18500 + i."""
    return _effect_free_set("calib32pid", CALIB32_EXCITATIONS, ["gracile", "meaty", "heftier"],
                            [(True, False), (True, True), (False, True)], [230.0, 470.0, 760.0, 330.0, 610.0],
                            [0.061, 0.072, 0.055], [0.0, 0.6, 0.0, 0.8], [0.0038, 0.0052], [0.0007, 0.0012],
                            18500, n, loops=("pid", "pid"), nff=1, plant_k=2, fs_k=2, tn_rule=(1, 5))


# calib33 and fresh31: the design of the floor's cap from r^2's own variance (issue #30); three
# plants no earlier set used
SCRAWNY = T.Plant(J=0.12, Fc=0.70, Fs=1.05, vs=0.055, sigma2=1.10, sigma0=190.0, sigma1=1.15)
HARDY = T.Plant(J=0.24, Fc=1.05, Fs=1.50, vs=0.060, sigma2=1.40, sigma0=240.0, sigma1=1.75)
ROTUND = T.Plant(J=0.33, Fc=1.45, Fs=1.95, vs=0.068, sigma2=1.65, sigma0=285.0, sigma1=2.30)
_add_plants({"scrawny": (SCRAWNY, T.VelocityPIController(kp=5.5, ki=32.0)),
             "hardy": (HARDY, T.VelocityPIController(kp=13.0, ki=78.0)),
             "rotund": (ROTUND, T.VelocityPIController(kp=22.0, ki=132.0))},
            {"scrawny": PidTuning(3.2, 0.002),
             "hardy": PidTuning(2.9, 0.003),
             "rotund": PidTuning(2.7, 0.005)})

CALIB33_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.044, 0.16, 0.57, 1.6, 3.45), "dwell": 3.0 if i % 2 else 3.3,
                            "transition": 0.33, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.0 + 0.45 * (i % 3), "f0": 0.05, "f1": 1.4, "duration": 36.0,
                             "bias": 0.55 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.5 * (i % 2), "f0": 0.048, "f1": 1.2 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 36.0},
    "position_sine": lambda i: {"amplitude": 2.4 + 2.2 * (i % 3), "frequency": 0.17 + 0.04 * (i % 2),
                                "duration": 33.5},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.2, 2.0, -2.4, 2.1) if i % 2 else (-2.1, 2.3, -2.0, 2.4, -1.8, 1.7),
                                 "move_time": 1.3 + 0.4 * (i % 2), "dwell": 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.052, 0.2, 0.66, 1.7, 3.5), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib33_settings(n: int = 40):
    """A thirty-third effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops (the position PID without feedforward in
    every fourth row) x the three sensor sets, on three plants no earlier set used (SCRAWNY, HARDY,
    ROTUND), 250-840 Hz, torque noise 0.058-0.077 N*m, white in half the rows and AR(1) of
    coefficient 0.55 or 0.8 in the other half, velocity noise 0.0033-0.005 deg/s, quantisation
    0.0005-0.001 deg; seeds 19100 + i."""
    return _effect_free_set("calib33", CALIB33_EXCITATIONS, ["scrawny", "hardy", "rotund"],
                            [(True, True), (True, False), (False, True)], [250.0, 520.0, 840.0, 360.0, 680.0],
                            [0.058, 0.069, 0.077], [0.0, 0.55, 0.0, 0.8], [0.0033, 0.005], [0.0005, 0.001],
                            19100, n, loops=("pid", "pi"), nff=2, plant_k=1, fs_k=3, tn_rule=(2, 7))


_F31_FS = {"a": 290.0, "b": 445.0, "c": 270.0, "d": 505.0, "e": 320.0, "f": 395.0, "g": 350.0, "h": 295.0,
           "i": 385.0}
_F31_VARIED = _varied(2.2, 1.07, -1.1)


def fresh31_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 270-505 Hz (by recipe), seeds 19200 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh31", _F31_FS, _F31_VARIED, 19200)


# calib34 and fresh32: the design of the refined noise fit's signal column (issue #30); three plants
# no earlier set used
PUNY = T.Plant(J=0.14, Fc=0.78, Fs=1.12, vs=0.05, sigma2=1.2, sigma0=205.0, sigma1=1.3)
BULBOUS = T.Plant(J=0.27, Fc=1.15, Fs=1.62, vs=0.064, sigma2=1.5, sigma0=255.0, sigma1=1.9)
STRAPPING = T.Plant(J=0.36, Fc=1.55, Fs=2.05, vs=0.071, sigma2=1.75, sigma0=300.0, sigma1=2.45)
_add_plants({"puny": (PUNY, T.VelocityPIController(kp=6.2, ki=36.0)),
             "bulbous": (BULBOUS, T.VelocityPIController(kp=14.5, ki=86.0)),
             "strapping": (STRAPPING, T.VelocityPIController(kp=24.0, ki=144.0))},
            {"puny": PidTuning(3.1, 0.002),
             "bulbous": PidTuning(2.8, 0.004),
             "strapping": PidTuning(2.6, 0.005)})

CALIB34_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.047, 0.17, 0.6, 1.55, 3.3), "dwell": 2.9 if i % 2 else 3.2,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.055, "f1": 1.5, "duration": 35.0,
                             "bias": 0.6 + 0.25 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.55 * (i % 2), "f0": 0.05, "f1": 1.25 + 0.3 * (i % 3),
                            "n": 12 + 2 * (i % 2), "duration": 35.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.0 * (i % 3), "frequency": 0.16 + 0.045 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (-2.2, 2.4, -2.1, 2.2, -1.9) if i % 2 else (2.0, -2.3, 2.2, -2.5, 1.8, -1.6),
                                 "move_time": 1.2 + 0.45 * (i % 2), "dwell": 2.4, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.21, 0.7, 1.65, 3.4), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib34_settings(n: int = 40):
    """A thirty-fourth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops (the position PID without feedforward in
    every fourth row) x the three sensor sets, on three plants no earlier set used (PUNY, BULBOUS,
    STRAPPING), 240-870 Hz, torque noise 0.056-0.075 N*m, white in half the rows and AR(1) of
    coefficient 0.65 or 0.8 in the other half, velocity noise 0.0035-0.0048 deg/s, quantisation
    0.0006-0.0011 deg; seeds 19300 + i."""
    return _effect_free_set("calib34", CALIB34_EXCITATIONS, ["puny", "bulbous", "strapping"],
                            [(False, True), (True, True), (True, False)], [240.0, 540.0, 870.0, 340.0, 650.0],
                            [0.064, 0.056, 0.075], [0.0, 0.8, 0.0, 0.65], [0.0035, 0.0048], [0.0006, 0.0011],
                            19300, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=2, tn_rule=(1, 4))


_F32_FS = {"a": 310.0, "b": 430.0, "c": 285.0, "d": 520.0, "e": 340.0, "f": 375.0, "g": 365.0, "h": 280.0,
           "i": 405.0}
_F32_VARIED = _varied(0.6, 0.94, 2.4)


def fresh32_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 280-520 Hz (by recipe), seeds 19400 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh32", _F32_FS, _F32_VARIED, 19400)


# calib35, outside10 and fresh33: the design with the acceleration's blur at the friction's fast
# changes as a nuisance column and the attribution decided by its calibrated tests alone (issues #30,
# #31); three plants no earlier set used
BONEY = T.Plant(J=0.15, Fc=0.82, Fs=1.18, vs=0.048, sigma2=1.25, sigma0=215.0, sigma1=1.35)
TUBBY = T.Plant(J=0.26, Fc=1.12, Fs=1.55, vs=0.058, sigma2=1.45, sigma0=250.0, sigma1=1.85)
CHONKY = T.Plant(J=0.39, Fc=1.6, Fs=2.15, vs=0.069, sigma2=1.8, sigma0=310.0, sigma1=2.6)
_add_plants({"boney": (BONEY, T.VelocityPIController(kp=6.8, ki=40.0)),
             "tubby": (TUBBY, T.VelocityPIController(kp=14.0, ki=84.0)),
             "chonky": (CHONKY, T.VelocityPIController(kp=26.0, ki=150.0))},
            {"boney": PidTuning(3.05, 0.002),
             "tubby": PidTuning(2.85, 0.004),
             "chonky": PidTuning(2.6, 0.005)})

CALIB35_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.044, 0.16, 0.62, 1.6, 3.5), "dwell": 3.0 if i % 2 else 3.4,
                            "transition": 0.32, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.0 + 0.45 * (i % 3), "f0": 0.052, "f1": 1.45, "duration": 36.0,
                             "bias": 0.55 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.5 * (i % 2), "f0": 0.053, "f1": 1.2 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 36.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.1 * (i % 3), "frequency": 0.15 + 0.05 * (i % 2),
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.1, 2.4, -2.0, 1.8) if i % 2 else (-2.1, 2.5, -2.3, 2.2, -1.7, 1.5),
                                 "move_time": 1.3 + 0.4 * (i % 2), "dwell": 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.055, 0.2, 0.65, 1.7, 3.5), "dwell": 2.5, "transition": 0.0, "repeats": 2},
}


def calib35_settings(n: int = 24):
    """A thirty-fifth effect-free set (issues #30, #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops (the position PID without feedforward in
    every fourth row) x the three sensor sets, on three plants no earlier set used (BONEY, TUBBY,
    CHONKY), 210-840 Hz, torque noise 0.058-0.07 N*m, white in half the rows and AR(1) of coefficient
    0.6 or 0.7 in the other half, velocity noise 0.0036-0.0046 deg/s, quantisation 0.0007-0.001 deg;
    seeds 19500 + i."""
    return _effect_free_set("calib35", CALIB35_EXCITATIONS, ["boney", "tubby", "chonky"],
                            [(True, True), (True, False), (False, True)], [210.0, 520.0, 840.0, 300.0, 680.0],
                            [0.06, 0.07, 0.058], [0.0, 0.7, 0.0, 0.6], [0.0036, 0.0046], [0.0007, 0.001],
                            19500, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=2, tn_rule=(1, 4))


def calib35v_settings():
    """calib35's third sensor set (rows 24-35 of its design: the velocity sensor alone), which its 24
    rows stop before; fixed and committed before its first run."""
    return calib35_settings(36)[24:]


# outside10: outside9's rows on calib35's plants, at excitation parameters, rates and seeds no earlier
# set used
_OUT10_RECIPES = {
    "a": ("boney", "pi", "multisine", {"amplitude": 2.3, "f0": 0.052, "f1": 1.6, "n": 12, "duration": 45.0},
          470.0, 0.06, 0.0, 0.0032, 0.0009, True, True),
    "b": ("chonky", "pid", "point_to_point", {"amplitudes": (2.9, -3.3, 3.2, -2.4, -2.5, 2.7), "move_time": 1.4,
                                            "dwell": 2.7, "repeats": 2}, 430.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("boney", "pi", "staircase", {"speeds": (0.042, 0.15, 0.68, 2.2, 5.0, 7.5), "dwell": 3.4,
                                      "transition": 0.4, "repeats": 1}, 365.0, 0.05, 0.0, 0.003, 0.001, True, True),
    "d": ("tubby", "pid", "sine_sweep", {"amplitude": 2.9, "f0": 0.052, "f1": 1.35, "duration": 46.0, "bias": 0.6},
          425.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("chonky", "pi", "multisine", {"amplitude": 2.3, "f0": 0.054, "f1": 1.5, "n": 11, "duration": 45.0},
          455.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("tubby", "pid", "point_to_point", {"amplitudes": (-2.8, 3.3, -3.0, 2.6, 3.4, -3.1), "move_time": 1.4,
                                           "dwell": 2.7, "repeats": 2}, 370.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("chonky", "pid_nff", "point_to_point", {"amplitudes": (3.1, -3.5, 2.8, -3.1, 2.2, 1.8), "move_time": 1.5,
                                                "dwell": 2.6, "repeats": 2}, 335.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("boney", "pi", "staircase", {"speeds": (0.05, 0.15, 0.6, 2.1, 4.5), "dwell": 4.0, "transition": 0.4,
                                      "repeats": 1}, 290.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside10_settings():
    """A tenth outside set (issue #31), fixed and committed before its first run: outside9's rows (the
    four effects outside the candidates, two recordings each, the lag a 1.4 ms) on BONEY, TUBBY and
    CHONKY, at excitation parameters, rates and seeds (19600 + k) no earlier set used."""
    return _outside_set("outside10_", OUTSIDE9_ROWS, _OUT10_RECIPES, 19600)


_F33_FS = {"a": 330.0, "b": 410.0, "c": 295.0, "d": 500.0, "e": 355.0, "f": 390.0, "g": 345.0, "h": 300.0,
           "i": 420.0}
_F33_VARIED = _varied(-0.5, 1.08, -2.2)


def fresh33_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 295-500 Hz (by recipe), seeds 19700 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh33", _F33_FS, _F33_VARIED, 19700)


# calib36 and fresh34: the held-out error reported and tested cross-validated over the block phases,
# with no separate rule on the fixed phase (issue #30); three plants no earlier set used
PETITE = T.Plant(J=0.11, Fc=0.7, Fs=1.02, vs=0.044, sigma2=1.1, sigma0=190.0, sigma1=1.2)
BRICKY = T.Plant(J=0.2, Fc=0.95, Fs=1.38, vs=0.052, sigma2=1.35, sigma0=235.0, sigma1=1.6)
ROTUNDA = T.Plant(J=0.32, Fc=1.35, Fs=1.85, vs=0.063, sigma2=1.6, sigma0=280.0, sigma1=2.2)
_add_plants({"petite": (PETITE, T.VelocityPIController(kp=5.0, ki=30.0)),
             "bricky": (BRICKY, T.VelocityPIController(kp=10.0, ki=60.0)),
             "rotunda": (ROTUNDA, T.VelocityPIController(kp=19.0, ki=112.0))},
            {"petite": PidTuning(3.2, 0.002),
             "bricky": PidTuning(2.95, 0.003),
             "rotunda": PidTuning(2.7, 0.004)})

CALIB36_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.05, 0.18, 0.7, 1.9, 3.8), "dwell": 2.8 if i % 2 else 3.2,
                            "transition": 0.28, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.05, "f1": 1.55, "duration": 35.0,
                             "bias": 0.5 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.6 * (i % 2), "f0": 0.051, "f1": 1.15 + 0.35 * (i % 3),
                            "n": 12 + 2 * (i % 2), "duration": 35.0},
    "position_sine": lambda i: {"amplitude": 2.4 + 2.3 * (i % 3), "frequency": 0.16 + 0.05 * (i % 2),
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (2.5, -2.2, 2.1, -2.4, 1.6) if i % 2 else (-2.4, 2.2, -2.6, 2.0, -1.9, 1.7),
                                 "move_time": 1.2 + 0.45 * (i % 2), "dwell": 2.4, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.06, 0.22, 0.7, 1.8, 3.6), "dwell": 2.4, "transition": 0.0, "repeats": 2},
}


def calib36_settings(n: int = 24):
    """A thirty-sixth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds with other parameters x both loops (the position PID without feedforward in
    every fourth row), the position sensor alone in rows 0-11 and the velocity sensor alone in rows
    12-23, on three plants no earlier set used (PETITE, BRICKY, ROTUNDA), 240-760 Hz, torque noise
    0.055-0.075 N*m, white in half the rows and AR(1) of coefficient 0.5 or 0.75 in the other half,
    velocity noise 0.0034-0.0044 deg/s, quantisation 0.0008-0.0011 deg; seeds 19900 + i."""
    return _effect_free_set("calib36", CALIB36_EXCITATIONS, ["petite", "bricky", "rotunda"],
                            [(True, False), (False, True), (True, True)], [240.0, 610.0, 380.0, 760.0, 450.0],
                            [0.065, 0.055, 0.075], [0.0, 0.5, 0.0, 0.75], [0.0034, 0.0044], [0.0008, 0.0011],
                            19900, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=3, tn_rule=(2, 4))


_F34_FS = {"a": 360.0, "b": 285.0, "c": 440.0, "d": 310.0, "e": 475.0, "f": 335.0, "g": 405.0, "h": 370.0,
           "i": 320.0}
_F34_VARIED = _varied(1.6, 0.92, 2.6)


def fresh34_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 285-475 Hz (by recipe), seeds 19800 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh34", _F34_FS, _F34_VARIED, 19800)


# outside11: outside10's rows on calib36's plants, at excitation parameters, rates and seeds no earlier
# set used
_OUT11_RECIPES = {
    "a": ("petite", "pi", "multisine", {"amplitude": 2.2, "f0": 0.053, "f1": 1.55, "n": 13, "duration": 44.0},
          445.0, 0.06, 0.0, 0.0034, 0.0009, True, True),
    "b": ("rotunda", "pid", "point_to_point", {"amplitudes": (3.1, -2.9, 3.4, -2.6, -2.3, 2.5), "move_time": 1.45,
                                             "dwell": 2.6, "repeats": 2}, 455.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("petite", "pi", "staircase", {"speeds": (0.045, 0.16, 0.72, 2.3, 5.2, 7.8), "dwell": 3.3,
                                       "transition": 0.38, "repeats": 1}, 380.0, 0.05, 0.0, 0.003, 0.001, True, True),
    "d": ("bricky", "pid", "sine_sweep", {"amplitude": 2.7, "f0": 0.05, "f1": 1.4, "duration": 45.0, "bias": 0.55},
          410.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("rotunda", "pi", "multisine", {"amplitude": 2.4, "f0": 0.052, "f1": 1.45, "n": 12, "duration": 44.0},
          470.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("bricky", "pid", "point_to_point", {"amplitudes": (-3.0, 3.1, -2.8, 2.7, 3.2, -3.3), "move_time": 1.35,
                                            "dwell": 2.8, "repeats": 2}, 355.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("rotunda", "pid_nff", "point_to_point", {"amplitudes": (3.3, -3.2, 2.9, -3.4, 2.1, 1.9), "move_time": 1.55,
                                                 "dwell": 2.5, "repeats": 2}, 320.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("petite", "pi", "staircase", {"speeds": (0.055, 0.16, 0.62, 2.0, 4.3), "dwell": 3.9, "transition": 0.42,
                                       "repeats": 1}, 305.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside11_settings():
    """An eleventh outside set (issue #31), fixed and committed before its first run: outside10's rows
    (the four effects outside the candidates, two recordings each, the lag a 1.4 ms) on PETITE, BRICKY
    and ROTUNDA, at excitation parameters, rates and seeds (20000 + k) no earlier set used."""
    return _outside_set("outside11_", OUTSIDE9_ROWS, _OUT11_RECIPES, 20000)


# calib37, outside12 and fresh35: the attribution held out over the block phases as the selection's
# test (issue #31); three plants no earlier set used
KNOBBY = T.Plant(J=0.13, Fc=0.76, Fs=1.1, vs=0.047, sigma2=1.15, sigma0=205.0, sigma1=1.3)
LUMPY = T.Plant(J=0.23, Fc=1.05, Fs=1.46, vs=0.055, sigma2=1.4, sigma0=245.0, sigma1=1.7)
SLIGHT = T.Plant(J=0.09, Fc=0.62, Fs=0.94, vs=0.041, sigma2=1.02, sigma0=180.0, sigma1=1.05)
_add_plants({"knobby": (KNOBBY, T.VelocityPIController(kp=6.0, ki=35.0)),
             "lumpy": (LUMPY, T.VelocityPIController(kp=12.0, ki=72.0)),
             "slight": (SLIGHT, T.VelocityPIController(kp=4.2, ki=25.0))},
            {"knobby": PidTuning(3.1, 0.002),
             "lumpy": PidTuning(2.9, 0.003),
             "slight": PidTuning(3.3, 0.002)})

CALIB37_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.047, 0.17, 0.66, 1.75, 3.6), "dwell": 2.9 if i % 2 else 3.3,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.1 + 0.4 * (i % 3), "f0": 0.051, "f1": 1.5, "duration": 34.0,
                             "bias": 0.6 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.5 * (i % 2), "f0": 0.052, "f1": 1.1 + 0.3 * (i % 3),
                            "n": 11 + 2 * (i % 2), "duration": 34.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.0 * (i % 3), "frequency": 0.15 + 0.06 * (i % 2),
                                "duration": 32.0},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.4, 2.6, -2.1, 1.7) if i % 2 else (-2.3, 2.4, -2.2, 2.1, -1.8, 1.6),
                                 "move_time": 1.25 + 0.4 * (i % 2), "dwell": 2.3, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.058, 0.21, 0.68, 1.75, 3.7), "dwell": 2.3, "transition": 0.0, "repeats": 2},
}


def calib37_settings(n: int = 24):
    """A thirty-seventh effect-free set (issue #31), fixed and committed before its first run: the
    six excitation kinds with other parameters x both loops (the position PID without feedforward in
    every fourth row), position and velocity sensors in rows 0-11 and the velocity sensor alone in
    rows 12-23, on three plants no earlier set used (KNOBBY, LUMPY, SLIGHT), 230-790 Hz, torque
    noise 0.05-0.07 N*m, white in half the rows and AR(1) of coefficient 0.55 or 0.7 in the other
    half, velocity noise 0.0032-0.0042 deg/s, quantisation 0.0007-0.001 deg; seeds 20100 + i."""
    return _effect_free_set("calib37", CALIB37_EXCITATIONS, ["knobby", "lumpy", "slight"],
                            [(True, True), (False, True), (True, False)], [230.0, 590.0, 350.0, 790.0, 470.0],
                            [0.06, 0.05, 0.07], [0.0, 0.55, 0.0, 0.7], [0.0032, 0.0042], [0.0007, 0.001],
                            20100, n, loops=("pi", "pid"), nff=2, plant_k=2, fs_k=1, tn_rule=(1, 3))


_OUT12_RECIPES = {
    "a": ("knobby", "pi", "multisine", {"amplitude": 2.3, "f0": 0.051, "f1": 1.5, "n": 12, "duration": 43.0},
          460.0, 0.06, 0.0, 0.0033, 0.0009, True, True),
    "b": ("lumpy", "pid", "point_to_point", {"amplitudes": (3.0, -3.1, 3.3, -2.7, -2.4, 2.6), "move_time": 1.4,
                                           "dwell": 2.65, "repeats": 2}, 440.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("slight", "pi", "staircase", {"speeds": (0.043, 0.155, 0.7, 2.25, 5.1, 7.6), "dwell": 3.35,
                                       "transition": 0.39, "repeats": 1}, 370.0, 0.05, 0.0, 0.003, 0.001, True, True),
    "d": ("lumpy", "pid", "sine_sweep", {"amplitude": 2.8, "f0": 0.051, "f1": 1.38, "duration": 45.5, "bias": 0.58},
          415.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("knobby", "pi", "multisine", {"amplitude": 2.35, "f0": 0.053, "f1": 1.48, "n": 11, "duration": 44.5},
          465.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("lumpy", "pid", "point_to_point", {"amplitudes": (-2.9, 3.2, -2.9, 2.65, 3.3, -3.2), "move_time": 1.38,
                                           "dwell": 2.75, "repeats": 2}, 360.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("knobby", "pid_nff", "point_to_point", {"amplitudes": (3.2, -3.3, 2.85, -3.25, 2.15, 1.85), "move_time": 1.52,
                                                "dwell": 2.55, "repeats": 2}, 325.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("slight", "pi", "staircase", {"speeds": (0.052, 0.155, 0.61, 2.05, 4.4), "dwell": 3.95, "transition": 0.41,
                                       "repeats": 1}, 298.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside12_settings():
    """A twelfth outside set (issue #31), fixed and committed before its first run: outside10's rows
    (the four effects outside the candidates, two recordings each, the lag a 1.4 ms) on KNOBBY, LUMPY
    and SLIGHT, at excitation parameters, rates and seeds (20200 + k) no earlier set used."""
    return _outside_set("outside12_", OUTSIDE9_ROWS, _OUT12_RECIPES, 20200)


_F35_FS = {"a": 345.0, "b": 395.0, "c": 305.0, "d": 460.0, "e": 325.0, "f": 415.0, "g": 355.0, "h": 290.0,
           "i": 385.0}
_F35_VARIED = _varied(-1.3, 1.12, 1.7)


def fresh35_settings():
    """A fresh set (issues #30, #31), fixed and committed before its first run: fresh3's effect rows
    k with k odd (12 rows, every effect), at 290-460 Hz (by recipe), seeds 20300 + k, with the
    gravity's phase, the asymmetry's sign and the ripple's period and phase changed."""
    return [r for k, r in enumerate(_refreshed("fresh35", _F35_FS, _F35_VARIED, 20300)) if k % 2 == 1]


# calib38, outside13 and fresh36: the block phases drawn at random within each run of five blocks
# (an excitation periodic in whole blocks no longer puts its events in one phase; issue #30); three
# plants no earlier set used
SKINNY = T.Plant(J=0.085, Fc=0.58, Fs=0.9, vs=0.039, sigma2=0.98, sigma0=175.0, sigma1=1.0)
PUDGY = T.Plant(J=0.27, Fc=1.2, Fs=1.62, vs=0.058, sigma2=1.5, sigma0=262.0, sigma1=1.95)
BOXY = T.Plant(J=0.16, Fc=0.86, Fs=1.24, vs=0.05, sigma2=1.25, sigma0=222.0, sigma1=1.45)
_add_plants({"skinny": (SKINNY, T.VelocityPIController(kp=4.0, ki=24.0)),
             "pudgy": (PUDGY, T.VelocityPIController(kp=14.0, ki=84.0)),
             "boxy": (BOXY, T.VelocityPIController(kp=8.0, ki=48.0))},
            {"skinny": PidTuning(3.4, 0.002),
             "pudgy": PidTuning(2.8, 0.004),
             "boxy": PidTuning(3.0, 0.003)})

CALIB38_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.052, 0.19, 0.64, 1.85, 3.9), "dwell": 3.0 if i % 2 else 2.5,
                            "transition": 0.25, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.0 + 0.45 * (i % 3), "f0": 0.05, "f1": 1.45, "duration": 36.0,
                             "bias": 0.55 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.55 * (i % 2), "f0": 0.05, "f1": 1.2 + 0.3 * (i % 3),
                            "n": 12 + (i % 2), "duration": 36.0},
    "position_sine": lambda i: {"amplitude": 2.5 + 2.2 * (i % 3), "frequency": 0.2 if i % 2 else 0.1,
                                "duration": 35.0},
    "point_to_point": lambda i: {"amplitudes": (2.4, -2.3, 2.5, -2.2, 1.8) if i % 2 else (-2.2, 2.5, -2.3, 2.2, -1.7, 1.9),
                                 "move_time": 1.0 if i % 2 else 1.5, "dwell": 1.5 if i % 2 else 2.5, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.055, 0.2, 0.72, 1.7, 3.5), "dwell": 2.0 if i % 2 else 2.5,
                              "transition": 0.0, "repeats": 2},
}


def calib38_settings(n: int = 24):
    """A thirty-eighth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds x both loops (the position PID without feedforward in every fourth row), with
    periods of whole seconds in half the point-to-point, position-sine and step rows, the velocity
    sensor alone in rows 0-11 and both sensors in rows 12-23, on three plants no earlier set used
    (SKINNY, PUDGY, BOXY), 260-720 Hz, torque noise 0.05-0.07 N*m, white in half the rows and AR(1)
    of coefficient 0.6 or 0.8 in the other half, velocity noise 0.0033-0.0043 deg/s, quantisation
    0.0008-0.0012 deg; seeds 20400 + i."""
    return _effect_free_set("calib38", CALIB38_EXCITATIONS, ["skinny", "pudgy", "boxy"],
                            [(False, True), (True, True), (True, False)], [260.0, 540.0, 330.0, 720.0, 430.0],
                            [0.055, 0.07, 0.05], [0.0, 0.6, 0.0, 0.8], [0.0033, 0.0043], [0.0008, 0.0012],
                            20400, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(2, 3))


_OUT13_RECIPES = {
    "a": ("skinny", "pi", "multisine", {"amplitude": 2.25, "f0": 0.052, "f1": 1.52, "n": 12, "duration": 42.0},
          450.0, 0.06, 0.0, 0.0033, 0.0009, True, True),
    "b": ("pudgy", "pid", "point_to_point", {"amplitudes": (3.1, -3.0, 3.2, -2.8, -2.5, 2.7), "move_time": 1.5,
                                           "dwell": 2.5, "repeats": 2}, 430.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "c": ("boxy", "pi", "staircase", {"speeds": (0.044, 0.16, 0.68, 2.2, 5.0, 7.7), "dwell": 3.0,
                                     "transition": 0.4, "repeats": 1}, 375.0, 0.05, 0.0, 0.003, 0.001, True, True),
    "d": ("pudgy", "pid", "sine_sweep", {"amplitude": 2.75, "f0": 0.05, "f1": 1.4, "duration": 46.0, "bias": 0.6},
          420.0, 0.06, 0.45, 0.0, 0.0009, True, False),
    "e": ("skinny", "pi", "multisine", {"amplitude": 2.3, "f0": 0.051, "f1": 1.46, "n": 12, "duration": 44.0},
          470.0, 0.085, 0.0, 0.004, 0.0, False, True),
    "f": ("pudgy", "pid", "point_to_point", {"amplitudes": (-3.0, 3.1, -2.8, 2.7, 3.2, -3.1), "move_time": 1.0,
                                           "dwell": 2.0, "repeats": 2}, 365.0, 0.06, 0.0, 0.0, 0.0009, True, False),
    "g": ("boxy", "pid_nff", "point_to_point", {"amplitudes": (3.25, -3.3, 2.9, -3.2, 2.2, 1.9), "move_time": 1.5,
                                              "dwell": 2.5, "repeats": 2}, 330.0, 0.085, 0.0, 0.004, 0.0009, True, True),
    "h": ("skinny", "pi", "staircase", {"speeds": (0.05, 0.16, 0.6, 2.0, 4.3), "dwell": 4.0, "transition": 0.4,
                                       "repeats": 1}, 305.0, 0.05, 0.45, 0.003, 0.0009, True, True),
}


def outside13_settings():
    """A thirteenth outside set (issue #31), fixed and committed before its first run: outside10's rows
    (the four effects outside the candidates, two recordings each, the lag a 1.4 ms) on SKINNY, PUDGY
    and BOXY, at excitation parameters, rates and seeds (20500 + k) no earlier set used."""
    return _outside_set("outside13_", OUTSIDE9_ROWS, _OUT13_RECIPES, 20500)


_F36_FS = {"a": 350.0, "b": 300.0, "c": 455.0, "d": 325.0, "e": 480.0, "f": 340.0, "g": 395.0, "h": 360.0,
           "i": 310.0}
_F36_VARIED = _varied(0.7, 0.95, -1.1)


def fresh36_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 300-480 Hz (by recipe), seeds 20600 + k, with the gravity's phase, the asymmetry's sign
    and the ripple's period and phase changed."""
    return _refreshed("fresh36", _F36_FS, _F36_VARIED, 20600)


# calib39: a second effect-free set for the drawn block phases (issue #30); three plants no earlier set used
WOBBLY = T.Plant(J=0.1, Fc=0.66, Fs=0.98, vs=0.043, sigma2=1.08, sigma0=192.0, sigma1=1.15)
STUBBY = T.Plant(J=0.3, Fc=1.28, Fs=1.75, vs=0.061, sigma2=1.55, sigma0=270.0, sigma1=2.05)
KNOTTY = T.Plant(J=0.18, Fc=0.92, Fs=1.32, vs=0.052, sigma2=1.3, sigma0=230.0, sigma1=1.55)
_add_plants({"wobbly": (WOBBLY, T.VelocityPIController(kp=4.6, ki=28.0)),
             "stubby": (STUBBY, T.VelocityPIController(kp=16.0, ki=95.0)),
             "knotty": (KNOTTY, T.VelocityPIController(kp=9.0, ki=54.0))},
            {"wobbly": PidTuning(3.3, 0.002),
             "stubby": PidTuning(2.75, 0.004),
             "knotty": PidTuning(2.95, 0.003)})

CALIB39_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.05, 0.18, 0.66, 1.8, 3.7), "dwell": 2.0 if i % 2 else 3.5,
                            "transition": 0.27, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.2 + 0.35 * (i % 3), "f0": 0.052, "f1": 1.4, "duration": 37.0,
                             "bias": 0.5 + 0.35 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.6 * (i % 2), "f0": 0.05, "f1": 1.15 + 0.35 * (i % 3),
                            "n": 11 + (i % 2), "duration": 37.0},
    "position_sine": lambda i: {"amplitude": 2.8 + 2.1 * (i % 3), "frequency": 0.25 if i % 2 else 0.125,
                                "duration": 34.0},
    "point_to_point": lambda i: {"amplitudes": (2.3, -2.5, 2.4, -2.1, 1.9) if i % 2 else (-2.4, 2.3, -2.5, 2.0, -1.8, 2.1),
                                 "move_time": 1.0 if i % 2 else 2.0, "dwell": 2.0 if i % 2 else 3.0, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.052, 0.19, 0.7, 1.75, 3.6), "dwell": 3.0 if i % 2 else 2.0,
                              "transition": 0.0, "repeats": 2},
}


def calib39_settings(n: int = 24):
    """A thirty-ninth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds x both loops (the position PID without feedforward in every fourth row), with
    periods of whole seconds in the point-to-point, position-sine and step rows, the position sensor
    alone in rows 0-11 and both sensors in rows 12-23, on three plants no earlier set used (WOBBLY,
    STUBBY, KNOTTY), 250-700 Hz, torque noise 0.05-0.075 N*m, white in half the rows and AR(1) of
    coefficient 0.5 or 0.75 in the other half, velocity noise 0.0035-0.0045 deg/s, quantisation
    0.0007-0.0011 deg; seeds 20700 + i."""
    return _effect_free_set("calib39", CALIB39_EXCITATIONS, ["wobbly", "stubby", "knotty"],
                            [(True, False), (True, True), (False, True)], [250.0, 520.0, 360.0, 700.0, 440.0],
                            [0.06, 0.075, 0.05], [0.0, 0.5, 0.0, 0.75], [0.0035, 0.0045], [0.0007, 0.0011],
                            20700, n, loops=("pi", "pid"), nff=2, plant_k=2, fs_k=3, tn_rule=(1, 4))


# fresh37, outside14 and calib40: the design as of da52481, frozen before their first run; fresh37's
# variations and rates are drawn (numpy default_rng(37) and (3714)), not chosen; three plants no
# earlier set used
_F37_FS = {"a": 450.0, "b": 280.0, "c": 370.0, "d": 410.0, "e": 315.0, "f": 380.0, "g": 425.0, "h": 370.0,
           "i": 335.0}
_F37_VARIED = _varied(1.2827, 1.0978, -2.7081)


def fresh37_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 280-450 Hz (by recipe, drawn), seeds 20800 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh37", _F37_FS, _F37_VARIED, 20800)


GRITTY = T.Plant(J=0.11, Fc=0.7, Fs=1.05, vs=0.046, sigma2=1.1, sigma0=198.0, sigma1=1.2)
SPRIGHTLY = T.Plant(J=0.075, Fc=0.52, Fs=0.8, vs=0.036, sigma2=0.9, sigma0=160.0, sigma1=0.9)
STOLID = T.Plant(J=0.24, Fc=1.1, Fs=1.55, vs=0.056, sigma2=1.45, sigma0=250.0, sigma1=1.85)
_add_plants({"gritty": (GRITTY, T.VelocityPIController(kp=5.2, ki=31.0)),
             "sprightly": (SPRIGHTLY, T.VelocityPIController(kp=3.6, ki=22.0)),
             "stolid": (STOLID, T.VelocityPIController(kp=12.5, ki=75.0))},
            {"gritty": PidTuning(3.2, 0.002),
             "sprightly": PidTuning(3.5, 0.002),
             "stolid": PidTuning(2.85, 0.004)})

_OUT14_RECIPES = {
    "a": ("gritty", "pi", "multisine", {"amplitude": 2.35, "f0": 0.05, "f1": 1.48, "n": 11, "duration": 43.0},
          410.0, 0.06, 0.0, 0.0035, 0.0008, True, True),
    "b": ("stolid", "pid", "point_to_point", {"amplitudes": (2.9, -3.2, 3.0, -2.6, -2.7, 2.9), "move_time": 1.4,
                                            "dwell": 2.3, "repeats": 2}, 455.0, 0.08, 0.0, 0.0042, 0.001, True, True),
    "c": ("sprightly", "pi", "staircase", {"speeds": (0.046, 0.17, 0.7, 2.1, 4.8, 7.4), "dwell": 3.2,
                                          "transition": 0.35, "repeats": 1}, 345.0, 0.05, 0.0, 0.0032, 0.0011, True,
          True),
    "d": ("stolid", "pid", "sine_sweep", {"amplitude": 2.6, "f0": 0.052, "f1": 1.35, "duration": 47.0, "bias": 0.65},
          395.0, 0.065, 0.4, 0.0, 0.001, True, False),
    "e": ("gritty", "pi", "multisine", {"amplitude": 2.4, "f0": 0.049, "f1": 1.5, "n": 13, "duration": 45.0},
          440.0, 0.08, 0.0, 0.0038, 0.0, False, True),
    "f": ("stolid", "pid", "point_to_point", {"amplitudes": (-2.9, 3.0, -3.1, 2.8, 3.1, -2.9), "move_time": 1.1,
                                            "dwell": 2.1, "repeats": 2}, 385.0, 0.06, 0.0, 0.0, 0.001, True, False),
    "g": ("sprightly", "pid_nff", "point_to_point", {"amplitudes": (3.1, -3.2, 3.0, -3.3, 2.1, 2.0),
                                                   "move_time": 1.6, "dwell": 2.4, "repeats": 2},
          350.0, 0.08, 0.0, 0.0038, 0.0008, True, True),
    "h": ("gritty", "pi", "staircase", {"speeds": (0.048, 0.15, 0.62, 2.1, 4.1), "dwell": 3.8, "transition": 0.35,
                                       "repeats": 1}, 320.0, 0.055, 0.4, 0.0032, 0.0008, True, True),
}


def outside14_settings():
    """A fourteenth outside set (issue #31), fixed and committed before its first run: outside13's rows
    (the four effects outside the candidates, two recordings each) on GRITTY, SPRIGHTLY and STOLID,
    at excitation parameters, rates and seeds (20900 + k) no earlier set used."""
    return _outside_set("outside14_", OUTSIDE9_ROWS, _OUT14_RECIPES, 20900)


CALIB40_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.048, 0.17, 0.62, 1.9, 3.8), "dwell": 2.8 if i % 2 else 2.2,
                            "transition": 0.3, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 2.1 + 0.4 * (i % 3), "f0": 0.048, "f1": 1.5, "duration": 38.0,
                             "bias": 0.6 + 0.25 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.2 + 0.5 * (i % 2), "f0": 0.05, "f1": 1.25 + 0.25 * (i % 3),
                            "n": 12 + (i % 2), "duration": 38.0},
    "position_sine": lambda i: {"amplitude": 2.6 + 2.4 * (i % 3), "frequency": 0.15 if i % 2 else 0.22,
                                "duration": 36.0},
    "point_to_point": lambda i: {"amplitudes": (2.2, -2.4, 2.6, -2.0, 1.7) if i % 2 else (-2.3, 2.4, -2.1, 2.5, -1.9, 2.0),
                                 "move_time": 1.2 if i % 2 else 1.8, "dwell": 1.8 if i % 2 else 2.7, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.05, 0.21, 0.68, 1.8, 3.4), "dwell": 2.4 if i % 2 else 1.9,
                              "transition": 0.0, "repeats": 2},
}


def calib40_settings(n: int = 24):
    """A fortieth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds x both loops (the position PID without feedforward in every fourth row), both
    sensors in rows 0-11, the position sensor alone in rows 12-23 (and the velocity sensor alone in
    none: calib38 covers it), on three plants no earlier set used (GRITTY, SPRIGHTLY, STOLID),
    280-760 Hz, torque noise 0.055-0.08 N*m, white in half the rows and AR(1) of coefficient 0.7 or
    0.55 in the other half, velocity noise 0.003-0.005 deg/s, quantisation 0.0006-0.001 deg; seeds
    21000 + i."""
    return _effect_free_set("calib40", CALIB40_EXCITATIONS, ["gritty", "sprightly", "stolid"],
                            [(True, True), (True, False), (False, True)], [280.0, 610.0, 390.0, 760.0, 470.0],
                            [0.055, 0.065, 0.08], [0.0, 0.7, 0.0, 0.55], [0.003, 0.005], [0.0006, 0.001],
                            21000, n, loops=("pid", "pi"), nff=1, plant_k=2, fs_k=3, tn_rule=(1, 3))


# fresh38, outside15 and calib41: the design as of d59c6ef, frozen before their first run; fresh38's
# and outside15's rates and fresh38's variations are drawn (numpy default_rng(38), (3814) and
# (4115)), not chosen; calib41 reaches past the rates, noise levels, colours and sensor steps of the
# sets before it (120-1,500 Hz, 0.025-0.16 N*m, AR(1) up to 0.85); three plants no earlier set used
_F38_FS = {"a": 540.0, "b": 375.0, "c": 705.0, "d": 645.0, "e": 855.0, "f": 230.0, "g": 785.0, "h": 550.0,
           "i": 505.0}
_F38_VARIED = _varied(1.3559, 0.9138, -0.1365)


def fresh38_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows, at 230-855 Hz (by recipe, drawn), seeds 21300 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh38", _F38_FS, _F38_VARIED, 21300)


PLUCKY = T.Plant(J=0.045, Fc=0.42, Fs=0.66, vs=0.03, sigma2=0.7, sigma0=140.0, sigma1=0.7)
FLEET = T.Plant(J=0.13, Fc=0.85, Fs=1.3, vs=0.05, sigma2=1.2, sigma0=210.0, sigma1=1.4)
DOUR = T.Plant(J=0.2, Fc=1.3, Fs=1.7, vs=0.07, sigma2=1.6, sigma0=260.0, sigma1=2.2)
_add_plants({"plucky": (PLUCKY, T.VelocityPIController(kp=2.2, ki=13.0)),
             "fleet": (FLEET, T.VelocityPIController(kp=6.5, ki=39.0)),
             "dour": (DOUR, T.VelocityPIController(kp=10.0, ki=60.0))},
            {"plucky": PidTuning(3.6, 0.002),
             "fleet": PidTuning(3.1, 0.003),
             "dour": PidTuning(2.9, 0.004)})

def _outside14_on(plants: dict, fs: tuple) -> dict:
    """outside14's recipes with each of its plants replaced (``plants``: its plant -> another) and the
    rows' rates ``fs`` (rows a-h)."""
    rates = dict(zip("abcdefgh", fs))
    return {k: (plants[r[0]],) + r[1:4] + (rates[k],) + r[5:] for k, r in _OUT14_RECIPES.items()}


_OUT15_RECIPES = _outside14_on({"gritty": "plucky", "sprightly": "fleet", "stolid": "dour"},
                               (755.0, 390.0, 540.0, 490.0, 575.0, 770.0, 210.0, 520.0))


def outside15_settings():
    """A fifteenth outside set (issue #31), fixed and committed before its first run: outside14's rows
    and excitations on PLUCKY, FLEET and DOUR, at drawn rates (210-770 Hz) and seeds 21500 + k."""
    return _outside_set("outside15_", OUTSIDE9_ROWS, _OUT15_RECIPES, 21500)


CALIB41_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.03, 0.11, 0.45, 1.6, 4.4), "dwell": 2.6 if i % 2 else 3.1,
                            "transition": 0.25, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.8 + 0.6 * (i % 3), "f0": 0.06, "f1": 1.9, "duration": 34.0,
                             "bias": 0.45 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.0 + 0.7 * (i % 2), "f0": 0.045, "f1": 1.1 + 0.35 * (i % 3),
                            "n": 10 + (i % 3), "duration": 36.0},
    "position_sine": lambda i: {"amplitude": 1.8 + 3.1 * (i % 3), "frequency": 0.18 if i % 2 else 0.27,
                                "duration": 33.0},
    "point_to_point": lambda i: {"amplitudes": (1.9, -2.7, 2.2, -1.6, 2.4) if i % 2 else (-2.6, 1.8, -2.2, 2.9, -1.7),
                                 "move_time": 0.9 if i % 2 else 1.5, "dwell": 2.0 if i % 2 else 1.4, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.04, 0.18, 0.75, 2.2, 4.1), "dwell": 2.1 if i % 2 else 1.7,
                              "transition": 0.0, "repeats": 2},
}


def calib41_settings(n: int = 24):
    """A forty-first effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds x both loops (the position PID without feedforward in every fourth row), the
    velocity sensor alone in rows 0-11 and both sensors in rows 12-23, on PLUCKY, FLEET and DOUR,
    at rates, noise levels and sensor steps past those of the sets before it: 120-1,500 Hz, torque
    noise 0.025-0.16 N*m, white in half the rows and AR(1) of coefficient 0.85 or 0.35 in the
    other half, velocity noise 0.0015 or 0.009 deg/s, quantisation 0.0003 or 0.0025 deg; seeds
    21400 + i."""
    return _effect_free_set("calib41", CALIB41_EXCITATIONS, ["plucky", "fleet", "dour"],
                            [(False, True), (True, True), (True, False)], [120.0, 1500.0, 170.0, 1100.0, 650.0],
                            [0.025, 0.16, 0.09], [0.0, 0.85, 0.0, 0.35], [0.0015, 0.009], [0.0003, 0.0025],
                            21400, n, loops=("pi", "pid"), nff=3, plant_k=1, fs_k=2, tn_rule=(2, 5))


# calib42: for the floor's torque noise capped by the baseline's residual (run on bd1d8f2, two commits
# after these settings); strongly coloured noise at low rates, where the noise profile reads high;
# three plants no earlier set used
ELFIN = T.Plant(J=0.07, Fc=0.6, Fs=0.95, vs=0.042, sigma2=0.85, sigma0=175.0, sigma1=1.0)
RUGGED = T.Plant(J=0.17, Fc=1.05, Fs=1.45, vs=0.06, sigma2=1.35, sigma0=230.0, sigma1=1.7)
FRAIL = T.Plant(J=0.095, Fc=0.75, Fs=1.2, vs=0.038, sigma2=1.0, sigma0=190.0, sigma1=1.15)
_add_plants({"elfin": (ELFIN, T.VelocityPIController(kp=3.5, ki=21.0)),
             "rugged": (RUGGED, T.VelocityPIController(kp=8.5, ki=51.0)),
             "frail": (FRAIL, T.VelocityPIController(kp=4.8, ki=29.0))},
            {"elfin": PidTuning(3.4, 0.002),
             "rugged": PidTuning(3.0, 0.004),
             "frail": PidTuning(3.3, 0.003)})

CALIB42_EXCITATIONS = {
    "staircase": lambda i: {"speeds": (0.035, 0.13, 0.5, 1.7, 3.9), "dwell": 2.9 if i % 2 else 2.4,
                            "transition": 0.35, "repeats": 1},
    "sine_sweep": lambda i: {"amplitude": 1.9 + 0.5 * (i % 3), "f0": 0.055, "f1": 1.6, "duration": 40.0,
                             "bias": 0.5 + 0.3 * (i % 2)},
    "multisine": lambda i: {"amplitude": 2.1 + 0.6 * (i % 2), "f0": 0.05, "f1": 1.15 + 0.3 * (i % 3),
                            "n": 11 + (i % 2), "duration": 40.0},
    "position_sine": lambda i: {"amplitude": 2.2 + 2.8 * (i % 3), "frequency": 0.2 if i % 2 else 0.13,
                                "duration": 38.0},
    "point_to_point": lambda i: {"amplitudes": (2.4, -2.1, 1.8, -2.6, 2.0) if i % 2 else (-2.0, 2.5, -1.9, 2.2, -2.4),
                                 "move_time": 1.3 if i % 2 else 1.0, "dwell": 2.2 if i % 2 else 1.6, "repeats": 2},
    "sharp_steps": lambda i: {"speeds": (0.045, 0.16, 0.7, 2.0, 3.7), "dwell": 2.3 if i % 2 else 1.8,
                              "transition": 0.0, "repeats": 2},
}


def calib42_settings(n: int = 24):
    """A forty-second effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds x both loops (the position PID without feedforward in every fourth row), both
    sensors in rows 0-11, the position sensor alone in 12-23 (the velocity sensor alone in none), on ELFIN,
    RUGGED and FRAIL, at 100-260 Hz with AR(1) torque noise in every row (coefficient 0.6, 0.75, 0.85
    or 0.9), torque noise 0.04-0.1 N*m, velocity noise 0.002 or 0.006 deg/s, quantisation 0.0004 or
    0.0015 deg; seeds 21600 + i."""
    return _effect_free_set("calib42", CALIB42_EXCITATIONS, ["elfin", "rugged", "frail"],
                            [(True, True), (True, False), (False, True)], [100.0, 200.0, 130.0, 260.0, 160.0],
                            [0.04, 0.1, 0.07], [0.6, 0.85, 0.75, 0.9], [0.002, 0.006], [0.0004, 0.0015],
                            21600, n, loops=("pi", "pid"), nff=1, plant_k=2, fs_k=3, tn_rule=(1, 4))


# fresh39, outside16 and calib43: the design as of 2cbe4ce, frozen before their first run; fresh39's
# rates and variations and outside16's and calib43's rates are drawn (numpy default_rng(39), (4316)
# and (4317)), not chosen; three plants no earlier set used
DAPPER = T.Plant(J=0.06, Fc=0.5, Fs=0.82, vs=0.035, sigma2=0.75, sigma0=150.0, sigma1=0.85)
JAUNTY = T.Plant(J=0.11, Fc=0.9, Fs=1.25, vs=0.055, sigma2=1.1, sigma0=200.0, sigma1=1.3)
LIMBER = T.Plant(J=0.15, Fc=1.15, Fs=1.6, vs=0.065, sigma2=1.45, sigma0=245.0, sigma1=1.9)
_add_plants({"dapper": (DAPPER, T.VelocityPIController(kp=3.0, ki=18.0)),
             "jaunty": (JAUNTY, T.VelocityPIController(kp=5.5, ki=33.0)),
             "limber": (LIMBER, T.VelocityPIController(kp=7.5, ki=45.0))},
            {"dapper": PidTuning(3.5, 0.002),
             "jaunty": PidTuning(3.2, 0.003),
             "limber": PidTuning(3.0, 0.004)})

_F39_FS = {"a": 550.0, "b": 580.0, "c": 295.0, "d": 415.0, "e": 605.0, "f": 755.0, "g": 305.0, "h": 360.0,
           "i": 860.0}
_F39_VARIED = _varied(1.0441, 1.2705, 1.0009)


def fresh39_settings():
    """A fresh set (issues #30 and #31), fixed and committed before its first run: all 24 of fresh3's
    effect rows at 295-860 Hz (by recipe, drawn), seeds 21800 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh39", _F39_FS, _F39_VARIED, 21800)


_OUT16_RECIPES = _outside14_on({"gritty": "dapper", "sprightly": "jaunty", "stolid": "limber"},
                               (260.0, 775.0, 580.0, 555.0, 480.0, 210.0, 430.0, 340.0))


def outside16_settings():
    """A sixteenth outside set (issue #31), fixed and committed before its first run: outside14's rows
    and excitations on DAPPER, JAUNTY and LIMBER, at drawn rates (210-775 Hz) and seeds 21900 + k."""
    return _outside_set("outside16_", OUTSIDE9_ROWS, _OUT16_RECIPES, 21900)


def calib43_settings(n: int = 24):
    """A forty-third effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib41's) x both loops (the position PID without feedforward in every fourth
    row), both sensors in rows 0-11 and the velocity sensor alone in rows 12-23, on DAPPER, JAUNTY
    and LIMBER, at drawn rates 170-880 Hz, torque noise 0.03-0.12 N*m, white in half the rows and
    AR(1) of coefficient 0.5 or 0.75 in the other half, velocity noise 0.003 or 0.008 deg/s,
    quantisation 0.0005 or 0.002 deg; seeds 21700 + i."""
    return _effect_free_set("calib43", CALIB41_EXCITATIONS, ["dapper", "jaunty", "limber"],
                            [(True, True), (False, True), (True, False)], [170.0, 695.0, 740.0, 875.0, 880.0],
                            [0.03, 0.12, 0.07], [0.0, 0.5, 0.0, 0.75], [0.003, 0.008], [0.0005, 0.002],
                            21700, n, loops=("pid", "pi"), nff=2, plant_k=1, fs_k=2, tn_rule=(2, 4))


# fresh40, outside17 and calib44: the design of the residual window check (the window chosen again by
# the fitted baseline's training residual), frozen before their first run; rates and fresh40's
# variations are drawn (numpy default_rng(40), (4417) and (4418)), not chosen; three plants no
# earlier set used
SLACK = T.Plant(J=0.08, Fc=0.65, Fs=1.0, vs=0.045, sigma2=0.9, sigma0=170.0, sigma1=1.0)
RIGID = T.Plant(J=0.13, Fc=1.0, Fs=1.45, vs=0.06, sigma2=1.25, sigma0=230.0, sigma1=1.6)
MELLOW = T.Plant(J=0.05, Fc=0.42, Fs=0.7, vs=0.03, sigma2=0.6, sigma0=130.0, sigma1=0.7)
_add_plants({"slack": (SLACK, T.VelocityPIController(kp=4.0, ki=24.0)),
             "rigid": (RIGID, T.VelocityPIController(kp=6.5, ki=39.0)),
             "mellow": (MELLOW, T.VelocityPIController(kp=2.5, ki=15.0))},
            {"slack": PidTuning(3.4, 0.002),
             "rigid": PidTuning(3.1, 0.003),
             "mellow": PidTuning(3.6, 0.002)})

_F40_FS = {"a": 725.0, "b": 700.0, "c": 860.0, "d": 290.0, "e": 700.0, "f": 850.0, "g": 560.0, "h": 470.0,
           "i": 640.0}
_F40_VARIED = _varied(1.1531, 0.9005, -1.9569)


def fresh40_settings():
    """A fresh set (issues #30 and #31), fixed and committed before its first run: all 24 of fresh3's
    effect rows at 290-860 Hz (by recipe, drawn), seeds 22000 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh40", _F40_FS, _F40_VARIED, 22000)


_OUT17_RECIPES = _outside14_on({"gritty": "slack", "sprightly": "rigid", "stolid": "mellow"},
                               (445.0, 235.0, 655.0, 515.0, 475.0, 345.0, 705.0, 750.0))


def outside17_settings():
    """A seventeenth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on SLACK, RIGID and MELLOW, at drawn rates (235-750 Hz) and seeds 22200 + k."""
    return _outside_set("outside17_", OUTSIDE9_ROWS, _OUT17_RECIPES, 22200)


def calib44_settings(n: int = 24):
    """A forty-fourth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib42's) x both loops (the position PID without feedforward in every fourth
    row), the position sensor alone in rows 0-11 and the velocity sensor alone in rows 12-23, on
    SLACK, RIGID and MELLOW, at drawn rates 245-740 Hz, torque noise 0.035-0.09 N*m, white in a
    quarter of the rows and AR(1) of coefficient 0.3, 0.6 or 0.8 in the rest, velocity noise 0.0015
    or 0.004 deg/s, quantisation 0.0003 or 0.001 deg; seeds 22100 + i."""
    return _effect_free_set("calib44", CALIB42_EXCITATIONS, ["slack", "rigid", "mellow"],
                            [(True, False), (False, True), (True, True)], [245.0, 305.0, 685.0, 715.0, 740.0],
                            [0.05, 0.09, 0.035], [0.0, 0.6, 0.3, 0.8], [0.004, 0.0015], [0.001, 0.0003],
                            22100, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=3, tn_rule=(1, 3))

# calib45: the design of the held-out window confirmation (a rechosen window kept only where the
# refitted baseline predicts the held-out samples better), frozen before its first run; rates and
# torque noise drawn (numpy default_rng(4545)); three plants no earlier set used
BREEZY = T.Plant(J=0.07, Fc=0.55, Fs=0.9, vs=0.04, sigma2=0.75, sigma0=150.0, sigma1=0.9)
HALE = T.Plant(J=0.14, Fc=1.1, Fs=1.55, vs=0.055, sigma2=1.35, sigma0=250.0, sigma1=1.7)
SNUG = T.Plant(J=0.1, Fc=0.8, Fs=1.2, vs=0.05, sigma2=1.0, sigma0=190.0, sigma1=1.2)
_add_plants({"breezy": (BREEZY, T.VelocityPIController(kp=3.5, ki=21.0)),
             "hale": (HALE, T.VelocityPIController(kp=7.0, ki=42.0)),
             "snug": (SNUG, T.VelocityPIController(kp=5.0, ki=30.0))},
            {"breezy": PidTuning(3.5, 0.002),
             "hale": PidTuning(3.0, 0.003),
             "snug": PidTuning(3.3, 0.002)})


def calib45_settings(n: int = 24):
    """A forty-fifth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib42's) x both loops (the position PID without feedforward in every fourth
    row), the velocity sensor alone in rows 0-11 and both sensors in rows 12-23 (where the window
    check moves), on BREEZY, HALE and SNUG, at drawn rates 510-830 Hz and torque noise
    0.054-0.077 N*m, white in a quarter of the rows and AR(1) of coefficient 0.3, 0.5 or 0.75 in
    the rest, velocity noise 0.003 or 0.006 deg/s, quantisation 0.0005 or 0.001 deg; seeds 22300 + i."""
    return _effect_free_set("calib45", CALIB42_EXCITATIONS, ["breezy", "hale", "snug"],
                            [(False, True), (True, True), (True, False)], [560.0, 510.0, 625.0, 830.0, 645.0],
                            [0.077, 0.062, 0.054], [0.0, 0.5, 0.3, 0.75], [0.003, 0.006], [0.0005, 0.001],
                            22300, n, loops=("pid", "pi"), nff=2, plant_k=1, fs_k=2, tn_rule=(1, 4))


# fresh41: the design of the held-out window confirmation (66086ec, with b6a2490's restored
# paths), frozen before its first run; rates and variations drawn (numpy default_rng(41):
# uniform(250, 900) Hz rounded to 5, then the gravity's phase uniform(-pi, pi), the ripple's period
# factor uniform(0.8, 1.25) and its phase uniform(-pi, pi)), not chosen; fresh3's plants, so its
# rows compare with fresh34-40's
_F41_FS = {"a": 870.0, "b": 750.0, "c": 330.0, "d": 790.0, "e": 800.0, "f": 475.0, "g": 580.0, "h": 640.0,
           "i": 470.0}
_F41_VARIED = _varied(0.7653, 1.1296, 2.2688)


def fresh41_settings():
    """A fresh set (issues #30 and #31), fixed and committed before its first run: all 24 of fresh3's
    effect rows at 330-870 Hz (by recipe, drawn), seeds 22400 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh41", _F41_FS, _F41_VARIED, 22400)


# calib46: the design of best_start (a candidate's fixed starts each over their own null mean),
# frozen before its first run; rates and torque noise drawn (numpy default_rng(4646): uniform(150,
# 900) Hz rounded to 5, then uniform(0.03, 0.12) N*m), not chosen; three plants no earlier set used
DEFT = T.Plant(J=0.065, Fc=0.5, Fs=0.85, vs=0.04, sigma2=0.7, sigma0=140.0, sigma1=0.8)
PLIANT = T.Plant(J=0.12, Fc=0.95, Fs=1.35, vs=0.05, sigma2=1.15, sigma0=215.0, sigma1=1.45)
SOBER = T.Plant(J=0.09, Fc=0.7, Fs=1.1, vs=0.045, sigma2=0.95, sigma0=175.0, sigma1=1.1)
_add_plants({"deft": (DEFT, T.VelocityPIController(kp=3.2, ki=19.0)),
             "pliant": (PLIANT, T.VelocityPIController(kp=6.0, ki=36.0)),
             "sober": (SOBER, T.VelocityPIController(kp=4.5, ki=27.0))},
            {"deft": PidTuning(3.5, 0.002),
             "pliant": PidTuning(3.1, 0.003),
             "sober": PidTuning(3.3, 0.002)})


def calib46_settings(n: int = 24):
    """A forty-sixth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib41's) x both loops (the position PID without feedforward in every fourth
    row), the position sensor alone in rows 0-11 (where a Stribeck shape was named on calib38) and
    both sensors in rows 12-23, on DEFT, PLIANT and SOBER, at drawn rates 190-710 Hz and torque
    noise 0.03-0.074 N*m, white in half the rows and AR(1) of coefficient 0.4 or 0.7 in the other
    half, velocity noise 0.002 or 0.005 deg/s, quantisation 0.0004 or 0.0012 deg; seeds 22500 + i."""
    return _effect_free_set("calib46", CALIB41_EXCITATIONS, ["deft", "pliant", "sober"],
                            [(True, False), (True, True), (False, True)], [250.0, 710.0, 515.0, 415.0, 190.0],
                            [0.03, 0.074, 0.043], [0.0, 0.4, 0.0, 0.7], [0.002, 0.005], [0.0004, 0.0012],
                            22500, n, loops=("pi", "pid"), nff=1, plant_k=2, fs_k=3, tn_rule=(1, 4))


# fresh42: the design of best_start (2abc6a8), frozen before its first run; rates and variations
# drawn as fresh41's (numpy default_rng(42)), not chosen; fresh3's plants
_F42_FS = {"a": 755.0, "b": 535.0, "c": 810.0, "d": 705.0, "e": 310.0, "f": 885.0, "g": 745.0, "h": 760.0,
           "i": 335.0}
_F42_VARIED = _varied(-0.3117, 0.9669, 2.6814)


def fresh42_settings():
    """A fresh set (issues #30 and #31), fixed and committed before its first run: all 24 of fresh3's
    effect rows at 310-885 Hz (by recipe, drawn), seeds 22600 + k, with the gravity's phase, the
    asymmetry's sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh42", _F42_FS, _F42_VARIED, 22600)


# calib47: the design of best_start (2abc6a8), frozen before its first run; rates and torque noise
# drawn (numpy default_rng(4747): uniform(150, 900) Hz rounded to 5, then uniform(0.03, 0.12) N*m), not
# chosen; three plants no earlier set used
TERSE = T.Plant(J=0.075, Fc=0.6, Fs=0.95, vs=0.035, sigma2=0.8, sigma0=160.0, sigma1=0.9)
AMPLE = T.Plant(J=0.14, Fc=1.05, Fs=1.5, vs=0.055, sigma2=1.25, sigma0=230.0, sigma1=1.6)
LUCID = T.Plant(J=0.1, Fc=0.8, Fs=1.2, vs=0.05, sigma2=1.0, sigma0=190.0, sigma1=1.2)
_add_plants({"terse": (TERSE, T.VelocityPIController(kp=3.6, ki=21.0)),
             "ample": (AMPLE, T.VelocityPIController(kp=6.6, ki=40.0)),
             "lucid": (LUCID, T.VelocityPIController(kp=4.9, ki=29.0))},
            {"terse": PidTuning(3.4, 0.002),
             "ample": PidTuning(3.0, 0.003),
             "lucid": PidTuning(3.2, 0.002)})


def calib47_settings(n: int = 24):
    """A forty-seventh effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib41's) x both loops (the position PID without feedforward in every fourth
    row), the position sensor alone in rows 0-11 and the velocity sensor alone in rows 12-23, on
    TERSE, AMPLE and LUCID, at drawn rates 255-785 Hz and torque noise 0.075-0.114 N*m, white in half
    the rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.003 or 0.006
    deg/s, quantisation 0.0005 or 0.001 deg; seeds 22700 + i."""
    return _effect_free_set("calib47", CALIB41_EXCITATIONS, ["terse", "ample", "lucid"],
                            [(True, False), (False, True), (True, True)], [525.0, 695.0, 785.0, 285.0, 255.0],
                            [0.113, 0.114, 0.075], [0.0, 0.5, 0.0, 0.8], [0.003, 0.006], [0.0005, 0.001],
                            22700, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(1, 4))

# outside18: the design of best_start (2abc6a8), frozen before its first run; rates drawn (numpy
# default_rng(18): uniform(200, 800) Hz rounded to 5, rows a-h), not chosen
_OUT18_RECIPES = _outside14_on({"gritty": "lucid", "sprightly": "terse", "stolid": "ample"},
                               (440.0, 630.0, 370.0, 250.0, 780.0, 540.0, 585.0, 545.0))


def outside18_settings():
    """An eighteenth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on LUCID, TERSE and AMPLE, at drawn rates (250-780 Hz) and seeds 22900 + k."""
    return _outside_set("outside18_", OUTSIDE9_ROWS, _OUT18_RECIPES, 22900)


# calib48: the design of best_start (2abc6a8), frozen before its first run; every row white torque
# noise with one sensor, the kind on which calib42-47's first naming step fell below the bar on 13 of
# 33 (step_size.py); rates and torque noise drawn (numpy default_rng(4848): uniform(150, 900) Hz
# rounded to 5, then uniform(0.03, 0.12) N*m), not chosen; three plants no earlier set used
PLUMB = T.Plant(J=0.09, Fc=0.7, Fs=1.05, vs=0.04, sigma2=0.95, sigma0=175.0, sigma1=1.0)
SLEEK = T.Plant(J=0.12, Fc=0.95, Fs=1.4, vs=0.05, sigma2=1.2, sigma0=220.0, sigma1=1.4)
VIVID = T.Plant(J=0.065, Fc=0.5, Fs=0.8, vs=0.035, sigma2=0.7, sigma0=150.0, sigma1=0.8)
_add_plants({"plumb": (PLUMB, T.VelocityPIController(kp=4.4, ki=26.0)),
             "sleek": (SLEEK, T.VelocityPIController(kp=5.8, ki=35.0)),
             "vivid": (VIVID, T.VelocityPIController(kp=3.2, ki=19.0))},
            {"plumb": PidTuning(3.3, 0.002),
             "sleek": PidTuning(3.0, 0.003),
             "vivid": PidTuning(3.5, 0.002)})


def calib48_settings(n: int = 24):
    """A forty-eighth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib41's) x both loops (the position PID without feedforward in every fourth
    row), the position sensor alone in rows 0-11 and the velocity sensor alone in rows 12-23, white
    torque noise in every row, on PLUMB, SLEEK and VIVID, at drawn rates 375-815 Hz and torque noise
    0.044-0.117 N*m, velocity noise 0.003 or 0.006 deg/s, quantisation 0.0005 or 0.001 deg; seeds
    23000 + i. It checks, held out, the naming test's size where calib42-47 found it high."""
    return _effect_free_set("calib48", CALIB41_EXCITATIONS, ["plumb", "sleek", "vivid"],
                            [(True, False), (False, True), (True, True)], [635.0, 375.0, 395.0, 815.0, 560.0],
                            [0.044, 0.089, 0.117], [0.0, 0.0, 0.0, 0.0], [0.003, 0.006], [0.0005, 0.001],
                            23000, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(1, 4))


# calib49 and outside19: the design with the attribution's cross-validated, family-wise held-out
# test, frozen before their first run; rates and torque noise drawn (numpy default_rng(4949):
# uniform(150, 900) Hz rounded to 5, then uniform(0.03, 0.12) N*m; default_rng(19): uniform(200,
# 800) Hz rounded to 5, rows a-h), not chosen; three plants no earlier set used
MILD = T.Plant(J=0.1, Fc=0.8, Fs=1.2, vs=0.045, sigma2=1.0, sigma0=190.0, sigma1=1.2)
PRIM = T.Plant(J=0.15, Fc=1.05, Fs=1.55, vs=0.055, sigma2=1.35, sigma0=240.0, sigma1=1.6)
SWIFT = T.Plant(J=0.075, Fc=0.6, Fs=0.9, vs=0.04, sigma2=0.8, sigma0=160.0, sigma1=0.9)
_add_plants({"mild": (MILD, T.VelocityPIController(kp=4.8, ki=29.0)),
             "prim": (PRIM, T.VelocityPIController(kp=7.2, ki=43.0)),
             "swift": (SWIFT, T.VelocityPIController(kp=3.6, ki=22.0))},
            {"mild": PidTuning(3.2, 0.002),
             "prim": PidTuning(2.9, 0.003),
             "swift": PidTuning(3.4, 0.002)})


def calib49_settings(n: int = 36):
    """A forty-ninth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row) x the three sensor sets (position alone, velocity alone, both; 12 rows each), on
    MILD, PRIM and SWIFT, at drawn rates 265-820 Hz and torque noise 0.065-0.087 N*m, white in half
    the rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.003 or 0.006
    deg/s, quantisation 0.0005 or 0.001 deg; seeds 23200 + i."""
    return _effect_free_set("calib49", CALIB41_EXCITATIONS, ["mild", "prim", "swift"],
                            [(True, False), (False, True), (True, True)], [265.0, 795.0, 480.0, 765.0, 820.0],
                            [0.087, 0.073, 0.065], [0.0, 0.5, 0.0, 0.8], [0.003, 0.006], [0.0005, 0.001],
                            23200, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(1, 4))


_OUT19_RECIPES = _outside14_on({"gritty": "mild", "sprightly": "prim", "stolid": "swift"},
                               (450.0, 755.0, 365.0, 235.0, 385.0, 630.0, 670.0, 525.0))


def outside19_settings():
    """A nineteenth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on MILD, PRIM and SWIFT, at drawn rates (235-755 Hz) and seeds 23100 + k."""
    return _outside_set("outside19_", OUTSIDE9_ROWS, _OUT19_RECIPES, 23100)

# fresh43: the design of b17e381 (the attribution confirmed cross-validated, family-wise), frozen
# before its first run; rates and variations drawn as fresh41's (numpy default_rng(43)), not chosen;
# fresh3's plants; fresh3's even rows only (12, every effect at least once: a run that fits a stop)
_F43_FS = {"a": 675.0, "b": 280.0, "c": 265.0, "d": 795.0, "e": 630.0, "f": 395.0, "g": 740.0, "h": 420.0,
           "i": 525.0}
_F43_VARIED = _varied(-0.3077, 1.2299, 2.4624)


def fresh43_settings():
    """A fresh set (issues #30 and #31), fixed and committed before its first run: fresh3's even effect
    rows (12: all eight effects) at 265-795 Hz (by recipe, drawn), seeds 23300 + k, with the gravity's
    phase, the asymmetry's sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh43", _F43_FS, _F43_VARIED, 23300)[::2]


# calib50 and fresh44: the design with the narrower windows' check of the acceleration (a step the
# loop makes in a few samples leaves the fit), frozen before their first run; rates and torque noise
# drawn (numpy default_rng(5050): uniform(150, 900) Hz rounded to 5, then uniform(0.03, 0.12) N*m;
# default_rng(44): uniform(250, 900) Hz rounded to 5 by recipe, then fresh41's variations), not
# chosen; three plants no earlier set used for calib50, fresh3's plants for fresh44
CALM = T.Plant(J=0.11, Fc=0.85, Fs=1.25, vs=0.05, sigma2=1.05, sigma0=200.0, sigma1=1.25)
STERN = T.Plant(J=0.07, Fc=0.55, Fs=0.85, vs=0.035, sigma2=0.75, sigma0=150.0, sigma1=0.85)
ARDENT = T.Plant(J=0.16, Fc=1.1, Fs=1.6, vs=0.06, sigma2=1.4, sigma0=250.0, sigma1=1.7)
_add_plants({"calm": (CALM, T.VelocityPIController(kp=5.3, ki=32.0)),
             "stern": (STERN, T.VelocityPIController(kp=3.4, ki=20.0)),
             "ardent": (ARDENT, T.VelocityPIController(kp=7.7, ki=46.0))},
            {"calm": PidTuning(3.1, 0.002),
             "stern": PidTuning(3.4, 0.002),
             "ardent": PidTuning(2.9, 0.003)})


def calib50_settings(n: int = 24):
    """A fiftieth effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib41's) x both loops (the position PID without feedforward in every fourth
    row), the position sensor alone in rows 0-11 and the velocity sensor alone in rows 12-23 (the
    kinds on which the naming test's first step fell below its bar on calib42-49), on CALM, STERN and
    ARDENT, at drawn rates 260-835 Hz and torque noise 0.078-0.095 N*m, white in half the rows and
    AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.003 or 0.006 deg/s,
    quantisation 0.0005 or 0.001 deg; seeds 23400 + i."""
    return _effect_free_set("calib50", CALIB41_EXCITATIONS, ["calm", "stern", "ardent"],
                            [(True, False), (False, True), (True, True)], [565.0, 450.0, 500.0, 835.0, 260.0],
                            [0.095, 0.078, 0.088], [0.0, 0.5, 0.0, 0.8], [0.003, 0.006], [0.0005, 0.001],
                            23400, n, loops=("pid", "pi"), nff=3, plant_k=1, fs_k=2, tn_rule=(1, 4))


_F44_FS = {"a": 330.0, "b": 420.0, "c": 515.0, "d": 880.0, "e": 355.0, "f": 805.0, "g": 355.0, "h": 470.0,
           "i": 690.0}
_F44_VARIED = _varied(0.7322, 1.2297, -0.5567)


def fresh44_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's odd effect rows
    (12: all eight effects; fresh43 ran the even ones) at 330-880 Hz (by recipe, drawn), seeds
    23500 + k, with the gravity's phase, the asymmetry's sign and the ripple's period and phase
    changed by drawn amounts."""
    return _refreshed("fresh44", _F44_FS, _F44_VARIED, 23500)[1::2]


# fresh45: the design of 122505c (the narrower windows' check, the attribution's held-out fits with
# cv_gains' rank cut, a supplied acceleration compared where both resolve), frozen before its first
# run; rates and variations drawn as fresh41's (numpy default_rng(45)), not chosen; fresh3's plants;
# all 24 of fresh3's effect rows
_F45_FS = {"a": 625.0, "b": 595.0, "c": 745.0, "d": 780.0, "e": 580.0, "f": 755.0, "g": 765.0, "h": 635.0,
           "i": 515.0}
_F45_VARIED = _varied(1.0762, 1.0824, 2.1368)


def fresh45_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 515-780 Hz (by recipe, drawn), seeds 23600 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh45", _F45_FS, _F45_VARIED, 23600)

# calib51: the design of 39f623d (as 122505c's for verdicts), frozen before its first run; three plants
# no earlier set used, their parameters drawn (numpy default_rng(51): J uniform(0.06, 0.18), Fc
# uniform(0.5, 1.2), Fs/Fc uniform(1.3, 1.6), vs uniform(0.03, 0.07), sigma2 uniform(0.7, 1.5),
# sigma0 uniform(120, 280); sigma1 sqrt(sigma0*J)/2.5, the velocity PI's gains 48*J and 290*J), then
# the rates uniform(150, 900) Hz rounded to 5 and the torque noise uniform(0.03, 0.12) N*m, not chosen
SEDATE = T.Plant(J=0.173, Fc=0.715, Fs=0.984, vs=0.0389, sigma2=1.329, sigma0=155.0, sigma1=2.07)
PLACID = T.Plant(J=0.157, Fc=1.013, Fs=1.445, vs=0.0497, sigma2=1.427, sigma0=247.0, sigma1=2.49)
SERENE = T.Plant(J=0.078, Fc=1.024, Fs=1.455, vs=0.0697, sigma2=0.869, sigma0=186.0, sigma1=1.52)
_add_plants({"sedate": (SEDATE, T.VelocityPIController(kp=8.3, ki=50.0)),
             "placid": (PLACID, T.VelocityPIController(kp=7.5, ki=45.5)),
             "serene": (SERENE, T.VelocityPIController(kp=3.7, ki=22.6))},
            {"sedate": PidTuning(3.0, 0.002),
             "placid": PidTuning(3.3, 0.003),
             "serene": PidTuning(2.8, 0.002)})


def calib51_settings(n: int = 24):
    """A fifty-first effect-free set (issue #30), fixed and committed before its first run: the six
    excitation kinds (calib41's) x both loops (the position PID without feedforward in every fourth
    row), both sensors in rows 0-11 and the velocity sensor alone in rows 12-23, on SEDATE, PLACID
    and SERENE, at drawn rates 325-855 Hz and torque noise 0.035-0.062 N*m, white in half the rows
    and AR(1) of coefficient 0.6 or 0.3 in the other half, velocity noise 0.002 or 0.004 deg/s,
    quantisation 0.0005 or 0.001 deg; seeds 23700 + i."""
    return _effect_free_set("calib51", CALIB41_EXCITATIONS, ["sedate", "placid", "serene"],
                            [(True, True), (False, True), (True, False)], [855.0, 585.0, 700.0, 605.0, 325.0],
                            [0.035, 0.039, 0.062], [0.0, 0.6, 0.0, 0.3], [0.002, 0.004], [0.0005, 0.001],
                            23700, n, loops=("pi", "pid"), nff=2, plant_k=1, fs_k=3, tn_rule=(1, 4))

# outside20 and outside21: the current design (bb870a6), frozen before their first run; outside14's
# rows on calib51's and calib50's plants, rates drawn (numpy default_rng(20) and default_rng(21):
# uniform(200, 800) Hz rounded to 5, rows a-h), not chosen
_OUT20_RECIPES = _outside14_on({"gritty": "sedate", "sprightly": "placid", "stolid": "serene"},
                               (370.0, 475.0, 275.0, 515.0, 445.0, 245.0, 260.0, 790.0))
_OUT21_RECIPES = _outside14_on({"gritty": "calm", "sprightly": "stern", "stolid": "ardent"},
                               (670.0, 565.0, 625.0, 255.0, 580.0, 790.0, 455.0, 265.0))


def outside20_settings():
    """A twentieth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on SEDATE, PLACID and SERENE, at drawn rates (245-790 Hz) and seeds 23800 + k."""
    return _outside_set("outside20_", OUTSIDE9_ROWS, _OUT20_RECIPES, 23800)


def outside21_settings():
    """A twenty-first outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on CALM, STERN and ARDENT, at drawn rates (255-790 Hz) and seeds 23900 + k."""
    return _outside_set("outside21_", OUTSIDE9_ROWS, _OUT21_RECIPES, 23900)


# fresh46: the design of 046cd8f (verdicts as bb870a6's), frozen before its first run; rates and
# variations drawn as fresh45's (numpy default_rng(46)), not chosen; fresh3's plants; all 24 of
# fresh3's effect rows
_F46_FS = {"a": 840.0, "b": 300.0, "c": 425.0, "d": 655.0, "e": 855.0, "f": 305.0, "g": 660.0, "h": 755.0,
           "i": 580.0}
_F46_VARIED = _varied(1.5614, 1.1962, -0.0054)


def fresh46_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 300-855 Hz (by recipe, drawn), seeds 24000 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh46", _F46_FS, _F46_VARIED, 24000)

# calib52: the design of 046cd8f (verdicts as bb870a6's), frozen before its first run; three plants no
# earlier set used, their parameters drawn by calib51's recipe (numpy default_rng(52); the position
# PID's kp uniform(2.8, 3.4), kd 0.002 or 0.003), then the rates uniform(150, 900) Hz rounded to 5 and
# the torque noise uniform(0.03, 0.12) N*m, not chosen
QUIET = T.Plant(J=0.134, Fc=0.902, Fs=1.313, vs=0.0303, sigma2=1.14, sigma0=275.0, sigma1=2.43)
TENDER = T.Plant(J=0.089, Fc=1.163, Fs=1.824, vs=0.049, sigma2=0.794, sigma0=133.0, sigma1=1.38)
GENTLE = T.Plant(J=0.068, Fc=0.843, Fs=1.199, vs=0.0606, sigma2=0.758, sigma0=200.0, sigma1=1.47)
_add_plants({"quiet": (QUIET, T.VelocityPIController(kp=6.4, ki=38.8)),
             "tender": (TENDER, T.VelocityPIController(kp=4.3, ki=25.9)),
             "gentle": (GENTLE, T.VelocityPIController(kp=3.3, ki=19.6))},
            {"quiet": PidTuning(3.0, 0.002),
             "tender": PidTuning(3.4, 0.002),
             "gentle": PidTuning(3.3, 0.002)})


def calib52_settings(n: int = 24):
    """A fifty-second effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the position sensor alone in rows 0-11 and both sensors in rows 12-23, on QUIET,
    TENDER and GENTLE, at drawn rates 290-735 Hz and torque noise 0.055-0.12 N*m, white in half the
    rows and AR(1) of coefficient 0.4 or 0.7 in the other half, velocity noise 0.003 or 0.005 deg/s,
    quantisation 0.0005 or 0.001 deg; seeds 24100 + i."""
    return _effect_free_set("calib52", CALIB41_EXCITATIONS, ["quiet", "tender", "gentle"],
                            [(True, False), (True, True), (False, True)], [735.0, 560.0, 290.0, 730.0, 340.0],
                            [0.085, 0.055, 0.12], [0.0, 0.4, 0.0, 0.7], [0.003, 0.005], [0.0005, 0.001],
                            24100, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))

# fresh47 and calib53: the design of a437f7f (a backlash width set by its profile), frozen before
# their first run. fresh47: rates and variations drawn as fresh46's (numpy default_rng(47)), fresh3's
# plants, all 24 of fresh3's effect rows. calib53: three plants no earlier set used, drawn by this
# recipe (numpy default_rng(53); per plant in turn J uniform(0.06, 0.18), Fc
# uniform(0.5, 1.2), Fs/Fc uniform(1.3, 1.6), vs uniform(0.03, 0.07), sigma2 uniform(0.7, 1.5), sigma0
# uniform(120, 280), sigma1 sqrt(sigma0*J)/2.5, the velocity PI's gains 48*J and 290*J; then per plant
# the position PID's kp uniform(2.8, 3.4) to 0.1 and kd 0.002 or 0.003; then five rates uniform(150,
# 900) Hz rounded to 5 and three torque noises uniform(0.03, 0.12) N*m), not chosen
_F47_FS = {"a": 730.0, "b": 740.0, "c": 550.0, "d": 315.0, "e": 880.0, "f": 460.0, "g": 380.0, "h": 810.0,
           "i": 585.0}
_F47_VARIED = _varied(-2.0154, 1.1377, 1.8408)


def fresh47_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 315-880 Hz (by recipe, drawn), seeds 24300 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh47", _F47_FS, _F47_VARIED, 24300)


HUMBLE = T.Plant(J=0.061, Fc=1.003, Fs=1.404, vs=0.0673, sigma2=0.784, sigma0=227.0, sigma1=1.49)
FRANK = T.Plant(J=0.158, Fc=0.984, Fs=1.574, vs=0.0608, sigma2=0.933, sigma0=168.0, sigma1=2.06)
CANDID = T.Plant(J=0.132, Fc=0.941, Fs=1.274, vs=0.0612, sigma2=1.417, sigma0=233.0, sigma1=2.22)
_add_plants({"humble": (HUMBLE, T.VelocityPIController(kp=2.9, ki=17.8)),
             "frank": (FRANK, T.VelocityPIController(kp=7.6, ki=45.9)),
             "candid": (CANDID, T.VelocityPIController(kp=6.3, ki=38.3))},
            {"humble": PidTuning(2.8, 0.002),
             "frank": PidTuning(3.0, 0.003),
             "candid": PidTuning(2.8, 0.002)})


def calib53_settings(n: int = 24):
    """A fifty-third effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the velocity sensor alone in rows 0-11 and both sensors in rows 12-23, on HUMBLE,
    FRANK and CANDID, at drawn rates 525-820 Hz and torque noise 0.04-0.119 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 24200 + i."""
    return _effect_free_set("calib53", CALIB41_EXCITATIONS, ["humble", "frank", "candid"],
                            [(False, True), (True, True), (True, False)], [665.0, 820.0, 755.0, 525.0, 815.0],
                            [0.119, 0.062, 0.04], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            24200, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=1, tn_rule=(2, 5))

# fresh48 and calib54: the design of 5697ea7 (a437f7f with a profiled width held in the
# identifiability check), frozen before their first run; a smaller check of what that change touches.
# fresh48: fresh3's three backlash rows at the rates drawn as fresh47's with numpy default_rng(48) and
# default_rng(49) (six rows). calib54: twelve effect-free rows on three new plants drawn by calib53's
# recipe (numpy default_rng(54)), not chosen
_F48_FS = ({"a": 500.0, "b": 635.0, "c": 585.0, "d": 700.0, "e": 675.0, "f": 810.0, "g": 635.0, "h": 595.0,
            "i": 750.0},
           {"a": 485.0, "b": 635.0, "c": 505.0, "d": 655.0, "e": 675.0, "f": 260.0, "g": 755.0, "h": 895.0,
            "i": 580.0})


def fresh48_settings():
    """A fresh set (issue #30), fixed and committed before its first run: fresh3's backlash rows
    (recipes a, e, f) at two draws of the rates (260-810 Hz), seeds 24400 + k and 24500 + k."""
    return [r for i, fs in enumerate(_F48_FS)
            for r in _refreshed(f"fresh48{'ab'[i]}", fs, {}, 24400 + 100 * i) if "backlash" in r["key"]]


DOCILE = T.Plant(J=0.087, Fc=0.863, Fs=1.143, vs=0.0531, sigma2=0.769, sigma0=193.0, sigma1=1.64)
EARNEST = T.Plant(J=0.14, Fc=0.59, Fs=0.931, vs=0.0673, sigma2=1.08, sigma0=234.0, sigma1=2.29)
PATIENT = T.Plant(J=0.077, Fc=0.621, Fs=0.951, vs=0.0454, sigma2=1.359, sigma0=271.0, sigma1=1.83)
_add_plants({"docile": (DOCILE, T.VelocityPIController(kp=4.2, ki=25.1)),
             "earnest": (EARNEST, T.VelocityPIController(kp=6.7, ki=40.6)),
             "patient": (PATIENT, T.VelocityPIController(kp=3.7, ki=22.4))},
            {"docile": PidTuning(2.9, 0.002),
             "earnest": PidTuning(3.2, 0.003),
             "patient": PidTuning(3.3, 0.002)})


def calib54_settings(n: int = 12):
    """A fifty-fourth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the position sensor alone, on DOCILE, EARNEST and PATIENT, at drawn rates 170-865 Hz
    and torque noise 0.033-0.055 N*m, white in half the rows and AR(1) of coefficient 0.5 or 0.8 in
    the other half, quantisation 0.0005 or 0.001 deg; seeds 24600 + i."""
    return _effect_free_set("calib54", CALIB41_EXCITATIONS, ["docile", "earnest", "patient"],
                            [(True, False), (False, True), (True, True)], [170.0, 365.0, 615.0, 865.0, 865.0],
                            [0.055, 0.034, 0.033], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.0005, 0.001],
                            24600, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))

# fresh49 and calib55: the design of e0edcfc (a step's runner-up judged alike, the better held-out
# predictor named, the other reported as an alternative), frozen before their first run. fresh49:
# fresh3's 24 effect rows at rates and variations drawn as fresh47's with numpy default_rng(50) (the
# next seed no set drew rates with). calib55: twelve effect-free rows, both sensors, on three new
# plants drawn by calib53's recipe (numpy default_rng(55)), not chosen
_F49_FS = {"a": 760.0, "b": 790.0, "c": 605.0, "d": 885.0, "e": 405.0, "f": 670.0, "g": 290.0, "h": 610.0,
           "i": 510.0}
_F49_VARIED = _varied(-1.4705, 1.244, -0.6452)


def fresh49_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 290-885 Hz (by recipe, drawn), seeds 24700 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh49", _F49_FS, _F49_VARIED, 24700)


PRUDENT = T.Plant(J=0.16, Fc=1.109, Fs=1.515, vs=0.0392, sigma2=1.094, sigma0=241.0, sigma1=2.48)
THRIFTY = T.Plant(J=0.145, Fc=1.163, Fs=1.535, vs=0.0496, sigma2=0.971, sigma0=216.0, sigma1=2.24)
SINCERE = T.Plant(J=0.065, Fc=0.738, Fs=0.977, vs=0.0688, sigma2=1.171, sigma0=201.0, sigma1=1.45)
_add_plants({"prudent": (PRUDENT, T.VelocityPIController(kp=7.7, ki=46.4)),
             "thrifty": (THRIFTY, T.VelocityPIController(kp=6.9, ki=41.9)),
             "sincere": (SINCERE, T.VelocityPIController(kp=3.1, ki=18.9))},
            {"prudent": PidTuning(3.4, 0.003),
             "thrifty": PidTuning(3.1, 0.002),
             "sincere": PidTuning(3.1, 0.002)})


def calib55_settings(n: int = 12):
    """A fifty-fifth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), both sensors, on PRUDENT, THRIFTY and SINCERE, at drawn rates 170-590 Hz and torque
    noise 0.058-0.099 N*m, white in half the rows and AR(1) of coefficient 0.5 or 0.8 in the other
    half, velocity noise 0.002 or 0.006 deg/s, quantisation 0.001 or 0.0005 deg; seeds 24800 + i."""
    return _effect_free_set("calib55", CALIB41_EXCITATIONS, ["prudent", "thrifty", "sincere"],
                            [(True, True), (False, True), (True, False)], [170.0, 380.0, 590.0, 585.0, 285.0],
                            [0.058, 0.099, 0.06], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            24800, n, loops=("pi", "pid"), nff=2, plant_k=1, fs_k=2, tn_rule=(1, 4))

# outside22: the design of e0edcfc, frozen before its first run; outside14's rows on calib55's
# plants, rates drawn (numpy default_rng(22): uniform(200, 800) Hz rounded to 5, rows a-h), not chosen
_OUT22_RECIPES = _outside14_on({"gritty": "prudent", "sprightly": "thrifty", "stolid": "sincere"},
                               (420.0, 320.0, 255.0, 590.0, 475.0, 795.0, 710.0, 700.0))


def outside22_settings():
    """A twenty-second outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on PRUDENT, THRIFTY and SINCERE, at drawn rates (255-795 Hz) and seeds 24900 + k."""
    return _outside_set("outside22_", OUTSIDE9_ROWS, _OUT22_RECIPES, 24900)


# fresh50, calib56 and outside23: the design that leaves out samples whose model torque the
# kinematics' noise moves by more than half the torque noise, frozen before their first run.
# fresh50: fresh3's 24 effect rows at rates and variations drawn as fresh41's with numpy
# default_rng(56) (the next seed no set drew with). calib56: 24 effect-free rows, the position
# sensor alone in rows 0-11 and both sensors in rows 12-23, on three new plants drawn by calib53's
# recipe (numpy default_rng(57)). outside23: outside14's rows on calib56's plants, rates drawn as
# outside22's (numpy default_rng(23)). None chosen
_F50_FS = {"a": 720.0, "b": 260.0, "c": 890.0, "d": 720.0, "e": 605.0, "f": 405.0, "g": 645.0, "h": 485.0,
           "i": 635.0}
_F50_VARIED = _varied(-1.5015, 0.8138, 0.5874)


def fresh50_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 260-890 Hz (by recipe, drawn), seeds 25000 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh50", _F50_FS, _F50_VARIED, 25000)


CANNY = T.Plant(J=0.142, Fc=0.828, Fs=1.285, vs=0.0436, sigma2=1.015, sigma0=145.0, sigma1=1.82)
PLAIN = T.Plant(J=0.112, Fc=1.008, Fs=1.399, vs=0.0435, sigma2=0.85, sigma0=197.0, sigma1=1.88)
FRUGAL = T.Plant(J=0.174, Fc=1.173, Fs=1.718, vs=0.0558, sigma2=0.757, sigma0=160.0, sigma1=2.11)
_add_plants({"canny": (CANNY, T.VelocityPIController(kp=6.8, ki=41.2)),
             "plain": (PLAIN, T.VelocityPIController(kp=5.4, ki=32.3)),
             "frugal": (FRUGAL, T.VelocityPIController(kp=8.3, ki=50.4))},
            {"canny": PidTuning(3.1, 0.003),
             "plain": PidTuning(3.0, 0.002),
             "frugal": PidTuning(3.3, 0.003)})


def calib56_settings(n: int = 24):
    """A fifty-sixth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the position sensor alone in rows 0-11 and both sensors in rows 12-23, on CANNY,
    PLAIN and FRUGAL, at drawn rates 330-825 Hz and torque noise 0.036-0.107 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 25100 + i."""
    return _effect_free_set("calib56", CALIB41_EXCITATIONS, ["canny", "plain", "frugal"],
                            [(True, False), (True, True), (False, True)], [590.0, 545.0, 660.0, 330.0, 825.0],
                            [0.107, 0.098, 0.036], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            25100, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


_OUT23_RECIPES = _outside14_on({"gritty": "canny", "sprightly": "plain", "stolid": "frugal"},
                               (615.0, 585.0, 275.0, 270.0, 590.0, 710.0, 320.0, 330.0))


def outside23_settings():
    """A twenty-third outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on CANNY, PLAIN and FRUGAL, at drawn rates (270-710 Hz) and seeds 25200 + k."""
    return _outside_set("outside23_", OUTSIDE9_ROWS, _OUT23_RECIPES, 25200)

# fresh51 and calib57: the design of 56f3f32 (94244b1's with step-down min-P), frozen before their
# first run. fresh51: rates and variations drawn as fresh50's with numpy default_rng(59).
# calib57: three plants no earlier set used, drawn by calib53's recipe (numpy default_rng(58)), the
# velocity sensor alone in rows 0-11 and both sensors in rows 12-23. None chosen
_F51_FS = {"a": 630.0, "b": 785.0, "c": 325.0, "d": 495.0, "e": 370.0, "f": 355.0, "g": 255.0, "h": 880.0,
           "i": 315.0}
_F51_VARIED = _varied(2.7302, 0.9918, 1.2970)


def fresh51_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 255-880 Hz (by recipe, drawn), seeds 25400 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh51", _F51_FS, _F51_VARIED, 25400)


WARY = T.Plant(J=0.097, Fc=1.116, Fs=1.532, vs=0.0383, sigma2=1.377, sigma0=142.0, sigma1=1.49)
ASTUTE = T.Plant(J=0.097, Fc=0.597, Fs=0.87, vs=0.067, sigma2=1.127, sigma0=163.0, sigma1=1.59)
SHREWD = T.Plant(J=0.174, Fc=0.795, Fs=1.096, vs=0.0524, sigma2=1.454, sigma0=262.0, sigma1=2.7)
_add_plants({"wary": (WARY, T.VelocityPIController(kp=4.7, ki=28.2)),
             "astute": (ASTUTE, T.VelocityPIController(kp=4.6, ki=28.0)),
             "shrewd": (SHREWD, T.VelocityPIController(kp=8.4, ki=50.5))},
            {"wary": PidTuning(3.1, 0.003),
             "astute": PidTuning(3.1, 0.002),
             "shrewd": PidTuning(2.8, 0.002)})


def calib57_settings(n: int = 24):
    """A fifty-seventh effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the velocity sensor alone in rows 0-11 and both sensors in rows 12-23, on WARY,
    ASTUTE and SHREWD, at drawn rates 220-785 Hz and torque noise 0.033-0.065 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 25300 + i."""
    return _effect_free_set("calib57", CALIB41_EXCITATIONS, ["wary", "astute", "shrewd"],
                            [(False, True), (True, True), (True, False)], [220.0, 270.0, 785.0, 265.0, 495.0],
                            [0.033, 0.065, 0.063], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            25300, n, loops=("pi", "pid"), nff=3, plant_k=2, fs_k=1, tn_rule=(2, 5))


# outside24: the design of 030d46c (56f3f32's with the time line placed between the periodogram's
# ordinates), frozen before its first run: outside14's rows on calib57's plants, rates drawn as
# outside22's (numpy default_rng(24)). None chosen
_OUT24_RECIPES = _outside14_on({"gritty": "wary", "sprightly": "astute", "stolid": "shrewd"},
                               (400.0, 445.0, 545.0, 505.0, 540.0, 540.0, 725.0, 250.0))


def outside24_settings():
    """A twenty-fourth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on WARY, ASTUTE and SHREWD, at drawn rates (250-725 Hz) and seeds 25500 + k."""
    return _outside_set("outside24_", OUTSIDE9_ROWS, _OUT24_RECIPES, 25500)


# outside25: the design of 36e4822 (030d46c's with a named candidate's library
# terms the held-out blocks cannot tell from it listed as its alternatives, which changes no
# verdict), frozen before its first run: outside14's rows on three plants no earlier set used, drawn
# by calib53's recipe (numpy default_rng(60)), rates drawn as outside22's (numpy default_rng(61)).
# None chosen
STOIC = T.Plant(J=0.099, Fc=0.519, Fs=0.683, vs=0.0696, sigma2=1.391, sigma0=208.0, sigma1=1.81)
DILIGENT = T.Plant(J=0.176, Fc=1.194, Fs=1.693, vs=0.0428, sigma2=1.243, sigma0=123.0, sigma1=1.86)
LOYAL = T.Plant(J=0.128, Fc=1.046, Fs=1.549, vs=0.0529, sigma2=1.119, sigma0=154.0, sigma1=1.77)
_add_plants({"stoic": (STOIC, T.VelocityPIController(kp=4.7, ki=28.7)),
             "diligent": (DILIGENT, T.VelocityPIController(kp=8.5, ki=51.1)),
             "loyal": (LOYAL, T.VelocityPIController(kp=6.2, ki=37.2))},
            {"stoic": PidTuning(3.1, 0.003),
             "diligent": PidTuning(3.0, 0.002),
             "loyal": PidTuning(3.1, 0.002)})
_OUT25_RECIPES = _outside14_on({"gritty": "stoic", "sprightly": "diligent", "stolid": "loyal"},
                               (425.0, 665.0, 605.0, 625.0, 460.0, 800.0, 800.0, 770.0))


def outside25_settings():
    """A twenty-fifth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on STOIC, DILIGENT and LOYAL, at drawn rates (425-800 Hz) and seeds 25600 + k."""
    return _outside_set("outside25_", OUTSIDE9_ROWS, _OUT25_RECIPES, 25600)


# fresh52 and calib58: outside25's design, frozen before their first run. fresh52: fresh3's 24
# effect rows at rates and variations drawn as fresh51's with numpy default_rng(62). calib58: 24
# effect-free rows on outside25's plants with the five rates and three torque noises its draw
# (numpy default_rng(60)) gives, the position sensor alone in rows 0-11 and both sensors in rows
# 12-23 (as calib56, calib57 having had the velocity sensor alone). None chosen
_F52_FS = {"a": 645.0, "b": 735.0, "c": 755.0, "d": 435.0, "e": 700.0, "f": 850.0, "g": 585.0, "h": 820.0,
           "i": 785.0}
_F52_VARIED = _varied(-1.6604, 1.1722, -3.0086)


def fresh52_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 435-850 Hz (by recipe, drawn), seeds 25700 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh52", _F52_FS, _F52_VARIED, 25700)


def calib58_settings(n: int = 24):
    """A fifty-eighth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the position sensor alone in rows 0-11 and both sensors in rows 12-23, on STOIC,
    DILIGENT and LOYAL, at drawn rates 560-900 Hz and torque noise 0.037-0.082 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 25800 + i."""
    return _effect_free_set("calib58", CALIB41_EXCITATIONS, ["stoic", "diligent", "loyal"],
                            [(True, False), (True, True), (False, True)], [560.0, 900.0, 835.0, 885.0, 870.0],
                            [0.073, 0.082, 0.037], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            25800, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# fresh53: fresh52's design on the hump restart after each accepted step, frozen before its first
# run: fresh3's 24 effect rows at rates and variations drawn as fresh52's with numpy
# default_rng(63). None chosen
_F53_FS = {"a": 615.0, "b": 895.0, "c": 380.0, "d": 580.0, "e": 380.0, "f": 360.0, "g": 490.0, "h": 435.0,
           "i": 520.0}
_F53_VARIED = _varied(3.0755, 1.0226, -0.0757)


def fresh53_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 360-895 Hz (by recipe, drawn), seeds 25900 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh53", _F53_FS, _F53_VARIED, 25900)


# calib59: the design of 4e01d45 (fresh53's: the hump restart after each finding), frozen before its
# first run: 24 effect-free rows on three plants no earlier set used, drawn by calib53's recipe
# (numpy default_rng(64)), the velocity sensor alone in rows 0-11 and both sensors in rows 12-23
# (calib58 had the position sensor alone). None chosen
JOVIAL = T.Plant(J=0.173, Fc=0.866, Fs=1.143, vs=0.0427, sigma2=1.387, sigma0=134.0, sigma1=1.92)
WISTFUL = T.Plant(J=0.178, Fc=0.938, Fs=1.261, vs=0.0314, sigma2=1.035, sigma0=209.0, sigma1=2.44)
QUAINT = T.Plant(J=0.143, Fc=0.533, Fs=0.847, vs=0.0524, sigma2=1.104, sigma0=245.0, sigma1=2.37)
_add_plants({"jovial": (JOVIAL, T.VelocityPIController(kp=8.3, ki=50.2)),
             "wistful": (WISTFUL, T.VelocityPIController(kp=8.6, ki=51.7)),
             "quaint": (QUAINT, T.VelocityPIController(kp=6.9, ki=41.5))},
            {"jovial": PidTuning(3.2, 0.003),
             "wistful": PidTuning(3.1, 0.003),
             "quaint": PidTuning(3.3, 0.002)})


def calib59_settings(n: int = 24):
    """A fifty-ninth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the velocity sensor alone in rows 0-11 and both sensors in rows 12-23, on JOVIAL,
    WISTFUL and QUAINT, at drawn rates 170-820 Hz and torque noise 0.052-0.112 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 26000 + i."""
    return _effect_free_set("calib59", CALIB41_EXCITATIONS, ["jovial", "wistful", "quaint"],
                            [(False, True), (True, True), (True, False)], [170.0, 820.0, 175.0, 515.0, 190.0],
                            [0.106, 0.052, 0.112], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            26000, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# outside26: the design of 4e01d45 (the hump restart), frozen before its first run: outside14's rows
# on calib59's plants, rates drawn as outside22's (numpy default_rng(65)). None chosen
_OUT26_RECIPES = _outside14_on({"gritty": "jovial", "sprightly": "wistful", "stolid": "quaint"},
                               (230.0, 510.0, 425.0, 335.0, 765.0, 555.0, 365.0, 225.0))


def outside26_settings():
    """A twenty-sixth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on JOVIAL, WISTFUL and QUAINT, at drawn rates (225-765 Hz) and seeds 26100 + k."""
    return _outside_set("outside26_", OUTSIDE9_ROWS, _OUT26_RECIPES, 26100)


# fresh54: the design of c83c071 (after a moved hump the selection goes on from both fits and keeps
# the path of lower cross-validated error), frozen before its first run: fresh3's 24 effect rows at
# rates and variations drawn as fresh52's with numpy default_rng(66). None chosen
_F54_FS = {"a": 850.0, "b": 700.0, "c": 295.0, "d": 655.0, "e": 555.0, "f": 800.0, "g": 315.0, "h": 535.0,
           "i": 550.0}
_F54_VARIED = _varied(2.5685, 1.1563, 0.1868)


def fresh54_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 295-850 Hz (by recipe, drawn), seeds 26200 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh54", _F54_FS, _F54_VARIED, 26200)


# calib60: the design of c83c071, frozen before its first run: 24 effect-free rows on three plants no
# earlier set used, drawn by calib53's recipe (numpy default_rng(67)), the position sensor alone in
# rows 0-11 and both sensors in rows 12-23. None chosen
ORNATE = T.Plant(J=0.110, Fc=0.589, Fs=0.857, vs=0.0419, sigma2=1.178, sigma0=189.0, sigma1=1.82)
HEARTY = T.Plant(J=0.097, Fc=0.749, Fs=0.994, vs=0.0665, sigma2=0.879, sigma0=122.0, sigma1=1.38)
ZESTY = T.Plant(J=0.158, Fc=1.097, Fs=1.745, vs=0.0587, sigma2=0.971, sigma0=180.0, sigma1=2.13)
_add_plants({"ornate": (ORNATE, T.VelocityPIController(kp=5.3, ki=31.9)),
             "hearty": (HEARTY, T.VelocityPIController(kp=4.7, ki=28.1)),
             "zesty": (ZESTY, T.VelocityPIController(kp=7.6, ki=45.8))},
            {"ornate": PidTuning(2.9, 0.002),
             "hearty": PidTuning(3.2, 0.002),
             "zesty": PidTuning(3.0, 0.003)})


def calib60_settings(n: int = 24):
    """A sixtieth effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the position sensor alone in rows 0-11 and both sensors in rows 12-23, on ORNATE,
    HEARTY and ZESTY, at drawn rates 230-750 Hz and torque noise 0.039-0.079 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 26300 + i."""
    return _effect_free_set("calib60", CALIB41_EXCITATIONS, ["ornate", "hearty", "zesty"],
                            [(True, False), (True, True), (False, True)], [625.0, 280.0, 565.0, 750.0, 230.0],
                            [0.039, 0.079, 0.060], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            26300, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# outside27: the design of c83c071, frozen before its first run: outside14's rows on calib60's plants,
# rates drawn as outside22's (numpy default_rng(68)). None chosen
_OUT27_RECIPES = _outside14_on({"gritty": "ornate", "sprightly": "hearty", "stolid": "zesty"},
                               (490.0, 710.0, 605.0, 575.0, 785.0, 615.0, 280.0, 515.0))


def outside27_settings():
    """A twenty-seventh outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on ORNATE, HEARTY and ZESTY, at drawn rates (280-785 Hz) and seeds 26400 + k."""
    return _outside_set("outside27_", OUTSIDE9_ROWS, _OUT27_RECIPES, 26400)


# fresh55: the design of the backlash's correlation-spaced width starts, frozen before its first
# run: fresh3's 24 effect rows at rates and variations drawn as fresh52's with numpy
# default_rng(69). None chosen
_F55_FS = {"a": 625.0, "b": 590.0, "c": 810.0, "d": 730.0, "e": 560.0, "f": 780.0, "g": 605.0, "h": 535.0,
           "i": 255.0}
_F55_VARIED = _varied(1.1214, 1.1538, 1.2939)


def fresh55_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 255-810 Hz (by recipe, drawn), seeds 26500 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh55", _F55_FS, _F55_VARIED, 26500)


# calib61: the design of fresh55, frozen before its first run: 24 effect-free rows on three plants no
# earlier set used, drawn by calib53's recipe (numpy default_rng(70)), the velocity sensor alone in
# rows 0-11 and both sensors in rows 12-23. None chosen
FRISKY = T.Plant(J=0.106, Fc=1.007, Fs=1.406, vs=0.0686, sigma2=1.292, sigma0=193.0, sigma1=1.81)
CHIPPER = T.Plant(J=0.085, Fc=0.502, Fs=0.771, vs=0.0393, sigma2=0.712, sigma0=175.0, sigma1=1.54)
PERKY = T.Plant(J=0.080, Fc=0.534, Fs=0.732, vs=0.0425, sigma2=1.274, sigma0=147.0, sigma1=1.37)
_add_plants({"frisky": (FRISKY, T.VelocityPIController(kp=5.1, ki=30.7)),
             "chipper": (CHIPPER, T.VelocityPIController(kp=4.1, ki=24.7)),
             "perky": (PERKY, T.VelocityPIController(kp=3.8, ki=23.2))},
            {"frisky": PidTuning(2.8, 0.002),
             "chipper": PidTuning(2.9, 0.002),
             "perky": PidTuning(3.0, 0.003)})


def calib61_settings(n: int = 24):
    """A sixty-first effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the velocity sensor alone in rows 0-11 and both sensors in rows 12-23, on FRISKY,
    CHIPPER and PERKY, at drawn rates 280-755 Hz and torque noise 0.058-0.091 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 26600 + i."""
    return _effect_free_set("calib61", CALIB41_EXCITATIONS, ["frisky", "chipper", "perky"],
                            [(False, True), (True, True), (True, False)], [325.0, 315.0, 755.0, 280.0, 630.0],
                            [0.083, 0.091, 0.058], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            26600, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# outside28: the design of bd43a77 (the backlash's correlation-spaced width starts), frozen before its
# first run: outside14's rows on calib61's plants, rates drawn as outside22's (numpy default_rng(71)).
# None chosen
_OUT28_RECIPES = _outside14_on({"gritty": "frisky", "sprightly": "chipper", "stolid": "perky"},
                               (350.0, 515.0, 655.0, 580.0, 325.0, 225.0, 515.0, 320.0))


def outside28_settings():
    """A twenty-eighth outside set (issue #31), fixed and committed before its first run: outside14's
    rows and excitations on FRISKY, CHIPPER and PERKY, at drawn rates (225-655 Hz) and seeds 26700 + k."""
    return _outside_set("outside28_", OUTSIDE9_ROWS, _OUT28_RECIPES, 26700)


# fresh56: the design of bd43a77 (as fresh55's), frozen before its first run: fresh3's 24 effect rows
# at rates and variations drawn as fresh52's with numpy default_rng(72). None chosen
_F56_FS = {"a": 795.0, "b": 255.0, "c": 400.0, "d": 325.0, "e": 715.0, "f": 450.0, "g": 625.0, "h": 285.0,
           "i": 440.0}
_F56_VARIED = _varied(2.85, 1.2084, -0.9534)


def fresh56_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 255-795 Hz (by recipe, drawn), seeds 26800 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh56", _F56_FS, _F56_VARIED, 26800)


# calib62: the design of bd43a77, frozen before its first run: 24 effect-free rows on three plants no
# earlier set used, drawn by calib53's recipe (numpy default_rng(73)), the position sensor alone in
# rows 0-11 and both sensors in rows 12-23. None chosen
SPUNKY = T.Plant(J=0.119, Fc=0.712, Fs=0.983, vs=0.0694, sigma2=0.876, sigma0=125.0, sigma1=1.54)
SUNNY = T.Plant(J=0.163, Fc=0.62, Fs=0.963, vs=0.0589, sigma2=0.763, sigma0=137.0, sigma1=1.89)
PEPPY = T.Plant(J=0.114, Fc=1.02, Fs=1.361, vs=0.0371, sigma2=1.318, sigma0=172.0, sigma1=1.77)
_add_plants({"spunky": (SPUNKY, T.VelocityPIController(kp=5.7, ki=34.5)),
             "sunny": (SUNNY, T.VelocityPIController(kp=7.8, ki=47.3)),
             "peppy": (PEPPY, T.VelocityPIController(kp=5.5, ki=33.1))},
            {"spunky": PidTuning(3.3, 0.002),
             "sunny": PidTuning(3.4, 0.002),
             "peppy": PidTuning(2.8, 0.003)})


def calib62_settings(n: int = 24):
    """A sixty-second effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the position sensor alone in rows 0-11 and both sensors in rows 12-23, on SPUNKY,
    SUNNY and PEPPY, at drawn rates 205-820 Hz and torque noise 0.035-0.108 N*m, white in half the
    rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or 0.006 deg/s,
    quantisation 0.001 or 0.0005 deg; seeds 26900 + i."""
    return _effect_free_set("calib62", CALIB41_EXCITATIONS, ["spunky", "sunny", "peppy"],
                            [(True, False), (True, True), (False, True)], [205.0, 655.0, 820.0, 210.0, 445.0],
                            [0.108, 0.035, 0.061], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            26900, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# calib63: the design of the compliance's spaced starts, frozen before its first run: 24 effect-free
# rows on three plants no earlier set used, drawn by calib53's recipe (numpy default_rng(74)), the
# velocity sensor alone in rows 0-11 and the position sensor alone in rows 12-23. None chosen
FEISTY = T.Plant(J=0.167, Fc=0.865, Fs=1.3, vs=0.0568, sigma2=1.152, sigma0=204.0, sigma1=2.33)
BOUNCY = T.Plant(J=0.06, Fc=1.024, Fs=1.629, vs=0.0611, sigma2=1.112, sigma0=274.0, sigma1=1.62)
SNAPPY = T.Plant(J=0.134, Fc=1.184, Fs=1.819, vs=0.0308, sigma2=0.822, sigma0=264.0, sigma1=2.38)
_add_plants({"feisty": (FEISTY, T.VelocityPIController(kp=8.0, ki=48.4)),
             "bouncy": (BOUNCY, T.VelocityPIController(kp=2.9, ki=17.4)),
             "snappy": (SNAPPY, T.VelocityPIController(kp=6.4, ki=38.9))},
            {"feisty": PidTuning(2.9, 0.002),
             "bouncy": PidTuning(3.0, 0.002),
             "snappy": PidTuning(3.0, 0.002)})


def calib63_settings(n: int = 24):
    """A sixty-third effect-free set (issues #30 and #31), fixed and committed before its first run:
    the six excitation kinds (calib41's) x both loops (the position PID without feedforward in every
    fourth row), the velocity sensor alone in rows 0-11 and the position sensor alone in rows 12-23,
    on FEISTY, BOUNCY and SNAPPY, at drawn rates 315-770 Hz and torque noise 0.042-0.086 N*m, white in
    half the rows and AR(1) of coefficient 0.5 or 0.8 in the other half, velocity noise 0.002 or
    0.006 deg/s, quantisation 0.001 or 0.0005 deg; seeds 27000 + i."""
    return _effect_free_set("calib63", CALIB41_EXCITATIONS, ["feisty", "bouncy", "snappy"],
                            [(False, True), (True, False), (True, True)], [485.0, 550.0, 535.0, 315.0, 770.0],
                            [0.086, 0.058, 0.042], [0.0, 0.5, 0.0, 0.8], [0.002, 0.006], [0.001, 0.0005],
                            27000, n, loops=("pid", "pi"), nff=1, plant_k=1, fs_k=2, tn_rule=(1, 4))


# fresh57: the design of the compliance's spaced starts, frozen before its first run: fresh3's 24
# effect rows at rates and variations drawn as fresh52's with numpy default_rng(75). None chosen
_F57_FS = {"a": 390.0, "b": 350.0, "c": 680.0, "d": 695.0, "e": 855.0, "f": 740.0, "g": 850.0, "h": 865.0,
           "i": 815.0}
_F57_VARIED = _varied(-3.0624, 0.986, 2.0298)


def fresh57_settings():
    """A fresh set (issue #30), fixed and committed before its first run: all 24 of fresh3's effect
    rows at 350-865 Hz (by recipe, drawn), seeds 27100 + k, with the gravity's phase, the asymmetry's
    sign and the ripple's period and phase changed by drawn amounts."""
    return _refreshed("fresh57", _F57_FS, _F57_VARIED, 27100)


# each study's rows, fixed before its first run
SETTINGS = {"calib": calib_settings, "fresh3": fresh3_settings, "outside": outside_settings,
            "calib2": calib2_settings, "fresh4": fresh4_settings, "calib3": calib3_settings,
            "fresh5": fresh5_settings, "calib4": calib4_settings, "fresh6": fresh6_settings,
            "calib5": calib5_settings, "outside2": outside2_settings, "calib6": calib6_settings,
            "fresh7": fresh7_settings, "calib7": calib7_settings, "fresh8": fresh8_settings,
            "calib8": calib8_settings, "fresh9": fresh9_settings, "outside3": outside3_settings,
            "calib9": calib9_settings, "fresh10": fresh10_settings, "outside4": outside4_settings,
            "calib10": calib10_settings, "fresh11": fresh11_settings, "outside5": outside5_settings,
            "calib11": calib11_settings, "fresh12": fresh12_settings,
            "calib12": calib12_settings, "fresh13": fresh13_settings,
            "calib13": calib13_settings, "fresh14": fresh14_settings,
            "calib14": calib14_settings, "fresh15": fresh15_settings,
            "calib15": calib15_settings, "fresh16": fresh16_settings, "outside6": outside6_settings,
            "fresh17": fresh17_settings, "outside7": outside7_settings, "calib16": calib16_settings,
            "calib17": calib17_settings, "fresh18": fresh18_settings,
            "calib18": calib18_settings, "fresh19": fresh19_settings, "calib19": calib19_settings,
            "calib20": calib20_settings, "fresh20": fresh20_settings,
            "calib21": calib21_settings, "outside8": outside8_settings, "fresh21": fresh21_settings,
            "calib22": calib22_settings, "fresh22": fresh22_settings,
            "calib23": calib23_settings, "fresh23": fresh23_settings,
            "calib24": calib24_settings, "fresh24": fresh24_settings,
            "calib25": calib25_settings, "fresh25": fresh25_settings,
            "calib26": calib26_settings, "fresh26": fresh26_settings,
            "calib27": calib27_settings, "fresh27": fresh27_settings,
            "calib28": calib28_settings, "fresh28": fresh28_settings,
            "calib29": calib29_settings, "fresh29": fresh29_settings,
            "calib30": calib30_settings, "outside9": outside9_settings,
            "calib31": calib31_settings, "fresh30": fresh30_settings, "calib31cells": calib31_cells_settings,
            "calib30cells": calib30_cells_settings, "calib32pid": calib32pid_settings,
            "calib33": calib33_settings, "fresh31": fresh31_settings,
            "calib34": calib34_settings, "fresh32": fresh32_settings,
            "calib35": calib35_settings, "calib35v": calib35v_settings, "outside10": outside10_settings, "fresh33": fresh33_settings,
            "calib36": calib36_settings, "fresh34": fresh34_settings, "outside11": outside11_settings,
            "calib37": calib37_settings, "outside12": outside12_settings, "fresh35": fresh35_settings,
            "calib38": calib38_settings, "outside13": outside13_settings, "fresh36": fresh36_settings,
            "calib39": calib39_settings, "fresh37": fresh37_settings, "outside14": outside14_settings,
            "calib40": calib40_settings, "fresh38": fresh38_settings, "outside15": outside15_settings,
            "calib41": calib41_settings, "calib42": calib42_settings, "fresh39": fresh39_settings,
            "outside16": outside16_settings, "calib43": calib43_settings, "fresh40": fresh40_settings,
            "outside17": outside17_settings, "calib44": calib44_settings, "calib45": calib45_settings,
            "fresh41": fresh41_settings, "calib46": calib46_settings, "fresh42": fresh42_settings, "calib47": calib47_settings, "outside18": outside18_settings, "calib48": calib48_settings,
            "calib49": calib49_settings, "outside19": outside19_settings, "fresh43": fresh43_settings, "calib50": calib50_settings, "fresh44": fresh44_settings,
            "fresh45": fresh45_settings, "calib51": calib51_settings, "outside20": outside20_settings,
            "outside21": outside21_settings, "fresh46": fresh46_settings,
            "calib52": calib52_settings, "fresh47": fresh47_settings, "calib53": calib53_settings,
            "fresh48": fresh48_settings, "calib54": calib54_settings,
            "fresh49": fresh49_settings, "calib55": calib55_settings,
            "outside22": outside22_settings,
            "fresh50": fresh50_settings, "calib56": calib56_settings, "outside23": outside23_settings,
            "fresh51": fresh51_settings, "calib57": calib57_settings,
            "outside24": outside24_settings, "outside25": outside25_settings,
            "fresh52": fresh52_settings, "calib58": calib58_settings,
            "fresh53": fresh53_settings, "calib59": calib59_settings,
            "fresh54": fresh54_settings, "calib60": calib60_settings, "outside27": outside27_settings,
            "outside26": outside26_settings,
            "fresh55": fresh55_settings, "calib61": calib61_settings, "outside28": outside28_settings,
            "fresh56": fresh56_settings, "calib62": calib62_settings,
            "calib63": calib63_settings, "fresh57": fresh57_settings,
            "null": null_settings, "heldout": heldout_settings, "fresh": fresh_settings}


def jobs(study: str, seeds, strengths):
    if study in SETTINGS:
        return SETTINGS[study]()
    if study == "issue":
        return [{"key": f"issue_{k}", "plant": "issue", "excitation": "staircase", "fs": 200.0,
                 "torque_noise": 0.08, "velocity_noise": 0.003, "quantisation": 0.0005,
                 "velocity_column": True, "effects": k, "seed": 7} for k in ISSUE_EFFECTS]
    out = []
    for st in strengths:
        for k in CONCEALED:
            for sd in seeds:
                out.append({"key": f"proof_{k}_{st}_{sd}", "plant": "issue", "excitation": "staircase_short",
                            "fs": 200.0, "torque_noise": 0.08, "velocity_noise": 0.003, "quantisation": 0.0005,
                            "velocity_column": True, "effects": k, "strength": st, "seed": sd})
    return out


def effects_of(job):
    if "effect_spec" in job:
        known = T.EFFECTS | T.OUTSIDE_EFFECTS
        return [known[eid](**kw) for eid, kw in job["effect_spec"]]
    e = job["effects"]
    if not e:
        return []
    if job["key"].startswith("held_effect"):
        return HELD_EFFECTS[e]
    if job["key"].startswith("fresh_effect"):
        return FRESH_EFFECTS[e]
    if "strength" in job:
        return CONCEALED[e](job["strength"])
    return ISSUE_EFFECTS[e]


def _cache_path(job, cache):
    """Where the generated recording of ``job`` is cached: keyed by the job's settings (effects and
    plant resolved to their parameters, controller included) and the generator's source, so any
    change to either regenerates."""
    if cache is None:
        return None
    extra = {"effects_params": [repr(e) for e in effects_of(job)], "plant_params": repr(controller_of(job))}
    spec = json.dumps({**job, **extra}, sort_keys=True, default=str)
    h = hashlib.sha256((spec + inspect.getsource(inspect.getmodule(T.generate))).encode()).hexdigest()[:16]
    return Path(cache) / f"{job['key']}_{h}.pkl"


def generated(job, cache=None):
    """The job's recording (from the cache where it is there) and the seconds its generation took
    (0 from the cache)."""
    plant, ctrl = controller_of(job)
    sens = T.Sensors(fs=job["fs"], torque_noise=job["torque_noise"], velocity_noise=job["velocity_noise"],
                     quantisation=job["quantisation"], velocity_column=job["velocity_column"],
                     position_column=job.get("position_column", True),
                     torque_noise_hz=job.get("torque_noise_hz", 0.0),
                     torque_noise_ar=job.get("torque_noise_ar", 0.0))
    cached = _cache_path(job, cache)
    if cached is not None and cached.exists():
        return pickle.loads(cached.read_bytes()), 0.0
    t0 = time.time()
    g = T.generate(excitation_of(job["excitation"], job["fs"], job["seed"], job.get("short", False),
                                 job.get("excitation_kw")), effects_of(job),
                   plant, ctrl, sens, seed=job["seed"])
    t_gen = time.time() - t0
    if cached is not None:
        cached.parent.mkdir(parents=True, exist_ok=True)
        tmp = cached.with_suffix(".tmp")
        tmp.write_bytes(pickle.dumps(g))
        tmp.replace(cached)
    return g, t_gen


def design_row(job, g, t_gen):
    """What generation alone shows (no diagnosis): size, tracking, the effect's peak against the
    noise. The concealed level is a peak effect torque below the per-sample torque noise std."""
    et = g.true["effect_torque"]
    if g.position_ref is not None:
        ref = g.position_ref
        err = g.true["theta"] - ref
    else:  # a velocity loop: its error against the velocity reference, relative to its range
        ref, err = g.velocity_ref, g.true["omega"] - g.velocity_ref
    return {"key": job["key"], "n_samples": int(g.time.size), "duration_s": float(g.time[-1]),
            "controller_kind": g.settings["controller_kind"],
            "true_torque_noise_std": g.torque_noise_std,
            "true_peak_nm": float(np.max(np.abs(et))), "true_rms_nm": float(np.sqrt(np.mean(et ** 2))),
            "peak_over_noise": float(np.max(np.abs(et)) / g.torque_noise_std) if g.torque_noise_std > 0 else None,
            "tracking_rms_over_range": float(np.sqrt(np.mean(err ** 2)) / max(np.ptp(ref), 1e-12)),
            "position_span_deg": float(np.ptp(g.true["theta"])),
            "max_speed_deg_s": float(np.max(np.abs(g.true["omega"]))), "seconds_generate": t_gen}


def _plain(x):
    """A JSON-able copy of a report's part (its ``to_json`` where it has one)."""
    if hasattr(x, "to_json"):
        return x.to_json()
    if dataclasses.is_dataclass(x):
        return dataclasses.asdict(x)
    return getattr(x, "__dict__", str(x))


def run_new(job, top_k, cache=None):
    """A row of the calib, fresh3 and outside studies: the verdict against the expected one, the
    floor against the TRUE torque noise std of the recording, and the report's missing physics
    whole (whatever fields the report has: the outside study reads the residual's attribution)."""
    from lugre_jax.diagnose import diagnose

    g, t_gen = generated(job, cache)
    rec = g.to_recording()
    t0 = time.time()
    rep = diagnose(rec, progress=False, top_k=top_k)
    secs = time.time() - t0
    b = rep.baseline
    named = list(rep.named)
    floor = float(b.noise_floor_nm)
    row = {**job, **design_row(job, g, t_gen), "verdict": rep.verdict, "named": named,
           "noise_floor": floor, "floor_over_true_noise": floor / g.torque_noise_std,
           "floor_ratio": getattr(b, "floor_ratio", None), "baseline_val_rmse": getattr(b, "validation_rmse_nm", None),
           "improved_val_rmse": getattr(getattr(rep, "improved", None), "validation_rmse_nm", None),
           "baseline": _plain(b), "missing_physics": [_plain(m) for m in rep.missing_physics],
           "attribution": rep.attribution,
           "seconds_diagnose": secs}
    row["correct"] = rep.verdict == job["expected"]
    # what a miss is made of: the baseline's residual less the true torque noise (the effect it left,
    # with the kinematics' imprint), RMS over resolved training rows in noise std, and the first
    # step's tests and refits as the report logs them
    r0, noise = np.asarray(rep.arrays.r0), g.true.get("torque_noise")
    if noise is not None and len(noise) == len(r0):
        train = (r0 != 0) & ~np.asarray(rep.arrays.val)
        row["baseline_misfit_over_noise"] = float(np.sqrt(np.mean((r0 - np.asarray(noise))[train] ** 2))
                                                  / g.torque_noise_std)
        if job.get("effects") and job["expected"] not in ("none", "unexplained"):
            # what a test knowing the effect's shape could see on the samples the fit kept
            from oracle_power import oracle

            row["oracle_lam_kept"] = oracle(g, true_params(job), float(job["torque_noise_ar"]), rows=train)["lam"]
    if rep.selection_log:
        row["step1_tests"] = rep.selection_log[0]["tests"]
        row["step1_refits"] = rep.selection_log[0]["joint_refits"]
        # where a moved hump sent the selection down two paths: which was kept, and what each named
        row["hump_restarts"] = [{"step": e["step"], "kept": e.get("hump_restarted"), **e["hump_restart_paths"]}
                                for e in rep.selection_log if "hump_restart_paths" in e]
    return row


def run_one(job, top_k, cache=None):
    if "expected" in job:
        return run_new(job, top_k, cache)
    from lugre_jax.diagnose import diagnose

    effs = effects_of(job)
    g, t_gen = generated(job, cache)
    rec = g.to_recording()
    t0 = time.time()
    rep = diagnose(rec, progress=False, top_k=top_k)
    b = rep.baseline
    named = rep.named
    truth = sorted(e.id for e in effs)
    row = {**job, "n_samples": rec.n, "verdict": rep.verdict, "named": named, "validation": rep.recording.validation,
           "true_effects": truth, "true_peak_nm": float(np.max(np.abs(g.true["effect_torque"]))),
           "true_rms_nm": float(np.sqrt(np.mean(g.true["effect_torque"] ** 2))),
           "baseline_val_rmse": b.validation_rmse_nm, "noise_floor": b.noise_floor_nm,
           "floor_ratio": b.floor_ratio, "conditioning": b.conditioning,
           "baseline_params": b.params, "improved_val_rmse": rep.improved.validation_rmse_nm,
           "n_located": len(rep.mismatch), "seconds_diagnose": time.time() - t0, "seconds_generate": t_gen,
           "true_params": [e.__dict__ | {"id": e.id} for e in effs],
           "fitted": {m.name: m.params for m in rep.missing_physics},
           "located": [{"test": m.test, "region": m.region, "p_holm": m.p_holm} for m in rep.mismatch][:5],
           "selection_log": rep.selection_log}
    row["correct"] = sorted(n for n in named if n != "unexplained") == truth and "unexplained" not in named
    return row


NEW_STUDIES = ("calib", "fresh3", "outside", "calib2", "fresh4", "calib3", "fresh5", "calib4", "fresh6", "calib5",
               "outside2", "calib6", "fresh7", "calib7",
               "fresh8", "calib8", "fresh9", "outside3", "calib9", "fresh10", "outside4",
               "calib10", "fresh11", "outside5", "calib11", "fresh12",
               "calib12", "fresh13", "calib13", "fresh14", "calib14", "fresh15", "calib15", "fresh16",
               "outside6", "fresh17", "outside7", "calib16", "calib17", "fresh18", "calib18",
               "fresh19", "calib19", "calib20", "fresh20", "calib21", "outside8", "fresh21", "calib22",
               "fresh22", "calib23", "fresh23", "calib24", "fresh24", "calib25", "fresh25",
               "calib26", "fresh26", "calib27", "fresh27", "calib28", "fresh28", "calib29", "fresh29",
               "calib30", "outside9", "calib31", "fresh30",
               "calib31cells", "calib30cells", "calib32pid", "calib33", "fresh31",
               "calib34", "fresh32", "calib35", "outside10", "fresh33", "calib35v", "calib36", "fresh34", "outside11", "calib37", "outside12", "fresh35",
               "calib38", "outside13", "fresh36", "calib39", "fresh37", "outside14", "calib40",
               "fresh38", "outside15", "calib41", "calib42", "fresh39", "outside16", "calib43",
               "fresh40", "outside17", "calib44", "calib45", "fresh41", "calib46", "fresh42", "calib47",
               "outside18", "calib48", "calib49", "outside19", "fresh43", "calib50", "fresh44", "fresh45", "calib51",
               "outside20", "outside21", "fresh46", "calib52", "fresh47", "calib53", "fresh48", "calib54",
               "fresh49", "calib55", "outside22",
               "fresh50", "calib56", "outside23", "fresh51", "calib57",
               "outside24", "outside25", "fresh52", "calib58", "fresh53", "calib59", "outside26",
               "fresh54", "calib60", "outside27", "fresh55", "calib61", "outside28", "fresh56", "calib62",
               "calib63", "fresh57")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", choices=("null", "issue", "proof", "heldout", "fresh") + NEW_STUDIES, required=True)
    ap.add_argument("--out", default=None,
                    help="results folder (default results/, results/<study> for calib, fresh3 and outside)")
    ap.add_argument("--shard", default="0/1", help="i/n: run every n-th job starting at i")
    ap.add_argument("--seeds", default="11")
    ap.add_argument("--strengths", default="1,0.5")
    ap.add_argument("--top-k", type=int, default=4)
    ap.add_argument("--only", default="", help="comma-separated job keys to run (default: all)")
    ap.add_argument("--cache", default=None, help="generated-recording cache (default <out>/cache; 'none': off)")
    ap.add_argument("--generate-only", action="store_true",
                    help="generate (and cache) the recordings and write what generation shows (tracking, "
                         "the effect's peak against the noise) to <out>/design_<study>.jsonl; no diagnosis")
    a = ap.parse_args()
    try:
        i, n = (int(x) for x in a.shard.split("/"))
        if not 0 <= i < n:
            raise ValueError
    except ValueError:
        ap.error(f"--shard: expected i/n with 0 <= i < n, got {a.shard!r}")
    here = Path(__file__).resolve().with_name("results")
    out = Path(a.out) if a.out else (here / a.study if a.study in NEW_STUDIES else here)
    out.mkdir(parents=True, exist_ok=True)
    path = out / (f"design_{a.study}.jsonl" if a.generate_only else f"runs_{a.study}.jsonl")
    refused = out / f"refused_{a.study}.jsonl"  # recordings the diagnosis refuses, with its one line
    done = set()
    for f in (path, refused):
        if f.exists():
            done |= {json.loads(line)["key"] for line in f.read_text().splitlines() if line.strip()}
    todo = [j for k, j in enumerate(jobs(a.study, [int(x) for x in a.seeds.split(",")],
                                         [float(x) for x in a.strengths.split(",")]))
            if k % n == i and j["key"] not in done and (not a.only or j["key"] in a.only.split(","))]
    cache = None if a.cache == "none" else Path(a.cache or out / "cache")
    for job in todo:
        if a.generate_only:
            g, t_gen = generated(job, cache)
            row = {**job, **design_row(job, g, t_gen)}
            with open(path, "a") as fh:
                fh.write(json.dumps(row, default=float) + "\n")
            print(f"{row['key']}: n {row['n_samples']}, peak/noise {row['peak_over_noise']:.2f}, tracking "
                  f"{row['tracking_rms_over_range']:.3f} of the range, {t_gen:.1f} s", flush=True)
            continue
        try:
            row = run_one(job, a.top_k, cache)
        except ValueError as e:  # a recording the diagnosis refuses (too few resolved samples): said, not run
            with open(refused, "a") as fh:
                fh.write(json.dumps({"key": job["key"], "refused": str(e)}) + "\n")
            print(f"{job['key']}: refused ({e})", flush=True)
            continue
        with open(path, "a") as fh:  # one complete line per run: a killed run loses only itself
            fh.write(json.dumps(row, default=float) + "\n")
        ratio = row.get("floor_over_true_noise", row.get("floor_ratio"))
        print(f"{row['key']}: {row['verdict']} (expected {row.get('expected', row.get('true_effects'))}) "
              f"ratio {ratio:.3f} {row['seconds_diagnose']:.0f} s", flush=True)


if __name__ == "__main__":
    main()
