"""Plot 'creep' from the raw results written by run.py (PNG in the same folder)."""

from pathlib import Path

from lugre_jax.reproduce._experiment import plot_main

if __name__ == "__main__":
    plot_main("creep", Path(__file__).with_name("results"))
