"""Summary figure of the EMPS study from ``<results>/RESULT.json``: per model, the closed-loop force
error and the benchmark-protocol RMSE on the held-out part (or the validation run), beside the
published anchors (closed-loop force 5.85 % on the estimation run, 8.94 % on the validation run;
neural state-space model ~8 mm on the validation run) and our simulation of the published model.

    python experiments/emps/plot.py [--results experiments/emps/results]
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for the shared _common.py
from _common import results_for_plot  # noqa: E402


def main(argv=None):
    res = results_for_plot(__doc__, Path(__file__).resolve().with_name("results"), ("RESULT.json",), argv)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lugre_jax.io import save_figure

    j = json.loads((res / "RESULT.json").read_text())
    run = "validation" if j["validation"] else "held_out"
    cl_run = "validation_pulses_estimated" if j["validation_has_pulses"] else run
    names = list(j["models"])
    force = [j["models"][n]["runs"][cl_run]["closed_loop"]["force_pct"] for n in names]
    rmse = [j["models"][n]["runs"][run]["benchmark"]["rmse_mm"] for n in names]
    ref = j["published_model_simulated"]["symmetric"]
    pub_cl, pub_b = ref["closed_loop"][cl_run]["force_pct"], ref["benchmark"][run]["rmse_mm"]
    panels = [  # values, colour, published anchor and its label, published model simulated, y label
        (force, "tab:blue", 5.85, "published closed loop, estimation run (5.85 %)",
         pub_cl, f"published model in our simulation ({pub_cl:.2f} %)", f"closed-loop force error, {cl_run} [%]"),
        (rmse, "tab:green", 8.0, "neural state-space model, validation run (~8 mm)",
         pub_b, f"published model ({pub_b:.2f} mm)", f"protocol (vir alone) RMSE, {run} [mm]"),
    ]
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for a, (values, colour, anchor, anchor_label, pub, pub_label, ylabel) in zip(ax, panels):
        a.bar(names, values, color=colour)
        a.axhline(anchor, color="r", ls="--", label=anchor_label)
        a.axhline(pub, color="k", ls=":", label=pub_label)
        a.set_ylabel(ylabel)
        a.legend(fontsize=8)
        a.tick_params(axis="x", rotation=20)
    fig.tight_layout()
    save_figure(fig, res / "summary.png")
    print(f"wrote {res / 'summary.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
