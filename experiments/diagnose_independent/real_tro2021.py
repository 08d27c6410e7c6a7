"""``diagnose`` on the TRO2021 steady-state sweeps (Mablekos-Alexiou et al., IEEE T-RO 2021): each
drive's constant-velocity runs, in the order they were recorded (EPOS ``Date:`` header), chained
into one recording.

The files carry velocity and torque only (19.5 Hz, 500 samples per run). Position is the running
integral of the measured velocity (trapezoid, chained across runs), marked not measured, so that the
kinematics are conditioned from the velocity (an integral's noise is a random walk, not the white
per-sample noise the conditioning assumes of a position sensor); acceleration is zero (each run holds
one set-point: the protocol is steady state); the baseline is the static Stribeck law
(``friction="stribeck"``, eq. 10), since steady-state runs carry no pre-sliding dynamics, with an
offset. What the tool can see here: asymmetry, drift over the session, position ripple (screw lead),
a Stribeck shape; it must not claim dynamics (compliance, backlash, load dependence) it cannot see.

    python experiments/diagnose_independent/real_tro2021.py [--data ../shared/data]
"""

from __future__ import annotations

import argparse
import datetime as dt
import sys
from pathlib import Path

import numpy as np

import lugre_jax
from lugre_jax.diagnose import diagnose, plot_report
from lugre_jax.io import load_epos_file, recording_from_arrays, write_json

lugre_jax.configure()


def chained(folder: Path):
    runs = []
    for f in sorted(folder.glob("*.csv")):
        r = load_epos_file(f)
        stamp = (r.header.get("Date") or [""])[0]
        try:
            t0 = dt.datetime.strptime(stamp.strip(), "%Y-%m-%d %H:%M:%S").timestamp()
        except ValueError:
            t0 = float("nan")
        runs.append((t0, f.name, r))
    runs.sort(key=lambda x: (np.nan_to_num(x[0], nan=np.inf), x[1]))
    t_all, v_all, y_all, names = [], [], [], []
    t_off = 0.0
    base = runs[0][0] if np.isfinite(runs[0][0]) else 0.0
    for t0, name, r in runs:
        start = (t0 - base) if np.isfinite(t0) else t_off
        start = max(start, t_off)  # strictly increasing even if two runs share a stamp
        t = start + r.time - r.time[0]
        t_all.append(t)
        v_all.append(r.velocity)
        y_all.append(r.torque)
        names.append(name)
        t_off = t[-1] + 1.0
    t, v, y = (np.concatenate(x) for x in (t_all, v_all, y_all))
    pos = np.zeros_like(t)
    # position within runs by the trapezoid; none accrues in the gaps between runs
    starts = np.cumsum([0] + [len(x) for x in t_all])[:-1]
    inc = 0.5 * (v[1:] + v[:-1]) * np.diff(t)
    inc[starts[1:] - 1] = 0.0
    pos[1:] = np.cumsum(inc)
    # the zero acceleration is this script's assumption (constant-velocity runs), not a signal that
    # came with the data, so the diagnosis may condition the kinematics from the samples instead
    rec = recording_from_arrays(t, pos, v, y, acceleration=np.zeros_like(t), source=str(folder),
                                meta={"acceleration_supplied": False, "position_measured": False})
    return rec, names


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--out", default=str(Path(__file__).resolve().with_name("results") / "tro2021"))
    ap.add_argument("--drives", default="driveNo1,driveNo3", help="comma-separated drive folders")
    a = ap.parse_args()
    root = Path(a.data) / "tro2021"
    if not root.exists():
        print(f"TRO2021 data not found at {root}; skipping (pass --data)")
        return 0
    out = Path(a.out)
    for drive in a.drives.split(","):
        folder = root / drive / "steady_state" / "0.096kg"
        rec, names = chained(folder)
        rep = diagnose(rec, friction="stribeck", fit_offset=True, progress=False, block_s=25.6)
        write_json(out / f"report_{drive}.json", rep.to_json())
        plot_report(rep, rec, out / drive)
        b = rep.baseline
        print(f"{drive}: {rec.n} samples from {len(names)} runs; verdict {rep.verdict}; baseline validation "
              f"RMSE {b.validation_rmse_nm:.4g} N*m (floor {b.noise_floor_nm:.4g}, ratio {b.floor_ratio:.3g}) "
              f"-> {rep.improved.validation_rmse_nm:.4g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
