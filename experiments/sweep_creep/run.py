"""Which friction parameters and gains govern creep and the dead zone (results the paper lacks).

A. Sobol' indices (S1, ST, 95 % bootstrap intervals) of the 0.005 deg/s dead zone, creep amplitude,
   +-0.001 deg/s band fraction and stick-slip flag w.r.t. the six LuGre parameters and the PI gains
   (SPEC: experiments/scenarios/sweep_creep_sobol.json; the paper's low-velocity friction segment,
   Table 1, J = 0.128, PI kp = 8, ki = 60, each parameter over a box around it).
B. Minimum stable velocity over (sigma0, Fs - Fc) and ki: one grid sweep per commanded velocity of a
   ladder; a grid point's minimum stable velocity is the lowest command from which on every higher
   command of the ladder runs without stick-slip (velocity never below 10 % of the command in the
   last half of the run). Each run lasts long enough to travel three times the largest pre-sliding
   deflection of the grid (Fs/sigma0 <= 0.3 deg), at least 30 s: a shorter run at 0.001 deg/s
   would end while the bristles still deflect and look "smooth" without ever breaking away.

    python experiments/sweep_creep/run.py [--out DIR] [--n 4096] [--quick]
    python experiments/sweep_creep/plot.py [--out DIR]

Writes OUT/sobol/ (a `lugre-jax sweep` folder: indices.json, outputs, tornado plots),
OUT/stepping_check.json, OUT/msv/v*/ (one grid sweep per velocity) and OUT/msv.json.
Rerunning resumes the sweeps.
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SPEC = HERE.parent / "scenarios" / "sweep_creep_sobol.json"
VELOCITIES = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0)  # deg/s
MSV_GRID = {"names": ["friction.sigma0", "friction.Fs", "controller.ki"],
            "bounds": [[30.0, 500.0], [1.415, 8.915], [20.0, 120.0]],  # Fs - Fc from 0.5 to 8 N*m (Fc 0.915)
            "levels": [10, 10, 4]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--n", type=int, default=None, help="Sobol' base points (power of two; default the SPEC's)")
    ap.add_argument("--quick", action="store_true", help="n = 256 and a 5x5x2 grid")
    a = ap.parse_args(argv)
    import lugre_jax as lj

    lj.configure(host_devices=2)
    from lugre_jax.io import write_json
    from lugre_jax.sweep import batch_system, run_sweep, spec_from_dict

    out = Path(a.out)
    base = json.loads(SPEC.read_text())
    if a.n or a.quick:
        base["n"] = a.n or 256
    t0 = time.perf_counter()
    spec = spec_from_dict(base, str(SPEC), SPEC.parent)
    res = run_sweep(spec, out / "sobol")
    t_sobol = time.perf_counter() - t0
    # Is the fast step accurate enough over this box? Re-solve 8 sampled lanes with the tight
    # adaptive reference and compare trajectories.
    X = np.load(out / "sobol" / "samples.npy")
    pick = X[np.linspace(0, len(X) - 1, 8).round().astype(int)]
    chk = lj.check_stepping(batch_system(spec.system, list(spec.paths), pick), spec.duration_s, spec.sample_hz,
                            spec.fast, batched=True, n_lanes=8)
    write_json(out / "stepping_check.json", chk.to_json())

    # B: minimum stable velocity.
    levels = [5, 5, 2] if a.quick else MSV_GRID["levels"]
    scen = copy.deepcopy(base["scenario"])
    travel = 3 * MSV_GRID["bounds"][1][1] / MSV_GRID["bounds"][0][0]  # deg
    t1 = time.perf_counter()
    flags, durations = [], []
    for v in VELOCITIES:
        T = float(max(30.0, np.ceil(travel / v / 10) * 10))
        hz = 100 if T <= 60 else 10 if T <= 600 else 5  # at most 6,000 samples per lane in memory
        durations.append(T)
        s = dict(scenario=dict(scen, reference={"type": "velocity_step", "velocity_deg_s": v}, duration_s=T,
                               sample_hz=hz),
                 problem={k: MSV_GRID[k] for k in ("names", "bounds")}, sampler="grid", n=2, levels=levels,
                 seed=0, outputs=[{"metric": "stick_slip", "window": 0.5}, {"metric": "creep_amplitude", "window": 0.5}],
                 stepping=base["stepping"], chunk_size=512)
        r = run_sweep(spec_from_dict(s, f"msv v={v}"), out / "msv" / f"v{v:g}", figures=False)
        with np.load(out / "msv" / f"v{v:g}" / "outputs.npz") as z:
            Xg, Y, st = z["X"], z["Y"], z["status"]
        # A point that failed both solvers counts as not stable (and is reported).
        flags.append(np.where(st == 2, 1.0, Y[:, 0]))
        print(f"v={v:g} deg/s: stick-slip at {int(np.nansum(flags[-1]))} of {len(st)} points; status {r.status_counts}")
    stick = np.stack(flags)  # (velocities, points)
    stable_from = np.full(stick.shape[1], np.inf)
    chain = np.ones(stick.shape[1], bool)  # stable at every command from the top down to here
    for k in range(len(VELOCITIES) - 1, -1, -1):
        chain &= stick[k] == 0
        stable_from = np.where(chain, VELOCITIES[k], stable_from)
    # With the paper's Gaussian Stribeck curve (delta = 2) friction is flat at v -> 0, so stick-slip
    # is a band of velocities: also record where it starts.
    lowest_unstable = np.array([min((v for v, f in zip(VELOCITIES, col) if f != 0), default=np.nan) for col in stick.T])
    write_json(out / "msv.json", dict(
        velocities_deg_s=list(VELOCITIES), durations_s=durations, names=MSV_GRID["names"], levels=levels,
        sigma0=np.unique(Xg[:, 0]), Fs_minus_Fc=np.unique(Xg[:, 1]) - 0.915, ki=np.unique(Xg[:, 2]),
        min_stable_velocity_deg_s=stable_from.reshape(levels),
        lowest_stick_slip_velocity_deg_s=lowest_unstable.reshape(levels), stick_slip=stick.reshape((len(VELOCITIES), *levels)),
        definition="lowest command of the ladder from which on no command shows stick-slip (omega < 0.1*v "
                   "in the last half of the run); inf: stick-slip up to 1 deg/s. lowest_stick_slip_velocity: the lowest "
                   "command with stick-slip (NaN: none); below it the joint creeps smoothly again",
        seconds=time.perf_counter() - t1))
    print(json.dumps(dict(sobol_seconds=t_sobol, sobol_points=res.n_points, status=res.status_counts,
                          msv_seconds=time.perf_counter() - t1)))


if __name__ == "__main__":
    main()
