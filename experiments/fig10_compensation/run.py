"""Reproduce 'fig10' of Li et al., Electronics 2020, 9, 284 in simulation (see lugre_jax.reproduce).

    python experiments/fig10_compensation/run.py [--out DIR] [--quick] [--setup-cache JSON]

Writes fig10.json (metrics, settings, set-up) and, for trajectory scenarios, fig10_traces.npz. The
identified set-up (observers, gains) is cached in OUT/setup.json; pass --setup-cache to share one.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import run_main  # noqa: E402

if __name__ == "__main__":
    run_main("fig10", __doc__, Path(__file__).with_name("results"))
