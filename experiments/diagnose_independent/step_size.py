"""The naming test's size on effect-free recordings, from committed study rows: per measured-sensor
kind and torque-noise colour (white, or AR(1)), how often the first greedy step's smallest
family-wise p-value (``p_family``, min-P over the candidates) is at or below the naming bar
``alpha/3``, against the bar itself, which is what the test's null promises; how often a raw
p-value (one candidate) is at or below 0.05; and how often a candidate was finally named (after
the plausibility, identifiability, held-out and rival checks). Binomial 95 % intervals
(Clopper-Pearson, scipy) go with each share. Reads the studies' ``runs_<study>.jsonl``; writes
nothing.

    python experiments/diagnose_independent/step_size.py --studies calib46,calib47
"""

from __future__ import annotations

import argparse
from collections import defaultdict
from pathlib import Path

from scipy.stats import binomtest

from lugre_jax.diagnose import CANDIDATES, DiagnoseConfig
from plot import load

ALPHA = DiagnoseConfig().alpha
BAR = DiagnoseConfig().alpha_name * (1.0 + 1e-9)  # the diagnosis's rule, with its tolerance for 2/120 against 0.05/3


def _share(k: int, n: int) -> str:
    ci = binomtest(k, n).proportion_ci(0.95) if n else None
    return f"{k}/{n} ({100 * k / n:.1f} %, 95 % CI {100 * ci.low:.1f}-{100 * ci.high:.1f})" if n else "-"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--studies", required=True, help="comma-separated effect-free study names")
    a = ap.parse_args()
    res = Path(__file__).resolve().with_name("results")
    rec, raw, named = defaultdict(list), defaultdict(list), defaultdict(list)
    flagged = []
    for study in a.studies.split(","):
        path = res / study / f"runs_{study}.jsonl"
        if not path.exists():
            raise SystemExit(f"{path}: no such study results")
        for r in load(path):  # the first run of each recording
            tests = [t for t in r.get("step1_tests") or [] if "p_family" in t]
            if r.get("expected", "none") != "none" or not tests:
                continue
            sensors = "+".join(s for s, on in (("position", r.get("position_column", True)),
                                               ("velocity", r.get("velocity_column", True))) if on)
            low = [t for t in tests if t["p_family"] <= BAR]
            colour = "white" if not r.get("torque_noise_ar") else "AR(1)"
            for kind in (f"{sensors}, {colour}", sensors, colour, "all"):
                rec[kind].append(bool(low))
                raw[kind] += [t["p_raw"] <= ALPHA for t in tests]
                named[kind].append(any(c in r["verdict"] for c in CANDIDATES))
            if low:
                flagged.append(f"{r['key']} ({sensors}, {colour}): " + ", ".join(t["name"] for t in low)
                               + f"; verdict {r['verdict']}")
    print(f"effect-free rows of {a.studies}; the naming bar alpha/3 = {ALPHA / 3:.4f}, a raw test's level {ALPHA}\n")
    print("| sensors, torque noise | step 1 below the bar (rows) | raw p <= 0.05 (tests) | named (rows) |")
    print("|---|---|---|---|")
    for kind in sorted(rec, key=lambda k: (k == "all", "," not in k, k)):
        print(f"| {kind} | {_share(sum(rec[kind]), len(rec[kind]))} | {_share(sum(raw[kind]), len(raw[kind]))} | "
              f"{_share(sum(named[kind]), len(named[kind]))} |")
    print("\nrows below the bar:\n" + "\n".join(f"* {f}" for f in flagged))


if __name__ == "__main__":
    main()
