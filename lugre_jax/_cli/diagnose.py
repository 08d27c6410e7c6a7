"""``lugre-jax diagnose REC.csv|DATA_EMPS.mat [--params P.json] --out REPORT.json [--plots DIR]``.

Thin wrapper around :func:`lugre_jax.diagnose.diagnose`: load, diagnose, write the report (and plots).
"""

from __future__ import annotations

from ._args import HelpFormatter, add_quiet, check_input, comma_choices
from ._outputs import FOLDER, check_outputs

# a diagnosis holds ~30 float64 arrays of the recording's length per null draw batch and refits
# a model of ~10 parameters many times: beyond this many samples it is refused up front with the
# cost and how to split it (the cost by length: docs/performance.md, Diagnosis)
MAX_SAMPLES = 200_000


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
            "velocity_deg_s, torque_nm, ...; one of position_deg and velocity_deg_s may be absent), one EPOS "
            "Studio export (velocity and torque), or the EMPS benchmark DATA_EMPS.mat (SI units: m, N). A "
            "candidate is named only when its gain beats a null distribution simulated for the recording "
            "(family-wise, a third of --alpha) and it lowers the held-out error; what no candidate explains "
            "is attributed to a term of a stated library (torque rate, v|v|, transmitted torque, jerk, "
            "time, position, a time line)."),
    )
    p.add_argument("recording", help="recording CSV, one EPOS Studio export, or DATA_EMPS.mat")
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
    p.add_argument("--resolution", type=float, default=None, metavar="SHARE",
                   help="smallest structure located, as a share of the noise floor (default 0.15): the margin "
                        "of the located means; 0 leaves the calibrated tests alone")
    p.add_argument("--candidates", help="comma-separated subset of candidate ids (default: all)")
    p.add_argument("--block-s", type=float, default=None,
                   help="length of the validation/cluster time blocks in seconds "
                        "(default ~1 s, at least 25 blocks; every 5th block is held out; a candidate is "
                        "cross-validated over the phases)")
    p.add_argument("--decimate", type=int, default=1, metavar="K",
                   help=f"keep every K-th sample (a recording over {MAX_SAMPLES:,} samples must be cut down)")
    p.add_argument("--segment", metavar="T0:T1", help="diagnose only the samples with T0 <= time < T1 (s)")
    add_quiet(p, "progress bars")


