"""``lugre-jax diagnose REC.csv|DATA_EMPS.mat [--params P.json] --out REPORT.json [--plots DIR]``.

Thin wrapper around :func:`lugre_jax.diagnose.diagnose`: load, diagnose, write the report (and plots).
"""

from __future__ import annotations

import json
from pathlib import Path

from ._args import comma_choices


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "diagnose",
        help="locate model-reality mismatch in a recording and name the missing physics",
        description=(
            "Fit the inverse LuGre joint model to a recording (or use --params), locate residual "
            "structure with a Holm-controlled false-alarm rate, and name missing physics from a "
            "library (position_ripple, gravity, asymmetry, thermal_drift, stribeck_shape, backlash, "
            "compliance, load_dependent). REC is a CSV in paper units (time_s, position_deg, "
            "velocity_deg_s, torque_nm, ...) or the EMPS benchmark DATA_EMPS.mat (SI units: m, N)."),
    )
    p.add_argument("recording", help="recording CSV, or DATA_EMPS.mat")
    p.add_argument("--params", help="baseline parameters JSON (a dict, or a previous REPORT.json)")
    p.add_argument("--out", required=True, help="REPORT.json to write")
    p.add_argument("--plots", help="directory for PNG figures")
    p.add_argument("--friction", choices=("lugre", "stribeck", "coulomb_viscous"), default="lugre",
                   help="baseline friction law (default lugre)")
    p.add_argument("--offset", action="store_true", help="fit a constant torque offset in the baseline")
    p.add_argument("--alpha", type=float, default=0.05, help="family-wise false-alarm rate (default 0.05)")
    p.add_argument("--candidates", help="comma-separated subset of candidate ids (default: all)")
    p.add_argument("--block-s", type=float, default=None,
                   help="length of the validation/cluster time blocks in seconds "
                        "(default ~1 s, at least 25 blocks; every 5th block is held out)")
    p.add_argument("--quiet", action="store_true", help="no progress bars")


def _load(path: str):
    from ..io._emps import load_emps
    from ..io._recording import load_recording

    if path.lower().endswith(".mat"):
        return load_emps(path)
    return load_recording(path)


def run(args) -> int:
    from ..diagnose import diagnose, plot_report, public_report
    from ..diagnose._physics import CANDIDATES
    from ..io._atomic import write_json

    if args.block_s is not None and not args.block_s > 0:
        raise ValueError(f"--block-s must be positive, got {args.block_s}")
    if not 0 < args.alpha < 1:
        raise ValueError(f"--alpha must be in (0, 1), got {args.alpha}")
    params = None
    if args.params:
        pth = Path(args.params)
        if not pth.exists():
            raise ValueError(f"--params: {pth} does not exist")
        try:
            params = json.loads(pth.read_text())
        except json.JSONDecodeError as e:
            raise ValueError(f"--params: {pth}: not valid JSON ({e})") from None
        if isinstance(params, dict) and "baseline" in params:
            params = params["baseline"]["params"]
        if not isinstance(params, dict):
            raise ValueError(f"--params: {pth}: expected a JSON object of parameter values")
    cands = comma_choices(args.candidates, CANDIDATES, "--candidates") if args.candidates else None
    rec = _load(args.recording)
    rep = diagnose(rec, params=params, friction=args.friction, fit_offset=args.offset,
                   alpha=args.alpha, candidates=cands, progress=not args.quiet, block_s=args.block_s)
    write_json(args.out, public_report(rep))
    if args.plots:
        plot_report(rep, rec, args.plots)
    names = [m["name"] for m in rep["missing_physics"]]
    print(f"verdict: {rep['verdict']}; baseline validation RMSE {rep['baseline']['validation_rmse_nm']:.5g} "
          f"-> {rep['improved']['validation_rmse_nm']:.5g} {rec.units['torque']}; "
          f"missing physics: {names or 'none'}; report: {args.out}")
    return 0
