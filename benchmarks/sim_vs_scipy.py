"""The batched simulator against a careful user's scipy loop, at matched accuracy (issue #33's table).

    python benchmarks/sim_vs_scipy.py [--lanes 2000] [--scipy-lanes 20] [--tight-lanes N] [--stiff]
                                      [--rows default,default_theta,adaptive,lane,tsit2]
                                      [--out benchmarks/results/sim_vs_scipy_2000.json]

The scenario: the paper's joint (J 0.128, segment 1 of Tables 1-2) under velocity PI (kp 8, ki 60),
a staircase 0.02 / 0.1 / -0.05 / 0.5 deg/s with sharp steps every 5 s, 20 s at 100 Hz; per lane Fs
drawn in [3, 8] N*m and sigma0 in [50, 200] N*m/deg (seed 0). The scipy loop is what a careful user
writes: ``solve_ivp`` LSODA at rtol 1e-6, atol 1e-9, restarted at each step of the staircase, one
lane after another (timed on ``--scipy-lanes`` lanes, per solve). Every row is scored against a
tight solve (``Adaptive(Tsit5(), rtol=1e-11, atol=1e-13)``, itself checked against scipy Radau at
rtol 1e-11 in tests/test_simulate_reference.py) on ``--tight-lanes`` lanes spread over the batch
(default: all). Batched rows are timed as the best of two calls after compilation, in this process,
through the public API only. Prints one line per row and writes the JSON.

``--stiff``: stiff bristles instead, sigma0 drawn in [1e3, 1e4] N*m/deg and sigma1 in [2.3, 30]
N*m*s/deg per lane (sigma0*|v|/g(v) up to ~5e3 1/s at 0.5 deg/s); the tight solve is then
``Adaptive(Kvaerno5(), rtol=1e-10, atol=1e-12)`` (implicit: Tsit5 at rtol 1e-11 takes too many
steps on these lanes) and the scipy loop is the same LSODA loop (it switches to BDF where stiff).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

import lugre_jax as lj
from _timing import best_of
from lugre_jax.testing import velocity_staircase

ROOT = Path(__file__).resolve().parents[1]
LEVELS, DWELL, DURATION, HZ = (0.02, 0.1, -0.05, 0.5), 5.0, 20.0, 100.0
KP, KI = 8.0, 60.0
# the positions alone (what the rows are scored on), computed where each sample is interpolated
POSITIONS = lj.SaveAt(fn=lambda sample: sample.theta)


def draw(lanes: int, seed: int = 0, stiff: bool = False):
    """``(Fs, sigma0, sigma1)`` per lane; ``sigma1`` is the paper's unless ``stiff``."""
    rng = np.random.default_rng(seed)
    Fs = rng.uniform(3.0, 8.0, lanes)
    if not stiff:
        return Fs, rng.uniform(50.0, 200.0, lanes), np.full(lanes, float(lj.paper_segment(1).sigma1))
    return Fs, rng.uniform(1e3, 1e4, lanes), rng.uniform(2.3, 30.0, lanes)


def batch(Fs, sigma0, sigma1):
    import equinox as eqx
    import jax.numpy as jnp

    one = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=lj.PAPER_J),
                    controller=lj.VelocityPID(kp=KP, ki=KI), reference=lj.VelocitySteps(list(LEVELS), dwell_s=DWELL))
    sys_b = lj.broadcast_system(one, len(Fs))
    return eqx.tree_at(lambda s: (s.friction.Fs, s.friction.sigma0, s.friction.sigma1), sys_b,
                       (jnp.asarray(Fs), jnp.asarray(sigma0), jnp.asarray(sigma1)))