def check(args) -> None:
    """Before the package loads: the flags' values, the input and every output path."""
    import math

    if args.block_s is not None and not (math.isfinite(args.block_s) and args.block_s > 0):
        raise ValueError(f"--block-s must be a positive number of seconds, got {args.block_s}")
    if not 0 < args.alpha < 1:
        raise ValueError(f"--alpha must be in (0, 1), got {args.alpha}")
    if args.resolution is not None and not (math.isfinite(args.resolution) and args.resolution >= 0):
        raise ValueError(f"--resolution must be a share of the noise floor >= 0, got {args.resolution}")
    if args.decimate < 1:
        raise ValueError(f"--decimate must be a positive integer, got {args.decimate}")
    _segment(args.segment)
    check_input(args.recording, "a recording CSV, an EPOS Studio export or DATA_EMPS.mat")
    check_outputs(args, out=".json", plots=FOLDER)
    if args.segment is None and not str(args.recording).lower().endswith(".mat"):
        # a CSV's size is known from its line count before anything is parsed
        with open(args.recording, "rb") as fh:
            rows = sum(chunk.count(b"\n") for chunk in iter(lambda: fh.read(1 << 20), b"")) - 1
        _size_guard(args, -(-rows // args.decimate))


def _size_guard(args, n: int) -> None:
    if n > MAX_SAMPLES:
        k = -(-n // MAX_SAMPLES) * args.decimate
        raise ValueError(f"{args.recording}: {n:,} samples; a diagnosis takes at most {MAX_SAMPLES:,} "
                         f"(about {n * 99 * 8 * 4 / 2**30:.1f} GiB of null draws alone, and time in "
                         f"proportion); use --decimate {k} or --segment T0:T1")


def _segment(text):
    if text is None:
        return None
    try:
        a, b = (float(x) for x in text.split(":"))
    except ValueError:
        raise ValueError(f"--segment {text!r}: expected T0:T1 in seconds, e.g. 10:70") from None
    if not a < b:
        raise ValueError(f"--segment {text!r}: expected T0 < T1")
    return a, b


def _load(path: str):
    from ..io import read_recording

    return read_recording(path)


def run(args) -> int:
    import math

    from ..diagnose import diagnose, plot_report
    from ..diagnose import CANDIDATES
    from ..io import load_params_json, write_json
    from ._outputs import Outputs

    check(args)
    cands = comma_choices(args.candidates, CANDIDATES, "--candidates") if args.candidates else None
    # Inputs and every output path are checked before the fit (tens of seconds) starts.
    with Outputs(meta={"command": "diagnose", "recording": str(args.recording)}) as outs:
        out_path = outs.file(args.out, "--out", ".json")
        plots_dir = outs.folder(args.plots, "--plots") if args.plots else None
        params = None if args.params is None else load_params_json(args.params)
        rec = _cut(_load(args.recording), args)
        if params is not None:
            _check_params_against(params, rec, args.params)
        rep = diagnose(rec, params=params, friction=args.friction, fit_offset=args.offset,
                       alpha=args.alpha, candidates=cands, progress=not args.quiet, block_s=args.block_s,
                       **({} if args.resolution is None else {"resolution": args.resolution}))
        for key, part in (("baseline", rep.baseline), ("improved", rep.improved)):
            v = part.validation_rmse_nm
            if not math.isfinite(v):
                raise ValueError(f"{args.params or args.recording}: the {key} model's validation RMSE is {v}; "
                                 "expected a finite error (are the parameters in the recording's units?)")
        write_json(out_path, rep.to_json())
        if plots_dir is not None:
            plot_report(rep, rec, plots_dir)
    named = [f.name + _or(f) for f in rep.missing_physics]
    print(f"verdict: {rep.verdict}; baseline validation RMSE {rep.baseline.validation_rmse_nm:.5g} "
          f"-> {rep.improved.validation_rmse_nm:.5g} {rec.units['torque']}; "
          f"missing physics: {', '.join(named) or 'none'}; report: {args.out}")
    return 0


def _cut(rec, args):
    """The segment and decimation asked for, then the size guard."""
    import numpy as np

    seg = _segment(args.segment)
    if seg is not None:
        keep = (rec.time >= seg[0]) & (rec.time < seg[1])
        if keep.sum() < 100:
            raise ValueError(f"--segment {args.segment}: {int(keep.sum())} samples of {args.recording} in it; "
                             "expected at least 100")
        rec = rec.subset(np.flatnonzero(keep))
    if args.decimate > 1:
        rec = rec.subset(slice(None, None, args.decimate))
    _size_guard(args, rec.n)
    return rec


def _check_params_against(params: dict, rec, source) -> None:
    """The baseline's friction torque over the recording's velocities must be finite and within a
    few hundred times the measured torque: parameters far off (wrong units, 1e300) are refused here
    rather than reported as an infinite RMSE."""
    import numpy as np

    from ..friction import stribeck_curve

    v = np.abs(np.asarray(rec.velocity, dtype=np.float64))
    fc, fs = params.get("Fc", 0.0), params.get("Fs", params.get("Fc", 0.0))
    f = np.asarray(stribeck_curve(v, fc, fs, params.get("vs", 1.0), params.get("sigma2", 0.0),
                                  params.get("delta", 2.0)))
    with np.errstate(all="ignore"):
        inertia = params["J"] * np.abs(np.asarray(rec.acceleration, dtype=np.float64))
        model = float(np.max(np.abs(f) + inertia + abs(params.get("offset", 0.0))))
    scale = float(np.max(np.abs(rec.torque)))
    if not np.isfinite(model) or model > 1e3 * max(scale, 1e-12):
        raise ValueError(f"{source}: the parameters predict torques up to {model:.3g} {rec.units['torque']} on this "
                         f"recording, whose torque stays below {scale:.3g}; expected parameters in the "
                         "recording's units "
                         f"({rec.units['velocity']}, {rec.units['torque']})")


def _or(finding) -> str:
    """The other explanations the held-out blocks cannot tell from a named finding, in one phrase."""
    others = ([a["name"] for a in finding.alternatives]
              + [f"a {a['term']} term [{a['reading']}]" for a in finding.alternative_terms])
    return f" (or {' or '.join(others)}: the held-out blocks do not tell them apart)" if others else ""
