"""``lugre-jax identify DATA``: static (Stribeck) identification, whole or piecewise (paper section 4.2).

DATA is a Stribeck CSV (velocity_deg_s, torque_nm[, branch]) or an EPOS Studio steady-state folder.
Writes RESULT.json (``Identification.to_json()``: one entry per segment with velocity range,
Fc/Fs/vs/sigma2 with their units and bounds, loss, standard errors, optimiser steps, evaluations,
wall time) and optionally a PNG of the identified curve.
"""

from __future__ import annotations

from ._args import HelpFormatter, add_quiet, check_input, plain
from ._outputs import check_outputs


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "identify",
        help="identify static Stribeck parameters from steady-state data (whole or piecewise)",
        description=plain(__doc__),
        formatter_class=HelpFormatter,
    )
    p.add_argument("data", metavar="DATA", help="Stribeck CSV file or EPOS steady-state export folder")
    p.add_argument("--method", default="gapso", choices=["ga", "ga_real", "pso", "gapso", "cmaes", "de", "lm"],
                   help="optimiser: the paper's GA, real-coded GA, PSO or hybrid GA-PSO; CMA-ES, differential "
                        "evolution, or gradient least squares (lm)")
    p.add_argument("--scheme", default="piecewise", choices=["whole", "piecewise"],
                   help="one model over all velocities, or the paper's three velocity segments")
    p.add_argument("--model", default="stribeck", choices=["stribeck", "coulomb_viscous"],
                   help="model for --scheme whole (stribeck is eq. 10, coulomb_viscous is eq. 11)")
    p.add_argument("--refine", action="store_true", help="polish the best result with gradient least squares")
    p.add_argument("--seeds", type=int, default=1, help="independent optimiser runs (best is kept)")
    p.add_argument("--seed", type=int, default=0, help="base PRNG seed")
    p.add_argument("--direction", default="positive", choices=["positive", "negative"],
                   help="which velocity direction to identify (negative data are mirrored)")
    p.add_argument("--bounds", default="paper",
                   help="'paper' (Fc,Fs,sigma2 in [0,10], vs in [0,1]), 'auto' (scaled to the data) or NAME=LO:HI,...")
    p.add_argument("--edges", default=None, help="piecewise boundaries VMIN,VCRIT in deg/s (default: detected)")
    p.add_argument("--target", default="data", choices=["data", "sines"],
                   help="fit the averaged data, or the eq. (12) sum-of-sines curves (the paper's route)")
    p.add_argument("--out", required=True, metavar="RESULT.json",
                   help="result JSON to write (an existing file is replaced atomically)")
    p.add_argument("--plot", default=None, metavar="FIG.png", help="optional PNG of the identified curve")
    add_quiet(p, "status line")


def _edges(text: str | None) -> tuple[float, float] | None:
    import math

    if not text:
        return None
    try:
        edges = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise ValueError(f"--edges must be two numbers VMIN,VCRIT in deg/s, got {text!r}") from None
    if len(edges) != 2 or not all(math.isfinite(e) for e in edges) or not 0 <= edges[0] < edges[1]:
        raise ValueError(f"--edges must be two finite numbers 0 <= VMIN < VCRIT in deg/s, got {text!r}")
    return edges


def check(args) -> None:
    """Arguments and output paths, before the package loads."""
    if args.seeds < 1:
        raise ValueError(f"--seeds must be >= 1, got {args.seeds}")
    if args.scheme == "piecewise" and args.model != "stribeck":
        raise ValueError("--model applies to --scheme whole only (piecewise uses eq. 10 below and eq. 11 above v_crit)")
    _edges(args.edges)
    check_input(args.data, "a Stribeck CSV or an EPOS steady-state folder", "any")
    check_outputs(args, out=".json", plot=".png")