def scipy_loop(Fs: float, sigma0: float, s1: float, rtol=1e-6, atol=1e-9, method="LSODA"):
    """One lane as a careful scipy user solves it: restarted at each step of the staircase."""
    seg = lj.paper_segment(1)
    _, states = velocity_staircase(lj.PAPER_J, float(seg.Fc), Fs, float(seg.vs), sigma0, s1, float(seg.sigma2),
                                   KP, KI, LEVELS, DWELL, DURATION, HZ, method=method, rtol=rtol, atol=atol)
    return states[:, 0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lanes", type=int, default=2000)
    ap.add_argument("--scipy-lanes", type=int, default=20)
    ap.add_argument("--tight-lanes", type=int, default=None, help="lanes scored against the tight solve")
    ap.add_argument("--rows", default="default,default_theta,adaptive,lane,tsit2",
                    help="batched rows to run (also: lane_theta, bosh3, tsit5, exp, exp5, exp2, tsit125, exp125, tsit1, exp1, "
                         "tsit0625, exp0625, tsit05, exp05)")
    ap.add_argument("--stiff", action="store_true", help="stiff bristles: sigma0 in [1e3, 1e4], sigma1 in [2.3, 30]")
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    lj.configure(host_devices=2)
    import diffrax
    import jax

    Fs, sigma0, sigma1 = draw(a.lanes, stiff=a.stiff)
    system = batch(Fs, sigma0, sigma1)
    n_tight = a.lanes if a.tight_lanes is None else min(a.tight_lanes, a.lanes)
    picked = np.unique(np.linspace(0, a.lanes - 1, n_tight).round().astype(int))
    t0 = time.perf_counter()
    tight_stepping = (lj.Adaptive(diffrax.Kvaerno5(), rtol=1e-10, atol=1e-12, max_steps=1_000_000) if a.stiff
                      else lj.Adaptive(rtol=1e-11, atol=1e-13))
    tight_sol = lj.simulate(batch(Fs[picked], sigma0[picked], sigma1[picked]), DURATION, HZ, batched=True,
                            stepping=tight_stepping)
    if not np.all(np.asarray(tight_sol.result) == lj.RESULT_OK):
        raise SystemExit("the tight solve failed on some lanes")
    tight = np.asarray(tight_sol.theta)
    tight_s = time.perf_counter() - t0
    print(f"tight solve of {len(picked)} lanes: {tight_s:.1f} s", flush=True)

    rows = []
    sl = picked[np.unique(np.linspace(0, len(picked) - 1, min(a.scipy_lanes, len(picked))).round().astype(int))]
    t = time.perf_counter()
    errs = [np.max(np.abs(scipy_loop(Fs[i], sigma0[i], sigma1[i]) - tight[np.searchsorted(picked, i)])) for i in sl]
    per = (time.perf_counter() - t) / len(sl)
    rows.append(dict(row="scipy loop (LSODA rtol 1e-6 atol 1e-9, restarted per step)", per_solve_ms=1e3 * per,
                     speedup=1.0, max_err_deg=float(max(errs)), lanes_scored=len(sl)))
    print(f"{rows[-1]['row']:60s} {1e3 * per:9.3f} ms/solve  err {max(errs):.1e} deg", flush=True)

    choices = {"default": ("lj.simulate(..., batched=True), no stepping given", None),
               "adaptive": ("Adaptive() (Tsit5, rtol 1e-8, atol 1e-10)", lj.Adaptive()),
               "bosh3": ("FixedStep(Bosh3(), dt=0.005)", lj.FixedStep(diffrax.Bosh3(), dt=0.005)),
               "lane": ("LaneAdaptive() (Tsit5, rtol 1e-6, atol 1e-9)", lj.LaneAdaptive()),
               "lane_theta": ("LaneAdaptive(), positions only: SaveAt(fn=theta)", lj.LaneAdaptive(), POSITIONS),
               "default_theta": ("no stepping given, positions only: SaveAt(fn=theta)", None, POSITIONS),
               "tsit5": ("FixedStep(Tsit5(), dt=0.0025)", lj.FixedStep(diffrax.Tsit5(), dt=0.0025)),
               "exp": ("ExponentialBristle(Tsit5(), dt=0.0025)", lj.ExponentialBristle(diffrax.Tsit5(), dt=0.0025)),
               "tsit2": ("FixedStep(Tsit5(), dt=0.002)", lj.FixedStep(diffrax.Tsit5(), dt=0.002)),
               "exp2": ("ExponentialBristle(Tsit5(), dt=0.002)", lj.ExponentialBristle(diffrax.Tsit5(), dt=0.002)),
               "exp5": ("ExponentialBristle(Tsit5(), dt=0.005)", lj.ExponentialBristle(diffrax.Tsit5(), dt=0.005)),
               "tsit125": ("FixedStep(Tsit5(), dt=0.00125)", lj.FixedStep(diffrax.Tsit5(), dt=0.00125)),
               "exp125": ("ExponentialBristle(Tsit5(), dt=0.00125)",
                          lj.ExponentialBristle(diffrax.Tsit5(), dt=0.00125)),
               "tsit0625": ("FixedStep(Tsit5(), dt=0.000625)", lj.FixedStep(diffrax.Tsit5(), dt=0.000625)),
               "exp0625": ("ExponentialBristle(Tsit5(), dt=0.000625)",
                           lj.ExponentialBristle(diffrax.Tsit5(), dt=0.000625)),
               "exp1": ("ExponentialBristle(Tsit5(), dt=0.001)", lj.ExponentialBristle(diffrax.Tsit5(), dt=0.001)),
               "tsit1": ("FixedStep(Tsit5(), dt=0.001)", lj.FixedStep(diffrax.Tsit5(), dt=0.001)),
               "exp05": ("ExponentialBristle(Tsit5(), dt=0.0005)", lj.ExponentialBristle(diffrax.Tsit5(), dt=0.0005)),
               "tsit05": ("FixedStep(Tsit5(), dt=0.0005)", lj.FixedStep(diffrax.Tsit5(), dt=0.0005))}
    for key in a.rows.split(","):
        label, stepping, *saveat = choices[key]
        saveat = saveat[0] if saveat else lj.SaveAt()

        def run():
            out = lj.simulate(system, DURATION, HZ, batched=True, stepping=stepping, saveat=saveat)
            return out, (out.theta if saveat.fn is None else out.value)

        t = time.perf_counter()
        sol, theta = run()
        theta = np.asarray(theta)
        first = time.perf_counter() - t
        wall = best_of(lambda: jax.block_until_ready(run()[1]), 2)
        # a lane that blew up counts as infinitely far (never as within tolerance)
        err = np.max(np.abs(theta[picked] - tight), axis=1)
        err = np.where(np.isfinite(err) & (np.asarray(sol.result)[picked] == lj.RESULT_OK), err, np.inf)
        ok = int(np.sum(np.asarray(sol.result) == lj.RESULT_OK))
        rows.append(dict(row=label, per_solve_ms=1e3 * wall / a.lanes, speedup=per / (wall / a.lanes),
                         max_err_deg=float(err.max()), median_err_deg=float(np.median(err)),
                         lanes_within_2e6=int(np.sum(err <= 2e-6)), lanes_scored=len(picked),
                         first_call_s=first, call_s=wall, lanes_ok=ok))
        r = rows[-1]
        print(f"{label:60s} {r['per_solve_ms']:9.4f} ms/solve  {r['speedup']:6.1f}x the loop  err max "
              f"{r['max_err_deg']:.1e} deg ({r['lanes_within_2e6']}/{len(picked)} lanes <= 2e-6)  "
              f"call {wall:.2f} s (first {first:.1f} s)", flush=True)
    result = dict(command="python benchmarks/sim_vs_scipy.py " + " ".join(argv or []), lanes=a.lanes,
                  scenario="stiff: sigma0 in [1e3, 1e4], sigma1 in [2.3, 30]" if a.stiff else
                  "sigma0 in [50, 200], sigma1 2.3042 (paper segment 1)",
                  device=f"{jax.devices()[0].platform}: {platform.processor() or platform.machine()}, "
                         f"{os.cpu_count()} cores, {len(jax.devices())} XLA devices",
                  jax=jax.__version__, loadavg=os.getloadavg(), tight_s=tight_s, rows=rows)
    out = Path(a.out or ROOT / "benchmarks" / "results" /
               f"sim_vs_scipy_{'stiff_' if a.stiff else ''}{a.lanes}.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1))
    print(out)


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
