"""``lugre-jax sweep SPEC.json --out DIR``: a sensitivity sweep (sobol / lhs / grid) of a scenario.

Resumable: run the same command again after an interruption (even SIGKILL) and it continues. Many
processes or hosts: give each the same ``--coordinator HOST:PORT --num-processes N`` and its own
``--process-id K`` (``jax.distributed``); DIR must be a folder they all see.
"""

from __future__ import annotations

import argparse
import json


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="sensitivity sweep of a scenario: Sobol' indices, LHS or grid (SPEC JSON)",
                       description="Run a sweep SPEC (see docs/sweeps.md) into DIR: samples, outputs per point, "
                                   "indices.json (SALib's keys), figures. Rerun the same command to resume.")
    p.add_argument("spec", help="sweep SPEC JSON")
    p.add_argument("--out", required=True, help="output folder (created; a folder of another SPEC is refused)")
    p.add_argument("--no-shard", action="store_true", help="run each chunk on one local device")
    p.add_argument("--max-chunks", type=int, default=None,
                   help="stop after computing this many chunks (run again to continue)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    p.add_argument("--coordinator", help="jax.distributed coordinator HOST:PORT (many processes)")
    p.add_argument("--num-processes", type=int, default=None, help="jax.distributed: number of processes")
    p.add_argument("--process-id", type=int, default=None, help="jax.distributed: this process's rank")


def run(args) -> int:
    from ..sweep import load_spec, run_sweep

    dist = (args.coordinator, args.num_processes, args.process_id)
    if any(x is not None for x in dist) and not all(x is not None for x in dist):
        raise ValueError("--coordinator, --num-processes and --process-id go together")
    if args.max_chunks is not None and args.max_chunks < 1:
        raise ValueError(f"--max-chunks: expected a positive integer, got {args.max_chunks}")
    if args.coordinator is not None:
        # Before any JAX computation (building the scenario's arrays is one).
        import jax

        jax.distributed.initialize(args.coordinator, num_processes=args.num_processes, process_id=args.process_id)
    spec = load_spec(args.spec)  # every check before any file is written
    res = run_sweep(spec, args.out, progress=not args.no_progress, shard=False if args.no_shard else None,
                    max_chunks=args.max_chunks, figures=not args.no_figures)
    summary = {k: v for k, v in res.to_json().items() if k != "indices"}
    print(json.dumps(summary))
    return 0
