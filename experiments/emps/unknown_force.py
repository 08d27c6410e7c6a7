"""``diagnose`` on EMPS runs that carry an unknown periodic force: is it found, and at its frequency?

Each run is the estimation run's closed loop (reference ``qg``, loop gains, the published IDIM-LS
plant, 50-nm encoder, the logged ``vir``'s noise) with a square-wave force of known amplitude and
frequency added on the plant (``lugre_jax.emps.make_pulse_run``, gain 1, no delay). The written run
holds no ``pulses_N`` column: the force is unknown to the tool. Each is read as
``lugre-jax diagnose RUN.mat --offset`` reads it (``lugre_jax.io.load_emps``: filtered,
decimated to 100 Hz) and diagnosed; a row records the verdict, the attributed terms (a
``time_periodic`` term's frequency against the truth) and the baseline's floor.

    python experiments/emps/unknown_force.py [--data DATA_EMPS.mat] [--out experiments/emps/results]
                                             [--amplitudes 5,1,0.2] [--frequency 0.5]
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from _common import emps_parser, emps_present  # noqa: E402


def square_run(run, amplitude: float, frequency: float, seed: int):
    """The estimation run's closed loop with a square-wave plant force (``pulses_N`` not kept)."""
    import numpy as np

    from lugre_jax.emps import EmpsCoulombViscous, PulseEntry, make_pulse_run

    t = np.arange(run.n) * float(np.median(np.diff(run.t)))
    force = amplitude * np.sign(np.sin(2 * np.pi * frequency * t + 0.3))
    return make_pulse_run(run, EmpsCoulombViscous.reference(), force, PulseEntry("plant", 1.0, 0), seed=seed)


def write_mat(run, path: Path) -> None:
    import numpy as np
    import scipy.io

    col = lambda x: np.asarray(x, np.float64)[:, None]  # noqa: E731
    scipy.io.savemat(path, {"t": col(run.t), "qm": col(run.qm), "qg": col(run.qg), "vir": col(run.vir),
                            "gtau": np.array([[run.gtau]]), "kp": np.array([[run.kp]]), "kv": np.array([[run.kv]])})


def main(argv=None) -> int:
    ap = emps_parser(__doc__)
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--amplitudes", default="5,1,0.2", help="square-wave amplitudes [N], comma-separated")
    ap.add_argument("--frequency", type=float, default=0.5, help="square-wave frequency [Hz]")
    a = ap.parse_args(argv)
    if not emps_present(a):
        return 0
    from lugre_jax.diagnose import diagnose
    from lugre_jax.emps import read_emps_mat
    from lugre_jax.io import load_emps, write_json

    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    run = read_emps_mat(a.data)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, amp in enumerate(float(x) for x in a.amplitudes.split(",")):
            path = Path(tmp) / f"square_{amp:g}N.mat"
            write_mat(square_run(run, amp, a.frequency, seed=11 + k), path)
            t0 = time.perf_counter()
            rep = diagnose(load_emps(path), fit_offset=True, progress=False)
            d = rep.to_json()
            b = d["baseline"]
            terms = (d.get("attribution") or {}).get("terms", [])
            line = [x for x in terms if x["signal"] == "time_periodic"]
            f_found = float(line[0]["columns"][0].split("*")[2]) if line else None
            row = {"amplitude_n": amp, "frequency_hz": a.frequency, "verdict": d["verdict"],
                   "attributed": [x["signal"] for x in terms],
                   "time_periodic_hz": f_found, "time_periodic_p_held_out": line[0]["p_held_out"] if line else None,
                   "located": [{"test": x["test"], "region": x["region"]} for x in d["mismatch"]],
                   "validation_rmse_n": b["validation_rmse_nm"], "noise_floor_n": b["noise_floor_nm"],
                   "torque_noise_n": b["torque_noise_nm"], "floor_ratio": b["floor_ratio"],
                   "unresolved_fraction": b["conditioning"]["unresolved_fraction"],
                   "seconds": time.perf_counter() - t0}
            rows.append(row)
            print(f"{amp:g} N at {a.frequency:g} Hz: {row['verdict']}; attributed {row['attributed']}; "
                  f"time line {f_found} Hz; floor ratio {row['floor_ratio']:.3g}", flush=True)
    write_json(out / "unknown_force.json", {"command": "python experiments/emps/unknown_force.py", "rows": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
