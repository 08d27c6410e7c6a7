"""``lugre-jax reproduce --out DIR [--quick]``: re-run the control experiments of Li et al.,
Electronics 2020, 9, 284 (Figs. 8-15, Table 2, sections 4.2.5, 5, 6) in simulation and write every
figure (PNG), the raw results (JSON, NPZ) and a report that puts the paper's claim beside our number
for each figure and table (REPORT.md, report.json).

The "real joint" is the paper's own Tables 1-2 model; the compensators use models identified from
noisy steady-state data by the paper's optimisers (never the plant itself). The full run takes a few
minutes; ``--quick`` (reduced optimiser settings, no time-series fits, no seed study or excitation
design) about a third of that.
"""

from __future__ import annotations

from ._args import HelpFormatter, add_quiet, check_input, comma_choices, plain
from ._outputs import FOLDER, check_output_file, check_outputs

CHOICES = ("fig08", "fig09", "fig10", "fig12", "fig13", "fig14", "fig15", "beyond", "creep", "table2", "design")


def add_parser(subparsers) -> None:
    p = subparsers.add_parser("reproduce", help="reproduce the paper's figures/tables and write a report",
                              description=plain(__doc__), formatter_class=HelpFormatter)
    p.add_argument("--out", required=True, metavar="DIR",
                   help="output folder: new, empty, or an earlier reproduce result (it holds MANIFEST.json), which is "
                        "replaced only when the new run has finished")
    p.add_argument("--quick", action="store_true", help="reduced settings for a fast smoke run (tests)")
    p.add_argument("--data", default=None, metavar="CSV",
                   help="steady-state Stribeck CSV to identify from (default: the shipped data/stribeck_paper_like.csv)")
    p.add_argument("--only", default=None, metavar="LIST",
                   help=f"comma-separated subset of {','.join(CHOICES)} (Fig. 10a-b rows need fig09 too)")
    p.add_argument("--seeds", type=int, default=None,
                   help="extra optimiser seeds for the PSO/GA dead-zone study (default 3; 0 with --quick)")
    p.add_argument("--setup-cache", default=None, metavar="JSON",
                   help="load the identified set-up from this JSON if it exists, else write it there")
    add_quiet(p, "progress")


def check(args) -> None:
    """Everything the run will write, and its options, before the package loads."""
    from pathlib import Path

    if args.only:
        comma_choices(args.only, CHOICES, "--only")
    if args.seeds is not None and args.seeds < 0:
        raise ValueError(f"--seeds must be >= 0, got {args.seeds}")
    if args.data is not None:
        check_input(args.data, "a steady-state Stribeck CSV (velocity_deg_s,torque_nm[,branch])", flag="--data")
    check_outputs(args, command="reproduce", out=FOLDER)
    if args.setup_cache is not None:
        if Path(args.out).resolve() in Path(args.setup_cache).resolve().parents:
            raise ValueError(f"--setup-cache {args.setup_cache}: inside --out {args.out}, which is replaced as a "
                             "whole at the end; expected a path outside it")
        if not Path(args.setup_cache).is_file():
            check_output_file(args.setup_cache, "--setup-cache", (".json",))


def run(args) -> int:
    from pathlib import Path

    from ..io import load_stribeck_csv

    only = comma_choices(args.only, CHOICES, "--only") if args.only else None
    # The data are read before the minutes of work start (check() has seen the paths).
    if args.data is not None:
        load_stribeck_csv(args.data)
    from ..reproduce import run_all

    res = run_all(args.out, quick=args.quick, data_path=args.data, only=only, seeds=args.seeds,
                  progress=not args.quiet, setup_cache=args.setup_cache)
    print(f"wrote {len(res['rows'])} report rows to {Path(args.out) / 'REPORT.md'}")
    for r in res["rows"]:
        print(f"  {r['id']:<45} {r['verdict']}")
    return 0
