"""Regenerate data/stribeck_paper_like.csv (synthetic; see data/README.md).

    python data/make_stribeck_data.py [--seed 284] [--out data/stribeck_paper_like.csv]
"""

import argparse
from pathlib import Path

from lugre_jax.identify._data_gen import PAPER_LIKE_SEED, write_paper_like_csv


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=PAPER_LIKE_SEED)
    ap.add_argument("--out", default=str(Path(__file__).with_name("stribeck_paper_like.csv")))
    a = ap.parse_args()
    d = write_paper_like_csv(a.out, seed=a.seed)
    print(f"wrote {a.out}: {len(d)} set-points, {int(d.count.sum())} samples")


if __name__ == "__main__":
    main()
