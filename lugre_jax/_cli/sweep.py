"""``lugre-jax sweep SPEC.json --out DIR``: a sensitivity sweep (sobol / lhs / grid) of a scenario.

Resumable: run the same command again after an interruption (even SIGKILL) and it continues. Many
processes or hosts: give each the same ``--coordinator HOST:PORT --num-processes N`` and its own
``--process-id K`` (``jax.distributed``); DIR must be a folder they all see.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from ._args import add_quiet, check_input
from ._outputs import _check_parent, _writable

# The sweep runner's own state file in --out (SPEC hash, point and chunk counts).
SWEEP_STATE = "sweep_state.json"


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="sensitivity sweep of a scenario: Sobol' indices, LHS or grid (SPEC JSON)",
                       description="Run a sweep SPEC (see docs/sweeps.md) into DIR: samples, outputs per point, "
                                   "indices.json (SALib's keys), figures. Rerun the same command to resume.")
    p.add_argument("spec", help="sweep SPEC JSON")
    p.add_argument("--out", required=True,
                   help="output folder: new, empty, or a sweep of the same SPEC, which resumes (another SPEC's "
                        "folder is refused)")
    p.add_argument("--no-shard", action="store_true", help="run each chunk on one local device")
    p.add_argument("--max-chunks", type=int, default=None,
                   help="stop after computing this many chunks (run again to continue)")
    add_quiet(p)
    p.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    p.add_argument("--coordinator", help="jax.distributed coordinator HOST:PORT (many processes)")
    p.add_argument("--num-processes", type=int, default=None, help="jax.distributed: number of processes")
    p.add_argument("--process-id", type=int, default=None, help="jax.distributed: this process's rank")


def check(args) -> None:
    """Options and the output folder, before the package loads (whether a folder with a sweep holds
    the same SPEC is checked by the runner, which needs the SPEC)."""
    dist = (args.coordinator, args.num_processes, args.process_id)
    if any(x is not None for x in dist) and not all(x is not None for x in dist):
        raise ValueError("--coordinator, --num-processes and --process-id go together")
    if args.max_chunks is not None and args.max_chunks < 1:
        raise ValueError(f"--max-chunks: expected a positive integer, got {args.max_chunks}")
    check_input(args.spec, "a sweep SPEC JSON file (docs/sweeps.md)")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {args.out}: is an existing file; expected a folder (new, empty, or a sweep of the "
                         "same SPEC, which resumes)")
    # Process 0 of a distributed sweep may be filling the folder right now (its state file comes last).
    first = args.process_id in (None, 0)
    if first and out.is_dir() and any(out.iterdir()) and not (out / SWEEP_STATE).is_file():
        raise ValueError(f"--out {args.out}: exists, is not empty and holds no {SWEEP_STATE} (not a sweep), so it "
                         "will not be used; expected a new or empty folder, or a sweep of the same SPEC")
    if not out.is_dir():
        _check_parent(args.out, out, "--out", "folder")
    elif (why := _writable(out)) is not None:
        raise ValueError(f"--out {args.out}: cannot write in it ({why}); expected a writable folder")


def _physical_memory_bytes() -> int | None:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, OSError, ValueError):
        return None


def _points(sampler, n: int, n_vars: int) -> int:
    from ..sweep import Grid, Saltelli

    if isinstance(sampler, Saltelli):
        return n * sampler.group_size(n_vars)
    if isinstance(sampler, Grid):
        levels = list(sampler.levels) if sampler.levels else [n] * n_vars
        p = 1
        for k in levels:
            p *= int(k)
        return p
    return n


def memory_estimate(spec, n: int | None = None) -> tuple[int, int]:
    """(points, bytes): the points of ``spec`` (with ``n`` in place of ``spec.n``) and the memory a
    run holds at its peak, in float64 words per point: the samples (4 x names: the sampler's
    intermediate copies), the outputs read back for the analysis (names + outputs) and, for Sobol',
    the bootstrap's resampled copies (1.5 x resamples). Calibrated on ``sobol_analyze`` and
    ``saltelli_sample`` alone (docs/performance.md); the simulator's per-chunk buffers come on top."""
    from ..sweep import Saltelli

    n = spec.n if n is None else n
    d, k = len(spec.names), len(spec.outputs)
    p = _points(spec.sampler, n, d)
    per_point = 4 * d + (d + k) + (1.5 * spec.num_resamples if isinstance(spec.sampler, Saltelli) else 0)
    return p, int(8 * p * per_point)


def check_memory(spec, where: str, limit: int | None) -> None:
    """Refuse, in one line with the figure and the largest "n" that fits, a SPEC whose arrays alone
    exceed ``limit`` bytes (the machine's physical memory)."""
    from ..sweep import Grid, Saltelli

    if limit is None:
        return
    points, need = memory_estimate(spec)
    if need <= limit:
        return
    fits = 0
    if isinstance(spec.sampler, Saltelli):
        m = 1
        while memory_estimate(spec, 2 * m)[1] <= limit:
            m *= 2
        fits = m if memory_estimate(spec, m)[1] <= limit else 0
        how = f'"n" at most {fits:,} (a power of two)'
    elif isinstance(spec.sampler, Grid):
        lv = 2
        while memory_estimate(spec, lv + 1)[1] <= limit:
            lv += 1
        how = f'at most {lv} levels per name' if not spec.sampler.levels else "fewer \"levels\""
    else:
        lo, hi = 1, spec.n
        while lo < hi:
            mid = (lo + hi + 1) // 2
            lo, hi = (mid, hi) if memory_estimate(spec, mid)[1] <= limit else (lo, mid - 1)
        how = f'"n" at most {lo:,}'
    gib = 1024 ** 3
    raise ValueError(f'{where}: "n" {spec.n:,} gives {points:,} points: about {need / gib:,.1f} GiB of arrays '
                     f"(samples, outputs{', bootstrap' if isinstance(spec.sampler, Saltelli) else ''}), more than "
                     f"this machine's {limit / gib:,.1f} GiB; expected {how}; split the study into sweeps of that "
                     'size with different "seed" values (each its own --out), or run it on a larger machine')


def run(args) -> int:
    from ..sweep import load_spec, run_sweep

    if args.coordinator is not None:
        # Before any JAX computation (building the scenario's arrays is one).
        import jax

        jax.distributed.initialize(args.coordinator, num_processes=args.num_processes, process_id=args.process_id)
    spec = load_spec(args.spec)  # every check before any file is written
    check_memory(spec, args.spec, _physical_memory_bytes())
    res = run_sweep(spec, args.out, progress=not args.quiet, shard=False if args.no_shard else None,
                    max_chunks=args.max_chunks, figures=not args.no_figures)
    summary = {k: v for k, v in res.to_json().items() if k != "indices"}
    print(json.dumps(summary))
    return 0
