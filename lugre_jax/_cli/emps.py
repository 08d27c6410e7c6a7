"""``lugre-jax emps [--data FILE.mat] [--validate OTHER.mat] --out DIR``.

Thin wrapper around :func:`lugre_jax.emps.identify_emps` and :func:`lugre_jax.emps.write_emps_outputs`.
"""

from __future__ import annotations

from pathlib import Path

from ._args import add_quiet, comma_choices
from ._outputs import FOLDER, Outputs, check_outputs


def _default_data() -> Path:
    from ..io import default_emps_path

    here = default_emps_path()
    if here.exists():
        return here
    # relative to the repository root (../shared/data beside the checkout), wherever we run from
    return Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "emps" / "DATA_EMPS.mat"


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "emps",
        help="EMPS benchmark: simulate the drive in closed loop, identify friction models, score them",
        description=(
            "Reproduce the EMPS benchmark's IDIM-LS, fit each friction model by output error through "
            "the sampled-data closed loop (driven by qg) and under the benchmark protocol (driven by "
            "vir, truncated simulation error), and score both on the held-out last 30 % of the "
            "estimation run and on --validate. Writes DIR/RESULT.json, validation_benchmark.csv, "
            "validation_closed_loop.csv and PNG figures."),
    )
    p.add_argument("--data", help="estimation run .mat (default ../shared/data/emps/DATA_EMPS.mat)")
    p.add_argument("--validate", help="validation run .mat (same layout, optional pulses_N)")
    p.add_argument("--out", required=True,
                   help="output folder: new, empty, or an earlier emps result (it holds MANIFEST.json), which is "
                        "replaced only when the new run has finished")
    p.add_argument("--models", help="comma-separated subset of models (default: the published structure, "
                                    "its asymmetric variant and the two position-dependent laws; --full: all)")
    p.add_argument("--full", action="store_true",
                   help="the full study: every model of lugre_jax.emps.MODELS (LuGre laws included; slower)")
    p.add_argument("--train-fraction", type=float, default=0.7,
                   help="fraction of the estimation run used for fitting (default 0.7)")
    p.add_argument("--segments", type=int, default=4,
                   help="shooting segments of the benchmark-protocol fit (default 4)")
    p.add_argument("--segment-len", type=int, default=None,
                   help="samples per shooting segment (default: the segments tile the training part)")
    p.add_argument("--max-steps", type=int, default=200,
                   help="Levenberg-Marquardt steps allowed per least-squares fit (default 200; a fit that "
                        "reaches the limit is reported on stderr and in RESULT.json's summary)")
    add_quiet(p, "progress output")


def check(args) -> None:
    """The output folder, before the package loads and long before the fits end."""
    check_outputs(args, command="emps", out=FOLDER)


def run(args) -> int:
    import sys

    from ..emps import DEFAULT_MODELS, MODELS, identify_emps, read_emps_mat, write_emps_outputs

    by_label = {m.label: m for m in MODELS}
    models = tuple(by_label[k] for k in comma_choices(args.models, list(by_label), "--models")) \
        if args.models else MODELS if args.full else DEFAULT_MODELS
    if args.segments < 1 or (args.segment_len is not None and args.segment_len < 20):
        raise ValueError(f"--segments must be >= 1 and --segment-len >= 20, got {args.segments}, "
                         f"{args.segment_len}")
    if args.max_steps < 1:
        raise ValueError(f"--max-steps must be >= 1, got {args.max_steps}")
    data = Path(args.data) if args.data else _default_data()
    if not args.data and not data.exists():
        raise ValueError(f"{data}: EMPS estimation run not found; pass --data DATA_EMPS.mat "
                         f"(see ../shared/data/README.md)")
    with Outputs(meta={"command": "emps"}) as outs:
        staging = outs.folder(args.out, "--out")  # the same check as check(), then a staging folder
        run_ = read_emps_mat(data)
        val = read_emps_mat(args.validate) if args.validate else None
        report = identify_emps(run_, val, models=models, train_fraction=args.train_fraction,
                               n_segments=args.segments, segment_len=args.segment_len,
                               max_steps=args.max_steps, progress=not args.quiet)
        paths = [Path(args.out) / p.relative_to(staging) for p in write_emps_outputs(report, staging)]
    # non-convergence is never silent, --quiet or not
    for line in report.not_converged:
        print(f"warning: {line}; RESULT.json's summary lists it", file=sys.stderr)
    if report.pulses is not None and not report.pulses.established:
        print(f"warning: validation pulses_N {report.pulses.reason}", file=sys.stderr)
    if not args.quiet:
        sm = report.summary()
        pr, cl = sm["protocol"], sm["closed_loop"]
        i = report.idim["symmetric"]
        print(f"IDIM-LS: rel. error {i.rel_err_pct:.3f} % (published 4.08 %)")
        for r in [k for k in ("held_out", "validation") if k in pr]:
            b, p = pr[r]["best_model"], pr[r]["published_idim_model"]
            print(f"protocol (vir alone), {r}: {pr['best_model']} ({pr['best_model_n_physical_parameters']} "
                  f"parameters) RMSE {b['rmse_mm']:.2f} mm, R2 {b['r2']:.4f}, fit {b['fit_index']:.1f} %; "
                  f"published IDIM model {p['rmse_mm']:.2f} mm, R2 {p['r2']:.4f}, fit {p['fit_index']:.1f} %")
        rows = [("held_out", cl["held_out"])] + list(cl.get("validation", {}).items())
        for r, c in rows:
            print(f"closed loop, {r}: {cl['best_model']} force {c['best_model']['force_pct']:.2f} %; "
                  f"published IDIM model {c['published_idim_model']['force_pct']:.2f} %")
        nc = sm["convergence"]
        print(f"fits converged: {nc['n_fits'] - len(nc['not_converged'])} of {nc['n_fits']}")
        print(f"total {report.total_time_s:.1f} s; wrote {', '.join(str(p) for p in paths)}")
    return 0
