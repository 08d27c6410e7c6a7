"""``lugre-jax simulate SCENARIO.json --out TRAJ.csv [--plot TRAJ.png] [--force]``."""

from __future__ import annotations

import argparse
import sys
import time

from ._args import HelpFormatter, add_quiet, check_input
from ._outputs import Outputs, check_output_size, check_outputs, csv_output_bytes

_COLUMNS = 7


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help="simulate one scenario (JSON) and write its trajectory (CSV)",
                       formatter_class=HelpFormatter,
                       description="Simulate the joint of a scenario file. Units: deg, deg/s, N*m, s.\n"
                                   "Without a 'solver' section the scenario is solved with error-controlled "
                                   "stepping that lands on the reference's steps (lugre_jax.Adaptive).")
    p.add_argument("scenario", help="scenario JSON (schema: lugre_jax/scenario/_build.py)")
    p.add_argument("--out", required=True, help="trajectory CSV to write (an existing file is replaced atomically)")
    p.add_argument("--plot", help="optional PNG figure of the trajectory")
    p.add_argument("--force", action="store_true", help="write a CSV larger than 500 MB")
    add_quiet(p)


def passivity_notes(friction) -> list[str]:
    """One line per LuGre set of ``friction`` (a segment of a Segmented model too) that is not
    passive, as LuGre(require_passive=True) words it; the scenario builds it anyway (on purpose, as
    the paper's segment 1), so this is said on the progress channel, not as an error."""
    from ..friction import LuGre, Segmented

    out = []
    for m in friction.segments if isinstance(friction, Segmented) else (friction,):
        if isinstance(m, LuGre):
            try:
                LuGre(Fc=m.Fc, Fs=m.Fs, vs=m.vs, sigma2=m.sigma2, sigma0=m.sigma0, sigma1=m.sigma1, delta=m.delta,
                      require_passive=True)
            except ValueError as e:
                out.append(str(e))
    return out


def check(args) -> None:
    check_input(args.scenario, "a scenario JSON file (schema: lugre_jax/scenario/_build.py)")
    check_outputs(args, out=".csv", plot=".png")


def run(args) -> int:
    import numpy as np

    from .. import RESULT_NONFINITE, RESULT_OK, result_name, simulate
    from ..io import write_csv
    from ..scenario import load_scenario

    # Progress on a terminal only: a failure's message stays the one line on stderr in logs and pipes.
    quiet = args.quiet or not sys.stderr.isatty()
    say = (lambda *a: None) if quiet else (lambda msg: print(f"simulate: {msg}", file=sys.stderr, flush=True))
    with Outputs() as outs:
        out = outs.file(args.out, "--out", ".csv")
        plot = outs.file(args.plot, "--plot", ".png") if args.plot else None
        system, opts = load_scenario(args.scenario)
        for note in passivity_notes(system.friction):
            say(f"note: {note}")
        n = int(round(opts["duration_s"] * opts["sample_hz"])) + 1
        check_output_size(csv_output_bytes(n, _COLUMNS), "--out", args.out, args.force)
        stepping = opts.get("stepping")
        _check_step_budget(stepping, opts["duration_s"], args.scenario)
        say(f"{n:,} samples, {'default Adaptive' if stepping is None else stepping.describe()}; compiling ...")
        t0 = time.perf_counter()
        sol = simulate(system, opts["duration_s"], opts["sample_hz"], stepping=stepping)
        sol.theta.block_until_ready()
        say(f"solver ran {time.perf_counter() - t0:.1f} s (compilation included; a second run reuses it)")
        if int(sol.result) != RESULT_OK:
            raise ValueError(
                f"{args.scenario}: the solver failed (result {result_name(int(sol.result))}: "
                + ("state blew up; try a smaller solver.dt or solver.method \"adaptive\")"
                   if int(sol.result) == RESULT_NONFINITE
                   else "adaptive solver gave up; raise solver.max_steps, loosen rtol/atol, or use "
                        "solver.name \"kvaerno5\" for a stiff system)")
            )
        cols = {
            "time_s": sol.ts, "position_deg": sol.theta, "velocity_deg_s": sol.omega,
            "torque_nm": sol.torque_nm, "z_deg": sol.z, "position_ref_deg": sol.theta_ref,
            "velocity_ref_deg_s": sol.v_ref,
        }
        cols = {k: np.asarray(v) for k, v in cols.items()}
        write_csv(out, _row_chunks(cols, n, args.quiet, args.out))
        if plot is not None:
            _plot(cols, plot)
    say(f"wrote {args.out}" + (f" and {args.plot}" if args.plot else ""))
    return 0


_WRITE_CHUNK_ROWS = 1_000_000  # rows per slice handed to the writer: no full-size copy, a progress step


def _row_chunks(cols: dict, n: int, quiet: bool, name: str):
    """The trajectory in row slices (views, not copies), with progress (a bar on a terminal, plain
    lines in a log): writing a CSV of millions of rows takes longer than solving for it."""
    from tqdm.auto import tqdm

    with tqdm(total=n, desc=f"simulate: writing {name}", unit=" rows", unit_scale=True,
              disable=quiet or n <= _WRITE_CHUNK_ROWS, file=sys.stderr) as bar:
        for i in range(0, n, _WRITE_CHUNK_ROWS):
            chunk = {k: v[i:i + _WRITE_CHUNK_ROWS] for k, v in cols.items()}
            yield chunk
            bar.update(len(chunk["time_s"]))


def _check_step_budget(stepping, duration_s: float, scenario) -> None:
    """Refuse before compiling a run the adaptive solver cannot finish: it takes steps of at most
    ``dtmax``, so it needs at least duration / dtmax of its ``max_steps``."""
    from .. import Adaptive

    stepping = Adaptive() if stepping is None else stepping
    if isinstance(stepping, Adaptive) and duration_s / stepping.dtmax > stepping.max_steps:
        need = int(duration_s / stepping.dtmax) + 1
        raise ValueError(
            f"{scenario}: duration_s {duration_s:g} s needs at least {need:,} adaptive steps (steps of at most "
            f"{stepping.dtmax:g} s), more than solver.max_steps = {stepping.max_steps:,}; expected solver.max_steps "
            f">= {need:,}, or a solver section with \"method\": \"fixed\"")


def _plot(cols, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..io import save_figure

    t = cols["time_s"]
    fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ax[0].plot(t, cols["position_ref_deg"], "r--", label="reference")
    ax[0].plot(t, cols["position_deg"], "k", label="joint")
    ax[0].set_ylabel("position [deg]")
    ax[0].legend()
    ax[1].plot(t, cols["velocity_ref_deg_s"], "r--", label="reference")
    ax[1].plot(t, cols["velocity_deg_s"], "k", label="joint")
    ax[1].set_ylabel("velocity [deg/s]")
    ax[2].plot(t, cols["torque_nm"], "b", label="actuator torque")
    ax[2].set_ylabel("torque [N*m]")
    ax[2].set_xlabel("time [s]")
    ax[2].legend()
    save_figure(fig, path)
