"""EMPS, closed loop and benchmark protocol: every friction model identified by output error through
the sampled-data simulation and scored beside the published anchors.

Writes, into ``--out`` (default ``experiments/emps/results``): what ``lugre-jax emps`` writes
(RESULT.json, validation_benchmark.csv, validation_closed_loop.csv, measured_vs_simulated.png,
residuals.png) and ``table.md``, the per-model table of docs/emps.md. Large CSVs (the per-sample
series) are not kept in git; RESULT.json, table.md and the PNGs are.

    python experiments/emps/run.py [--data ../shared/data/emps/DATA_EMPS.mat] [--validate VAL.mat] [--out DIR]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]


def table(report_json: dict, run: str) -> str:
    pub = report_json["published"]
    ref = report_json["published_model_simulated"]
    rows = ["| model | fit on | closed loop: position % | velocity % | force % "
            f"| benchmark ({run}): RMSE mm | R² | fit index % | fit time s (closed loop / benchmark) |",
            "|---|---|---|---|---|---|---|---|---|"]
    p = pub["closed_loop_estimation"]
    rows.append(f"| published IDIM-LS model, published (Simulink) | estimation | {p['position_pct']} | "
                f"{p['velocity_pct']} | {p['force_pct']} | | | | |")
    for key in ("symmetric", "asymmetric"):
        for r in ("estimation", run):
            c, b = ref[key]["closed_loop"][r], ref[key]["benchmark"][r]
            rows.append(f"| IDIM-LS {key} (reproduced), our simulation | {r} | {c['position_pct']:.4f} | "
                        f"{c['velocity_pct']:.3f} | {c['force_pct']:.2f} | {b['rmse_mm']:.2f} | {b['r2']:.4f} | "
                        f"{b['fit_index']:.1f} | |")
    for name, m in report_json["models"].items():
        for r in ("estimation", run):
            c, b = m["runs"][r]["closed_loop"], m["runs"][r]["benchmark"]
            ft = (f"{m['closed_loop_fit']['fit_time_s']:.1f} / {m['benchmark_fit']['fit_time_s']:.1f}"
                  if r == run else "")
            rows.append(f"| {name} | {r} | {c['position_pct']:.4f} | {c['velocity_pct']:.3f} | "
                        f"{c['force_pct']:.2f} | {b['rmse_mm']:.2f} | {b['r2']:.4f} | {b['fit_index']:.1f} | {ft} |")
    return "\n".join(rows) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(ROOT / ".." / "shared" / "data" / "emps" / "DATA_EMPS.mat"))
    ap.add_argument("--validate", default=None)
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if not Path(a.data).exists():
        print(f"{a.data}: EMPS data not present; nothing to do (see ../shared/data/README.md)")
        return 0
    import lugre_jax

    lugre_jax.configure()
    from lugre_jax.emps import identify_emps, read_emps_mat, write_emps_outputs
    from lugre_jax.io import atomic_path

    run = read_emps_mat(a.data)
    val = read_emps_mat(a.validate) if a.validate else None
    t0 = time.perf_counter()
    report = identify_emps(run, val, progress=not a.quiet)
    write_emps_outputs(report, a.out)
    j = report.to_json()
    which = "validation" if val is not None else "held_out"
    load = Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else []
    head = (f"Command: `python experiments/emps/run.py`; total {time.perf_counter() - t0:.0f} s wall, "
            f"{os.cpu_count()} cores, load average at the end {' '.join(load)}. "
            f"Best closed loop (on held-out force): {j['best']['closed_loop']}; best benchmark "
            f"(on held-out RMSE): {j['best']['benchmark']}.\n\n")
    with atomic_path(Path(a.out) / "table.md") as tmp:
        tmp.write_text(head + table(j, which))
    print(head + table(j, which))
    return 0


if __name__ == "__main__":
    sys.exit(main())
