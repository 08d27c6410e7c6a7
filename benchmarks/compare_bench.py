"""Compare simulator benchmark runs (``lugre-jax bench --out X.json``) of two code versions, run
alternately on the same machine: our side only (the scipy loops' speed drifts by itself), as a
markdown table of the median over each version's runs and the ratio new/old.

    python benchmarks/compare_bench.py --old old_1.json old_2.json --new new_1.json new_2.json
"""

from __future__ import annotations

import argparse
import json
import statistics


def figures(d: dict) -> dict:
    out = {}
    for r in d["throughput"]:
        out[f"throughput {r['solver']} dt={r['dt_s']} batch={r['batch']} devices={r['devices']} [sims/s]"] = r["sims_per_s"]
    for k, v in d.items():
        if k.startswith("jacobian_b") and isinstance(v, dict):
            for f in ("forward_s", "grad_reverse_s", "jacfwd_s"):
                if f in v:
                    out[f"{k} {f} [s]"] = v[f]
    m = d.get("memory_one_call")
    if isinstance(m, dict):
        for f in ("seconds_incl_compile", "peak_rss_gb"):
            if f in m:
                out[f"memory_one_call {f}"] = m[f]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--old", nargs="+", required=True)
    ap.add_argument("--new", nargs="+", required=True)
    a = ap.parse_args(argv)
    old = [figures(json.load(open(p))) for p in a.old]
    new = [figures(json.load(open(p))) for p in a.new]
    keys = [k for k in old[0] if all(k in r for r in old + new)]
    print("| figure | old (runs) | new (runs) | new/old (medians) |\n|---|---|---|---|")
    for k in keys:
        o, n = [r[k] for r in old], [r[k] for r in new]
        fmt = lambda xs: ", ".join(f"{x:.4g}" for x in xs)  # noqa: E731
        print(f"| {k} | {fmt(o)} | {fmt(n)} | {statistics.median(n) / statistics.median(o):.2f} |")


if __name__ == "__main__":
    main()
