"""``lugre-jax diagnose REC.csv|DATA_EMPS.mat [--params P.json] --out REPORT.json [--plots DIR]``.

Thin wrapper around :func:`lugre_jax.diagnose.diagnose`: load, diagnose, write the report (and plots).
"""

from __future__ import annotations

from ._args import HelpFormatter, comma_choices


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "diagnose",
        formatter_class=HelpFormatter,
        help="locate model-reality mismatch in a recording and name the missing physics",
        description=(
            "Fit the inverse LuGre joint model to a recording (or use --params), locate residual "
            "structure with a Holm-controlled false-alarm rate, and name missing physics from a "
            "library (position_ripple, gravity, asymmetry, thermal_drift, stribeck_shape, backlash, "
            "compliance, load_dependent). REC is a CSV in paper units (time_s, position_deg, "
            "velocity_deg_s, torque_nm, ...; one of position_deg and velocity_deg_s may be absent) or the EMPS benchmark DATA_EMPS.mat (SI units: m, N)."),
    )
    p.add_argument("recording", help="recording CSV, or DATA_EMPS.mat")
    p.add_argument("--params", metavar="P.json",
                   help="baseline parameters JSON instead of fitting: an object with J, Fc, Fs, vs, sigma0, sigma1, "
                        "sigma2 (recording units; friction_model LuGre, Stribeck or CoulombViscous), or a previous "
                        "REPORT.json")
    p.add_argument("--out", required=True, metavar="REPORT.json", help="report JSON to write")
    p.add_argument("--plots", metavar="DIR",
                   help="folder for PNG figures (new, empty, or an earlier plots folder; it gets a MANIFEST.json)")
    p.add_argument("--friction", choices=("lugre", "stribeck", "coulomb_viscous"), default="lugre",
                   help="baseline friction law")
    p.add_argument("--offset", action="store_true", help="fit a constant torque offset in the baseline")
    p.add_argument("--alpha", type=float, default=0.05, help="family-wise false-alarm rate")
    p.add_argument("--candidates", help="comma-separated subset of candidate ids (default: all)")
    p.add_argument("--block-s", type=float, default=None,
                   help="length of the validation/cluster time blocks in seconds "
                        "(default ~1 s, at least 25 blocks; every 5th block is held out; a candidate is "
                        "cross-validated over the phases)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def _load(path: str):
    from ..io import load_emps, load_recording

    if path.lower().endswith(".mat"):
        return load_emps(path)
    return load_recording(path)


def run(args) -> int:
    import math

    from ..diagnose import diagnose, plot_report
    from ..diagnose import CANDIDATES
    from ..io import load_params_json, write_json
    from ._outputs import Outputs

    if args.block_s is not None and not (math.isfinite(args.block_s) and args.block_s > 0):
        raise ValueError(f"--block-s must be a positive number of seconds, got {args.block_s}")
    if not 0 < args.alpha < 1:
        raise ValueError(f"--alpha must be in (0, 1), got {args.alpha}")
    cands = comma_choices(args.candidates, CANDIDATES, "--candidates") if args.candidates else None
    # Inputs and every output path are checked before the fit (tens of seconds) starts.
    with Outputs(meta={"command": "diagnose", "recording": str(args.recording)}) as outs:
        out_path = outs.file(args.out, "--out", ".json")
        plots_dir = outs.folder(args.plots, "--plots") if args.plots else None
        params = None if args.params is None else load_params_json(args.params)
        rec = _load(args.recording)
        if params is not None:
            _check_params_against(params, rec, args.params)
        rep = diagnose(rec, params=params, friction=args.friction, fit_offset=args.offset,
                       alpha=args.alpha, candidates=cands, progress=not args.quiet, block_s=args.block_s)
        for key, part in (("baseline", rep.baseline), ("improved", rep.improved)):
            v = part.validation_rmse_nm
            if not math.isfinite(v):
                raise ValueError(f"{args.params or args.recording}: the {key} model's validation RMSE is {v}; "
                                 "expected a finite error (are the parameters in the recording's units?)")
        write_json(out_path, rep.to_json())
        if plots_dir is not None:
            plot_report(rep, rec, plots_dir)
    print(f"verdict: {rep.verdict}; baseline validation RMSE {rep.baseline.validation_rmse_nm:.5g} "
          f"-> {rep.improved.validation_rmse_nm:.5g} {rec.units['torque']}; "
          f"missing physics: {rep.named or 'none'}; report: {args.out}")
    return 0


def _check_params_against(params: dict, rec, source) -> None:
    """The baseline's friction torque over the recording's velocities must be finite and within a
    few hundred times the measured torque: parameters far off (wrong units, 1e300) are refused here
    rather than reported as an infinite RMSE."""
    import numpy as np

    v = np.abs(np.asarray(rec.velocity, dtype=np.float64))
    fc, fs = params.get("Fc", 0.0), params.get("Fs", params.get("Fc", 0.0))
    vs, d = params.get("vs", 1.0), params.get("delta", 2.0)
    with np.errstate(all="ignore"):
        f = fc + (fs - fc) * np.exp(-np.abs(v / vs) ** d) + params.get("sigma2", 0.0) * v
        inertia = params["J"] * np.abs(np.asarray(rec.acceleration, dtype=np.float64))
        model = float(np.max(np.abs(f) + inertia + abs(params.get("offset", 0.0))))
    scale = float(np.max(np.abs(rec.torque)))
    if not np.isfinite(model) or model > 1e3 * max(scale, 1e-12):
        raise ValueError(f"{source}: the parameters predict torques up to {model:.3g} {rec.units['torque']} on this "
                         f"recording, whose torque stays below {scale:.3g}; expected parameters in the "
                         "recording's units "
                         f"({rec.units['velocity']}, {rec.units['torque']})")
