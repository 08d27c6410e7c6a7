"""Plot 'fig13' from the raw results written by run.py (PNG in the same folder)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import plot_main  # noqa: E402

if __name__ == "__main__":
    plot_main("fig13", Path(__file__).with_name("results"))
