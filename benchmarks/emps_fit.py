"""Time of the EMPS output-error fits, and how the benchmark-protocol fit scales with the number
of shooting segments.

For each model: the closed-loop fit (first 70 % of DATA_EMPS.mat, from the published values) and
the benchmark-protocol fit with the training part cut into K segments that cover it (K*L = 17,389
samples; K = 1 is a free simulation of the whole part, where the mass drifts). Wall time includes
compilation (every fit compiles its own loop; this is what a user waits for) and is reported with
the process CPU time, the time of one residual + forward-mode Jacobian evaluation after
compilation, the residual evaluations of the least-squares solver, whether it converged and the
held-out benchmark RMSE of the result. The machine is shared:
the load average is recorded before and after each row.

    python benchmarks/emps_fit.py [--data ../shared/data/emps/DATA_EMPS.mat] [--out benchmarks/emps_fit.json]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "experiments"))  # the EMPS data check the experiments use
from _common import emps_parser, emps_present  # noqa: E402


def load():
    try:
        return float(Path("/proc/loadavg").read_text().split()[0])
    except OSError:
        return None


def main(argv=None):
    ap = emps_parser(__doc__)
    ap.add_argument("--out", default=str(HERE / "emps_fit.json"))
    ap.add_argument("--models", default="coulomb_viscous,asymmetric,asymmetric_position")
    ap.add_argument("--segments", default="1,4,16,64")
    a = ap.parse_args(argv)
    if not emps_present(a):
        return 0
    import jax
    import numpy as np

    from lugre_jax.emps import (MODELS, RunArrays, benchmark_score, closed_loop_score, closed_loop_window,
                                fit_closed_loop, fit_open_loop, open_loop_segments, read_emps_mat,
                                segment_starts)
    from lugre_jax.io import write_json

    run = read_emps_mat(a.data)
    data = RunArrays(run)
    cut = int(round(0.7 * run.n))
    by = {m.label: m for m in MODELS}
    rows = []

    def timed(fn):
        l0, c0, t0 = load(), time.process_time(), time.perf_counter()
        out = fn()
        return out, time.perf_counter() - t0, time.process_time() - c0, l0, load()

    def eval_time(residual, p):
        f = jax.jit(lambda pp: (residual(pp), jax.jacfwd(residual)(pp)))
        jax.block_until_ready(f(p))
        t0 = time.perf_counter()
        for _ in range(3):
            jax.block_until_ready(f(p))
        return (time.perf_counter() - t0) / 3

    for label in a.models.split(","):
        cls = by[label]
        m0 = cls.reference()
        fr, wall, cpu, l0, l1 = timed(lambda: fit_closed_loop(m0, data, 0, cut))
        p0 = m0.vector()

        def res_cl(p, cls=cls):
            q, v, f, _ = closed_loop_window(cls.from_vector(p), data, 0, cut)
            return f - data.force[:cut]

        rows.append(dict(model=label, protocol="closed_loop", segments=1, segment_len=cut, wall_s=wall,
                         cpu_s=cpu, eval_with_jacobian_s=eval_time(res_cl, p0), evaluations=fr.n_steps, status=fr.status,
                         success=fr.success, held_out_force_pct=closed_loop_score(fr.model, data, cut).force_pct,
                         load_before=l0, load_after=l1))
        print(rows[-1], flush=True)
        for K in (int(k) for k in a.segments.split(",")):
            L = cut // K
            fr, wall, cpu, l0, l1 = timed(lambda: fit_open_loop(m0, data, 0, cut, n_segments=K, segment_len=L))
            starts = segment_starts(0, cut, K, L)
            Y = run.qm[starts[:, None] + np.arange(L)[None, :]]

            def res_ol(p, cls=cls, starts=starts, L=L, Y=Y):
                q, _ = open_loop_segments(cls.from_vector(p), data, starts, L)
                return (q - Y).ravel()

            b = benchmark_score(fr.model, data, cut)
            rows.append(dict(model=label, protocol="benchmark", segments=K, segment_len=L, wall_s=wall, cpu_s=cpu,
                             eval_with_jacobian_s=eval_time(res_ol, p0), evaluations=fr.n_steps, status=fr.status, success=fr.success,
                             held_out_rmse_mm=b.rmse_mm, held_out_r2=b.r2, load_before=l0, load_after=l1))
            print(rows[-1], flush=True)
    write_json(a.out, dict(command="python benchmarks/emps_fit.py " + " ".join(argv or sys.argv[1:]),
                           cpu_count=os.cpu_count(), jax=jax.__version__, devices=str(jax.devices()),
                           note="wall includes compilation; the machine is shared (load averages per row)",
                           rows=rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
