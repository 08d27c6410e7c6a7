"""Effect-free recordings whose torque noise is not AR(1): does the diagnosis still say `none`?

The null the diagnosis simulates holds AR(1) torque noise (docs/diagnosis.md). Real drives add
other colours: a sensor's white noise on top of a filtered current (ARMA(1,1)), or a second-order
anti-alias filter. This set, fixed before its first run, takes calib40's first 12 rows (six
excitations x both loops, both sensors, GRITTY/SPRIGHTLY/STOLID, 280-760 Hz), generates each without
torque noise and adds noise of the row's std (seeded, 21100 + i) of one of two colours:

* ``arma`` (even rows): half the variance white, half AR(1) of coefficient 0.85;
* ``butter2`` (odd rows): white noise through a second-order Butterworth low-pass at fs/12
  (``scipy.signal``), rescaled to the std.

colour2, fixed before its first run (for the broader noise colours of 34bc953; colour1 showed the
need, so it is not held out for them): calib38's rows 12-23 (both sensors; SKINNY, PUDGY, BOXY),
seeds 21200 + i, the colour cycling over

* ``butter4``: a fourth-order Butterworth low-pass at fs/10;
* ``cheby``: a second-order Chebyshev type I (1 dB ripple) at fs/8;
* ``white_ar07``: 30 % of the variance white, 70 % AR(1) of coefficient 0.7;
* ``butter2_fs6``: a second-order Butterworth at fs/6.

Writes ``results/<study>/runs_<study>.jsonl`` (one line a row: verdict, the floor and the torque
noise estimate over the noise's true std, seconds) and prints a summary line.

    python experiments/diagnose_independent/noise_colour.py --study colour1 --shard 0/2   # and 1/2
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np
from scipy import signal

import run as R


def coloured_noise(kind: str, n: int, std: float, fs: float, seed: int) -> np.ndarray:
    """``n`` samples of torque noise of std ``std``: ``arma`` or ``butter2`` (module docstring)."""
    rng = np.random.default_rng(seed)
    burn = 2000
    w = rng.standard_normal(n + burn)
    if kind in ("arma", "white_ar07"):
        phi, white = (0.85, 0.5) if kind == "arma" else (0.7, 0.3)
        ar = signal.lfilter([np.sqrt(1 - phi ** 2)], [1.0, -phi], rng.standard_normal(n + burn))
        x = np.sqrt(white) * w + np.sqrt(1.0 - white) * ar
    elif kind == "butter2":
        x = signal.sosfilt(signal.butter(2, fs / 12.0, fs=fs, output="sos"), w)
    elif kind == "butter2_fs6":
        x = signal.sosfilt(signal.butter(2, fs / 6.0, fs=fs, output="sos"), w)
    elif kind == "butter4":
        x = signal.sosfilt(signal.butter(4, fs / 10.0, fs=fs, output="sos"), w)
    elif kind == "cheby":
        x = signal.sosfilt(signal.cheby1(2, 1.0, fs / 8.0, fs=fs, output="sos"), w)
    else:
        raise ValueError(f"kind: expected one of {COLOURS}, got {kind!r}")
    x = x[burn:]
    return std * x / np.std(x)


COLOURS = ("arma", "butter2", "butter4", "cheby", "white_ar07", "butter2_fs6")


def rows(study: str = "colour1") -> list[dict]:
    """The study's rows without torque noise in the generator; the colour and seed of the added noise."""
    if study == "colour1":
        base, colours, seed0 = R.SETTINGS["calib40"]()[:12], ("arma", "butter2"), 21100
    elif study == "colour2":
        base, colours, seed0 = R.SETTINGS["calib38"]()[12:24], ("butter4", "cheby", "white_ar07", "butter2_fs6"), 21200
    else:
        raise ValueError(f"study: expected colour1 or colour2, got {study!r}")
    out = []
    for i, job in enumerate(base):
        out.append(job | {"key": f"{study}_{i:02d}_{job['excitation']}_{job['controller']}",
                          "noise_std": job["torque_noise"], "torque_noise": 0.0, "torque_noise_ar": 0.0,
                          "colour": colours[i % len(colours)], "noise_seed": seed0 + i})
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", default="colour1", choices=("colour1", "colour2"))
    ap.add_argument("--shard", default="0/1", help="i/n: every n-th row starting at i")
    ap.add_argument("--cache", default=None, help="generated-recording cache (default <out>/cache)")
    ap.add_argument("--out", default=None, help="output folder (default results/colour1)")
    a = ap.parse_args()
    import lugre_jax
    from lugre_jax.diagnose import diagnose

    lugre_jax.configure()
    out = Path(a.out) if a.out else Path(__file__).resolve().with_name("results") / a.study
    out.mkdir(parents=True, exist_ok=True)
    cache = Path(a.cache) if a.cache else out / "cache"
    path = out / f"runs_{a.study}.jsonl"
    done = {json.loads(line)["key"] for line in path.read_text().splitlines()} if path.exists() else set()
    i0, n = (int(x) for x in a.shard.split("/"))
    for job in rows(a.study)[i0::n]:
        if job["key"] in done:
            continue
        g, t_gen = R.generated(job, cache)
        noise = coloured_noise(job["colour"], g.time.size, job["noise_std"], job["fs"], job["noise_seed"])
        g = dataclasses.replace(g, torque=g.torque + noise, torque_noise_std=float(np.std(noise)))
        t0 = time.time()
        rep = diagnose(g.to_recording(), progress=False)
        b = rep.baseline
        row = {"key": job["key"], "colour": job["colour"], "plant": job["plant"], "controller": job["controller"],
               "excitation": job["excitation"], "fs": job["fs"], "n_samples": int(g.time.size),
               "true_torque_noise_std": g.torque_noise_std, "verdict": rep.verdict,
               "floor_over_true_noise": b.noise_floor_nm / g.torque_noise_std,
               "torque_noise_over_true": b.torque_noise_nm / g.torque_noise_std,
               "noise_colour_estimated": b.conditioning.get("torque_noise_colour"),
               "noise_arma_estimated": b.conditioning.get("torque_noise_arma"), "floor_ratio": b.floor_ratio,
               "seconds_generate": t_gen, "seconds_diagnose": time.time() - t0}
        with path.open("a") as f:
            f.write(json.dumps(row) + "\n")
        print(f"{row['key']} ({row['colour']}): {row['verdict']}; floor / true noise "
              f"{row['floor_over_true_noise']:.3f}, torque noise {row['torque_noise_over_true']:.3f}, "
              f"{row['seconds_diagnose']:.0f} s", flush=True)
    got = [json.loads(line) for line in path.read_text().splitlines()]
    print(f"{len(got)} rows: none on {sum(r['verdict'] == 'none' for r in got)}; floor within 10 % on "
          f"{sum(abs(r['floor_over_true_noise'] - 1) <= 0.1 for r in got)}")


if __name__ == "__main__":
    main()