def plot_identification(res, path) -> None:
    """Identified curve(s) over the averaged data (Fig. 6 style)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from ..io import save_figure

    d = res.data
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for br, mk in (("accel", "o"), ("decel", "s")):
        m = (d.branch == br) & (d.velocity > 0)
        if m.any():
            ax.errorbar(d.velocity[m], d.torque[m], yerr=np.nan_to_num(2 * d.torque_se[m]), fmt=mk, ms=3,
                        alpha=0.6, label=f"data ({br}), +-2 SE")
    for s in res.segments:
        lo = max(s.v_range[0], float(np.min(s.velocity)) if s.velocity.size else s.v_range[0])
        v = np.linspace(lo, s.v_range[1], 300)
        ax.plot(v, np.asarray(s.model().steady_state(v)), "--" if s.branch == "decel" else "-", lw=2,
                label=f"segment {s.name}")
    if res.boundaries is not None:
        for vb in (res.boundaries.v_min, res.boundaries.v_crit):
            ax.axvline(vb, color="gray", lw=0.8, ls=":")
    ax.set_xlabel("velocity [deg/s]")
    ax.set_ylabel("friction torque [N*m]")
    ax.set_title(f"{res.scheme} identification ({res.method}), RMS {res.rms():.3g} N*m")
    ax.legend(fontsize=8)
    save_figure(fig, path)


MIN_SET_POINTS = {"whole": 4, "piecewise": 8}  # 4 parameters per model; piecewise fits 3 segments


def run(args) -> int:
    import sys
    import time

    import jax
    import numpy as np
    from tqdm.auto import tqdm

    from ..identify import identify
    from ..io import load_friction_data, write_json
    from ._outputs import Outputs

    edges = _edges(args.edges)
    t_start = time.perf_counter()
    with Outputs() as outs:
        out_path = outs.file(args.out, "--out", ".json")
        plot_path = outs.file(args.plot, "--plot", ".png") if args.plot else None
        data = load_friction_data(args.data)
        if args.direction == "negative":
            data = data.direction(-1)
        n_pts = int(np.unique(np.round(data.velocity[data.velocity > 0], 12)).size)
        need = MIN_SET_POINTS[args.scheme]
        if n_pts < need:
            raise ValueError(f"{args.data}: {n_pts} distinct {args.direction} velocity set-point(s); expected at least "
                             f"{need} to identify --scheme {args.scheme}")
        if args.bounds in ("paper", "", None):
            vmax, tmax = float(np.max(np.abs(data.velocity))), float(np.max(np.abs(data.torque)))
            if vmax > 10.0 or tmax < 1e-2:
                print(f"lugre-jax identify: note: the data span up to {vmax:.4g} deg/s and {tmax:.4g} N*m, "
                      "far from the "
                      "paper's ranges (vs in [0, 1] deg/s, Fc, Fs in [0, 10] N*m); consider --bounds auto",
                      file=sys.stderr)
        kw = dict(key=jax.random.key(args.seed), n_seeds=args.seeds, refine=args.refine, bounds=args.bounds)
        with tqdm(total=2, desc=f"identify ({args.scheme}, {args.method}): compile + optimise", disable=args.quiet or not sys.stderr.isatty(),
                  bar_format="{desc} {n_fmt}/{total_fmt} [{elapsed}]") as pb:
            if args.scheme == "piecewise":
                res = identify(data, "piecewise", args.method, edges=edges, target=args.target, **kw)
            else:
                res = identify(data, "whole", args.method, kind=args.model, **kw)
            pb.update(1)
            pb.set_description("identify: writing")
            out = res.to_json()
            out["command"] = dict(vars(args))
            write_json(out_path, out)
            if plot_path is not None:
                plot_identification(res, plot_path)
            pb.update(1)
    total = time.perf_counter() - t_start
    print(res.table())
    for s in res.segments:
        print(f"segment {s.name}: {s.uncertainty.statement}")
    # The optimiser's own time excludes compilation, which dominates a first (uncached) run.
    print(f"time: {total:.1f} s in total = compilation {res.compile_time:.1f} s + optimiser {res.wall_time:.2f} s "
          f"+ loading, uncertainty, plot and writing {max(total - res.compile_time - res.wall_time, 0.0):.1f} s")
    return 0
