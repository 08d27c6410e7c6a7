"""Render Table 1 (paper vs regenerated) from experiments/table1/results/ as PNG and Markdown."""

import json
import sys
from pathlib import Path

import matplotlib.pyplot as plt

from lugre_jax.io import atomic_path, save_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402

NAMES = ("Fc", "Fs", "vs", "sigma2")


def _cell(p, se, n):
    if n not in p:
        return "/"
    s = se.get(n)
    return f"{p[n]:.4f}" + ("" if s is None else f" ± {s:.2g}")


def main(argv=None) -> None:
    r = results_for_plot(__doc__, Path(__file__).with_name("results"), ("table1.json",), argv)
    t = json.loads((r / "table1.json").read_text())
    header = ["source", "segment", "v range [deg/s]", "Fc [N*m]", "Fs [N*m]", "vs [deg/s]", "sigma2 [N*m*s/deg]", "RMS [N*m]", "evals"]
    rows = []
    edges = {"1": "0-0.05", "2": "0.05-1.2", "3": ">1.2"}
    for k, v in t["paper_table1"].items():
        rows.append(["paper Table 1", k, edges[k]] + [("/" if v[n] is None else f"{v[n]:.4f}") for n in NAMES] + ["", ""])
    for name, res in t["results"].items():
        for s in res["segments"]:
            lo, hi = s["velocity_range_deg_s"]
            rows.append([name, s["segment"], f"{lo:.3g}-{hi:.3g}"] + [_cell(s["parameters"], s["standard_errors"], n) for n in NAMES]
                        + [f"{s['rms_nm']:.3g}", str(s["evaluations"])])
    md = "| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n" + "".join("| " + " | ".join(x) + " |\n" for x in rows)
    with atomic_path(r / "table1.md") as tmp:
        tmp.write_text(md)
    fig, ax = plt.subplots(figsize=(16, 0.32 * len(rows) + 1))
    ax.axis("off")
    tab = ax.table(cellText=rows, colLabels=header, loc="center", cellLoc="center")
    tab.auto_set_font_size(False)
    tab.set_fontsize(7)
    tab.auto_set_column_width(list(range(len(header))))
    ax.set_title("Table 1: paper vs regenerated from the shipped synthetic data (value ± standard error)", fontsize=9)
    save_figure(fig, r / "table1.png")
    print(md)


if __name__ == "__main__":
    main()
