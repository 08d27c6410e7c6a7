"""EMPS pulse runs made from the estimation run's closed loop: how ``pulses_N`` enters, recovered.

The benchmark's validation run (external force pulses) is not shipped, so this builds its
stand-ins: the estimation run's reference ``qg`` and loop gains, a plant model simulated in closed
loop (the published IDIM-LS model, or the asymmetric LuGre + ripple law whose friction the
estimator's regression does not contain), and a square pulse train (30 N, 0.1 s every 1.5 s,
alternating sign) entering with a known location, gain and delay. For each run it writes the
estimate (gain, delay, their 95 % intervals, whether established) and the closed-loop force error
of the published model with the pulses as estimated, ignored and at unit gain.

    python experiments/emps/pulses.py [--data ../shared/data/emps/DATA_EMPS.mat] [--out DIR] [--write-mat DIR]

``--write-mat DIR`` also writes each synthetic run as ``DIR/<name>.mat`` (the DATA_EMPS layout plus
``pulses_N``) for ``lugre-jax emps --validate``; they are not kept in git.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import emps_parser, emps_present  # noqa: E402


def main(argv=None):
    ap = emps_parser(__doc__)
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--write-mat", default=None)
    a = ap.parse_args(argv)
    if not emps_present(a):
        return 0
    import numpy as np

    from lugre_jax.emps import (AsymmetricLuGreRipple, EmpsCoulombViscous, PulseEntry, RunArrays, closed_loop_score,
                                estimate_pulse_entry, make_pulse_run, pulse_train, read_emps_mat)
    from lugre_jax.io import write_json

    run = read_emps_mat(a.data)
    published = EmpsCoulombViscous.reference()
    # a plant unlike the regression's structure: bristles, Stribeck, ripple (fitted values, docs/emps.md)
    lugre = AsymmetricLuGreRipple(95.14, 157.4, 21.22, 230.9, 21.46, 14.73, 0.0146, 1.47e6, 3.9e3, 0.4, 0.38,
                                  2.4723e-3)
    p = pulse_train(run.n, 1e-3)
    cases = {
        "plant_gain-0.64_delay12": (published, PulseEntry("plant", -0.64, 12)),
        "plant_gain0.64_delay12_lugre_plant": (lugre, PulseEntry("plant", 0.64, 12)),
        "command_gain0.8_delay5": (published, PulseEntry("command", 0.8, 5)),
        "no_effect": (published, PulseEntry("plant", 0.0, 0)),
    }
    rows = {}
    for name, (plant, entry) in cases.items():
        t0 = time.perf_counter()
        syn = make_pulse_run(run, plant, p, entry, seed=7)
        est = estimate_pulse_entry(syn)
        data = RunArrays(syn)
        cl = {"pulses_estimated": closed_loop_score(published, data, pulses=est.entry).force_pct,
              "pulses_ignored": closed_loop_score(published, data).force_pct,
              "pulses_unit_gain": closed_loop_score(published, data, pulses=PulseEntry("plant", 1.0, 0)).force_pct}
        fit = est.fits.get(entry.location)
        rows[name] = {"truth": entry.to_json(), "plant_model": plant.label, "estimate": est.to_json(),
                      "truth_in_gain_ci95": bool(fit.gain_ci95[0] <= entry.gain <= fit.gain_ci95[1]),
                      "truth_in_delay_ci95": bool(fit.delay_ci95[0] <= entry.delay <= fit.delay_ci95[1]),
                      "published_model_closed_loop_force_pct": cl, "time_s": time.perf_counter() - t0}
        print(f"{name}: {est.reason}; published model closed-loop force error: estimated "
              f"{cl['pulses_estimated']:.2f} %, ignored {cl['pulses_ignored']:.2f} %, unit gain "
              f"{cl['pulses_unit_gain']:.2f} %", flush=True)
        if a.write_mat:
            import scipy.io

            Path(a.write_mat).mkdir(parents=True, exist_ok=True)
            col = lambda x: np.asarray(x, np.float64)[:, None]  # noqa: E731
            scipy.io.savemat(Path(a.write_mat) / f"{name}.mat",
                             {"t": col(syn.t), "qm": col(syn.qm), "qg": col(syn.qg), "vir": col(syn.vir),
                              "pulses_N": col(syn.pulses_N), "gtau": np.array([[syn.gtau]]),
                              "kp": np.array([[syn.kp]]), "kv": np.array([[syn.kv]])})
    write_json(Path(a.out) / "pulses.json",
               {"command": "python experiments/emps/pulses.py", "pulse_train": "30 N, 0.1 s every 1.5 s from 0.5 s, "
                "alternating sign", "runs": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
