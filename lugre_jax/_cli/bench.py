"""``lugre-jax bench [--quick] --out BENCH.json``: simulator speed, all ratios from one run."""

from __future__ import annotations

import argparse

from ._args import add_quiet
from ._outputs import check_outputs


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("bench", help="benchmark the batched simulator against a scipy loop",
                       description="Batched JAX simulator vs a Python loop of scipy LSODA, gradient "
                       "cost vs forward cost, 1 vs 2 devices, peak memory. Writes JSON.")
    p.add_argument("--out", required=True, metavar="BENCH.json", help="JSON file to write")
    p.add_argument("--quick", action="store_true", help="smaller batches (a few minutes)")
    add_quiet(p)


def check(args) -> None:
    check_outputs(args, out=".json")


def run(args) -> int:
    from ..io import write_json
    from ._bench import run_benchmark
    from ._outputs import Outputs

    with Outputs() as outs:
        out = outs.file(args.out, "--out", ".json")  # checked before minutes of work
        if args.quiet:
            from tqdm.auto import tqdm

            res = run_benchmark(quick=args.quick, progress=tqdm(disable=True))
        else:
            res = run_benchmark(quick=args.quick)
        write_json(out, res)
    keys = [k for k in res if k.startswith(("speedup", "two_devices"))]
    for k in keys:
        print(f"{k}: {res[k]:.1f}")
    for k in ("jacobian_b1", "jacobian_b100", "jacobian_b1000"):
        if k in res:
            j = res[k]
            print(f"{k}: Jacobian (6 params) / forward solve = {j['jacobian_over_forward']:.2f} "
                  f"({j['cheaper_mode']} mode; forward mode {j['best_forward_mode_over_forward']:.2f}, "
                  f"reverse mode {j['reverse_over_forward']:.2f})")
    m = res["memory_one_call"]
    print(f"{m['lanes']} lanes in one call: {m['seconds_incl_compile']:.1f} s, peak RSS {m['peak_rss_gb']:.2f} GB")
    return 0
