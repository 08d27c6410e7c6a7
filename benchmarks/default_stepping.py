"""Accuracy and cost of the simulator's default stepping against the stiff scipy reference of
tests/test_simulate_reference.py, beside the fixed step that was the default before, per case.

    python benchmarks/default_stepping.py [--out benchmarks/results/default_stepping.json]

Prints one row per case: max |position error| [deg], max |torque error| [N*m], and the wall time of
one unbatched solve after compilation (best of 5), for Adaptive() (the default) and FixedStep().
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import lugre_jax as lj

lj.configure()  # before the reference cases below build their first arrays

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from test_simulate_reference import CASES, J, KI, KP, scipy_reference  # noqa: E402

from _timing import best_of  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "default_stepping.json"))
    a = ap.parse_args(argv)
    rows = []
    for name, (reference, (ref_fn, jumps), duration, hz) in sorted(CASES.items()):
        system = lj.System(friction=lj.paper_segment(1), joint=lj.Joint(J=J),
                           controller=lj.VelocityPID(kp=KP, ki=KI), reference=reference)
        theta, torque = scipy_reference(ref_fn, jumps, duration, hz)
        for label, stepping in (("Adaptive() default", None), ("FixedStep() (old default)", lj.FixedStep())):
            def run():
                return lj.simulate(system, duration, hz, stepping=stepping).torque_nm.block_until_ready()
            sol = lj.simulate(system, duration, hz, stepping=stepping)
            rows.append(dict(case=name, stepping=label, samples=int(sol.ts.shape[0]),
                             theta_err_deg=float(np.max(np.abs(np.asarray(sol.theta) - theta))),
                             torque_err_nm=float(np.max(np.abs(np.asarray(sol.torque_nm) - torque))),
                             solve_s=best_of(run, 5)))
            r = rows[-1]
            print(f"{name:20s} {label:26s} theta {r['theta_err_deg']:.1e} deg  torque {r['torque_err_nm']:.1e} N*m  "
                  f"{1e3 * r['solve_s']:.2f} ms", flush=True)
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(dict(rows=rows, loadavg=open("/proc/loadavg").read().split()[:3]), indent=1))
    print(out)


if __name__ == "__main__":
    main()
