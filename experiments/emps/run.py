"""EMPS, closed loop and benchmark protocol: the default models (``--full``: every model) identified
by output error through the sampled-data simulation and scored beside the published anchors.

Writes, into ``--out`` (default ``experiments/emps/results``): what ``lugre-jax emps`` writes
(RESULT.json, validation_benchmark.csv, validation_closed_loop.csv, measured_vs_simulated.png,
residuals.png) and ``table.md``, the per-model table of docs/emps.md. Large CSVs (the per-sample
series) are not kept in git; RESULT.json, table.md and the PNGs are.

    python experiments/emps/run.py [--data ../shared/data/emps/DATA_EMPS.mat] [--validate VAL.mat] [--out DIR] [--full]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import emps_parser, emps_present  # noqa: E402


def _row(name, runs, r, cl_key=None, ft=""):
    c = runs.get(cl_key or r, {}).get("closed_loop")
    b = runs.get(r, {}).get("benchmark")
    cs = (f"{c['position_pct']:.4f} | {c['velocity_pct']:.3f} | {c['force_pct']:.2f}" if c else " | | ")
    bs = f"{b['rmse_mm']:.2f} | {b['r2']:.4f} | {b['fit_index']:.1f}" if b else " | | "
    return f"| {name} | {r if cl_key is None else cl_key} | {cs} | {bs} | {ft} |"


def table(report_json: dict) -> str:
    """Per model and run: closed-loop errors (qg-driven) and the protocol's score (vir alone)."""
    pub = report_json["published"]
    ref = report_json["published_model_simulated"]
    runs_order = ["estimation", "held_out"] + (["validation"] if report_json["validation"] else [])
    pulses = report_json["validation_has_pulses"]
    rows = ["| model | run | closed loop: position % | velocity % | force % "
            "| protocol (vir alone): RMSE mm | R² | fit index % | fits: steps, status (closed loop / protocol) |",
            "|---|---|---|---|---|---|---|---|---|"]
    p = pub["closed_loop_estimation"]
    rows.append(f"| published IDIM-LS model, published (Simulink) | estimation | {p['position_pct']} | "
                f"{p['velocity_pct']} | {p['force_pct']} | | | | |")

    def runs_of(cl, bm):
        return {k: {"closed_loop": cl.get(k), "benchmark": bm.get(k)} for k in {*cl, *bm}}

    entries = [(f"IDIM-LS {k} (reproduced), our simulation", runs_of(v["closed_loop"], v["benchmark"]), "")
               for k, v in ref.items()]
    for name, m in report_json["models"].items():
        a, b = m["closed_loop_fit"], m["benchmark_fit"]
        ft = f"{a['steps']} {a['status']} / {b['steps']} {b['status']}"
        entries.append((f"{name} ({m['n_physical_parameters']} parameters)", m["runs"], ft))
    for name, runs, ft in entries:
        for r in runs_order:
            if r == "validation" and pulses:
                rows.append(_row(name, runs, r, "validation_pulses_estimated", ft if r == runs_order[-1] else ""))
                rows.append(_row(name, runs, r, "validation_pulses_ignored"))
            else:
                rows.append(_row(name, runs, r, None, ft if r == runs_order[-1] else ""))
    return "\n".join(rows) + "\n"


def main(argv=None):
    ap = emps_parser(__doc__)
    ap.add_argument("--validate", default=None)
    ap.add_argument("--out", default=str(HERE / "results"))
    ap.add_argument("--full", action="store_true", help="every model (lugre_jax.emps.MODELS), not the default set")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    if not emps_present(a):
        return 0
    from lugre_jax.emps import DEFAULT_MODELS, MODELS, identify_emps, read_emps_mat, write_emps_outputs
    from lugre_jax.io import atomic_path

    run = read_emps_mat(a.data)
    val = read_emps_mat(a.validate) if a.validate else None
    t0 = time.perf_counter()
    report = identify_emps(run, val, models=MODELS if a.full else DEFAULT_MODELS, progress=not a.quiet)
    write_emps_outputs(report, a.out)
    j = report.to_json()
    load = Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else []
    cmd = "python experiments/emps/run.py" + (" --full" if a.full else "") + (" --validate VAL" if val else "")
    nc = j["summary"]["convergence"]
    head = (f"Command: `{cmd}`; total {time.perf_counter() - t0:.0f} s wall, "
            f"{os.cpu_count()} cores, load average at the end {' '.join(load)}. "
            f"Best closed loop (held-out force, one-standard-error rule): {j['best']['closed_loop']}; "
            f"best under the protocol (held-out RMSE, same rule): {j['best']['benchmark']}. Fits converged: "
            f"{nc['n_fits'] - len(nc['not_converged'])} of {nc['n_fits']}.\n\n")
    with atomic_path(Path(a.out) / "table.md") as tmp:
        tmp.write_text(head + table(j))
    print(head + table(j))
    return 0


if __name__ == "__main__":
    sys.exit(main())
