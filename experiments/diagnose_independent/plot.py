"""Tables and figures of the independent-recording study (``run.py``): null recordings (verdict,
baseline-to-floor ratio), issue #20's recording kind, the concealed-level proof table, and the
held-out and fresh held-out sets; with ``--new`` the studies of the rebuilt diagnosis (calib,
fresh3, outside): the null rate of ``none``, the noise floor against the true torque noise std,
the exact-verdict rate, and for effects outside the library the dependence the report attributes.

    python experiments/diagnose_independent/plot.py [--out experiments/diagnose_independent/results]
    python experiments/diagnose_independent/plot.py --new

Writes ``summary.md`` (the tables quoted in docs/diagnosis_studies.md) and ``null_floor_ratio.png``, or
with ``--new`` ``summary_rebuilt.md``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from lugre_jax.io import save_figure


def load(path):
    if not path.exists():
        return []
    rows, seen = [], set()
    for x in path.read_text().splitlines():  # first run of each job kept (reruns append)
        if x.strip():
            r = json.loads(x)
            if r["key"] not in seen:
                seen.add(r["key"])
                rows.append(r)
    return rows


def null_table(null, title, figure):
    """Markdown lines of an effect-free study (and its floor-ratio figure where ``figure`` is given)."""
    lines = []
    if not null:
        return []
    none = sum(r["verdict"] == "none" for r in null)
    ratios = np.array([r["floor_ratio"] for r in null])
    lines += [f"## {title} ({len(null)})", "",
              f"`none` in {none}/{len(null)} ({100 * none / len(null):.0f} %); baseline validation RMSE / "
              f"estimated noise floor: median {np.median(ratios):.3f}, max {ratios.max():.3f}; "
              f"at most 1.1: {int(np.sum(ratios <= 1.1))}/{len(null)}; within 10 % either way (the floor "
              f"neither under- nor overestimated): {int(np.sum(np.abs(ratios - 1) <= 0.1))}/{len(null)}", "",
              "Torque noise: std, and the low-pass corner where it is coloured.", "",
              "| key | plant | excitation | fs | torque noise | vel. noise | quant. | measured | n | "
              "conditioning | unresolved | torque noise est. | kinematic noise est. | floor est. | ratio | verdict | s |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(null, key=lambda r: r["key"]):
        c = r["conditioning"]
        measured = "+".join(k for k, on in (("pos", r.get("position_column", True)),
                                            ("vel", r["velocity_column"])) if on)
        tn = c["torque_noise"]
        eiv = float(np.sqrt(max(r["noise_floor"] ** 2 - tn ** 2, 0.0)))
        hz = r.get("torque_noise_hz", 0.0)
        tn_set = f"{r['torque_noise']}" + (f" ({hz:g} Hz)" if hz else "")
        lines.append(f"| {r['key']} | {r['plant']} | {r['excitation']} | {r['fs']:.0f} | {tn_set} | "
                     f"{r['velocity_noise']} | {r['quantisation']} | {measured} | "
                     f"{r['n_samples']} | {c['source']} W={c['window']}{' order 5' if c.get('order', 3) == 5 else ''} | {c.get('unresolved_fraction', 0.0):.3f} | "
                     f"{tn:.4f} | {eiv:.4f} | {r['noise_floor']:.4f} | "
                     f"{r['floor_ratio']:.3f} | {r['verdict']} | {r['seconds_diagnose']:.0f} |")
    lines.append("")
    if figure is None:
        return lines
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 3.5))
    keys = [r["key"] for r in sorted(null, key=lambda r: r["key"])]
    rr = [r["floor_ratio"] for r in sorted(null, key=lambda r: r["key"])]
    col = ["C0" if r["verdict"] == "none" else "C3" for r in sorted(null, key=lambda r: r["key"])]
    ax.bar(range(len(rr)), rr, color=col)
    ax.axhline(1.1, color="k", ls="--", lw=0.8, label="10 % above / below the floor")
    ax.axhline(0.9, color="k", ls="--", lw=0.8)
    ax.set_ylim(min(0.85, min(rr) - 0.05), max(1.15, max(rr) + 0.02))
    ax.set_xticks(range(len(rr)), keys, rotation=90, fontsize=7)
    ax.set_ylabel("validation RMSE / noise floor")
    ax.set_title("Effect-free independent recordings (blue: verdict none, red: anything else)")
    ax.legend(fontsize=8)
    save_figure(fig, figure)
    return lines


def _dependence(row):
    """The signals the report's attribution names for the unexplained residual (REPORT
    ``missing_physics[...].params.attribution.signals``), with each term's coefficient, and the
    library terms a named candidate is listed with (``alternative_terms``: "or <term>"); '-' when
    there is none."""
    found = []
    for m in row.get("missing_physics") or []:
        att = ((m or {}).get("params") or {}).get("attribution") or {}
        for t in att.get("terms", []):
            found.append(f"{t['signal']} ({', '.join(f'{c:.3g}' for c in t['coefficients'])} {t['units'][0]})")
        found += [f"{m['name']} or {a['term']}" for a in (m or {}).get("alternative_terms", [])]
    return "; ".join(found) or "-"


def new_study_tables(out, suffix="", studies=("calib", "fresh3", "outside")):
    """Summary of the studies of the rebuilt diagnosis (results/<study>/runs_<study>.jsonl):
    verdict rates, and the noise floor against the TRUE torque noise std of each recording."""
    lines = []
    for study in studies:
        rows = load(out / (study + suffix) / f"runs_{study}.jsonl")
        if not rows:
            continue
        nulls = [r for r in rows if r["expected"] == "none"]
        effects = [r for r in rows if r["expected"] != "none"]
        lines += [f"## Study {study} ({len(rows)} rows)", ""]
        if nulls:
            ratios = np.array([r["floor_over_true_noise"] for r in nulls])
            none = sum(r["verdict"] == "none" for r in nulls)
            worst = nulls[int(np.argmax(np.abs(ratios - 1)))]
            lines += [f"Effect-free: `none` in {none}/{len(nulls)} ({100 * none / len(nulls):.0f} %); noise floor / "
                      f"true torque noise std: median {np.median(ratios):.3f}, min {ratios.min():.3f}, max "
                      f"{ratios.max():.3f}; within 10 %: {int(np.sum(np.abs(ratios - 1) <= 0.1))}/{len(nulls)} "
                      f"(farthest: {worst['key']}, {worst['floor_over_true_noise']:.3f})", ""]
            # the floor adds the kinematics' errors through the model, which a complete model's residual
            # keeps too; the torque channel's own estimate is compared on its own
            tn = np.array([r["baseline"]["torque_noise_nm"] / r["true_torque_noise_std"] for r in nulls
                           if isinstance(r.get("baseline"), dict) and "torque_noise_nm" in r["baseline"]])
            if tn.size:
                lines += [f"Torque noise estimate / true torque noise std: median {np.median(tn):.3f}, min "
                          f"{tn.min():.3f}, max {tn.max():.3f}; within 10 %: {int(np.sum(np.abs(tn - 1) <= 0.1))}/"
                          f"{tn.size}", ""]
        if effects:
            ok = sum(r["verdict"] == r["expected"] for r in effects)
            lines += [f"Effects: verdict exactly as expected (no extras) in {ok}/{len(effects)} "
                      f"({100 * ok / len(effects):.0f} %)", ""]
            if study == "outside":
                lines += [f"`unexplained` in {sum('unexplained' in r['named'] for r in effects)}/{len(effects)}", ""]
        secs = [r["seconds_diagnose"] for r in rows]
        lines += [f"Diagnosis time: median {np.median(secs):.0f} s, max {max(secs):.0f} s "
                  f"(samples: median {int(np.median([r['n_samples'] for r in rows]))}, max "
                  f"{max(r['n_samples'] for r in rows)})", "",
                  "| key | plant | loop | excitation | fs | sensors | noise (AR) | peak / noise | expected | verdict | "
                  "floor / true noise | val. RMSE before -> after | dependence reported | its CV RMSE before -> after | s |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(rows, key=lambda r: r["key"]):
            sensors = "+".join(k for k, on in (("pos", r.get("position_column", True)), ("vel", r["velocity_column"])) if on)
            exp = (r["expected"] + (f" ({r['expected_dependence']})" if r.get("expected_dependence") else "")
                   ).replace("|", "\\|")
            before, after = r.get("baseline_val_rmse"), r.get("improved_val_rmse")
            rmse = f"{before:.4f} -> {after:.4f}" if before is not None and after is not None else "-"
            peak = r.get("peak_over_noise")
            # the attribution's terms are not in the named model: their own held-out change
            att = r.get("attribution") if isinstance(r.get("attribution"), dict) else {}
            cv = (f"{att['cv_rmse_before_nm']:.4f} -> {att['cv_rmse_after_nm']:.4f}"
                  if att.get("terms") and "cv_rmse_after_nm" in att else "-")
            lines.append(f"| {r['key']} | {r['plant']} | {r.get('controller', 'pi')} | {r['excitation']} | {r['fs']:.0f} | "
                         f"{sensors} | {r['torque_noise']} ({r.get('torque_noise_ar', 0.0):g}) | "
                         f"{'-' if peak is None else f'{peak:.2f}'} | {exp} | {r['verdict']} | "
                         f"{r['floor_over_true_noise']:.3f} | {rmse} | {_dependence(r)} | {cv} | {r['seconds_diagnose']:.0f} |")
        lines.append("")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().with_name("results")))
    ap.add_argument("--new", action="store_true",
                    help="only the calib, fresh3 and outside studies, to <out>/summary_rebuilt<suffix>.md")
    ap.add_argument("--suffix", default="",
                    help="with --new: read <out>/<study><suffix>/ (a re-run into another folder, e.g. _final)")
    ap.add_argument("--studies", default="calib,fresh3,outside",
                    help="with --new: the studies to summarise (e.g. calib2,fresh4: then written to "
                         "<out>/summary_<studies joined by _>.md)")
    a = ap.parse_args()
    out = Path(a.out)
    if a.new:
        studies = tuple(x for x in a.studies.split(",") if x)
        lines = new_study_tables(out, a.suffix, studies)
        if not lines:
            print(f"no runs of {', '.join(studies)} under {out} (runs_<study>.jsonl in <out>/<study>/)")
            return
        default = studies == ("calib", "fresh3", "outside")
        name = f"summary_rebuilt{a.suffix}.md" if default else f"summary_{'_'.join(studies)}{a.suffix}.md"
        (out / name).write_text("\n".join(lines) + "\n")
        print("\n".join(lines))
        return
    null, proof = (load(out / f"runs_{s}.jsonl") for s in ("null", "proof"))
    issue = load(out / "issue_final" / "runs_issue.jsonl") or load(out / "runs_issue.jsonl")
    held = load(out / "heldout" / "runs_heldout.jsonl")
    held_null = [r for r in held if r["key"].startswith("held_null")]
    fresh, first = (load(out / "fresh" / f) for f in ("runs_fresh.jsonl", "runs_fresh_firstpass.jsonl"))
    lines = null_table(null, "Null recordings", out / "null_floor_ratio.png")
    lines += null_table(held_null, "Held-out null recordings (no threshold calibrated on them)", None)
    lines += null_table([r for r in first if r["key"].startswith("fresh_null")],
                        "Fresh held-out null recordings, first run (on 82fb22d)", None)
    lines += null_table([r for r in fresh if r["key"].startswith("fresh_null")],
                        "Fresh held-out null recordings, final code", None)
    for title, rows in (("Issue #20's recording kind", issue), ("Concealed level (proof)", proof),
                        ("Fresh held-out effects, first run (on 82fb22d)",
                         [r for r in first if r["key"].startswith("fresh_effect")]),
                        ("Fresh held-out effects, final code", [r for r in fresh if r["key"].startswith("fresh_effect")]),
                        ("Held-out: issue #20's recording kind, seeds 21 and 22",
                         [r for r in held if r["key"].startswith("held_issue")]),
                        ("Held-out: effects on the new plants and excitations",
                         [r for r in held if r["key"].startswith("held_effect")])):
        if not rows:
            continue
        ok = sum(r["correct"] for r in rows)
        lines += [f"## {title}: {ok}/{len(rows)} exactly right (extra claims count as wrong)", "",
                  "| key | true | true peak / noise | verdict | baseline ratio | val. RMSE before -> after | fitted | s |",
                  "|---|---|---|---|---|---|---|---|"]
        for r in rows:
            fit = "; ".join(f"{k}: " + ", ".join(f"{p}={v:.3g}" for p, v in d.items() if isinstance(v, float))
                            for k, d in r["fitted"].items() if k != "unexplained")
            lines.append(f"| {r['key']} | {'+'.join(r['true_effects']) or 'none'} | "
                         f"{r['true_peak_nm'] / r['torque_noise']:.2f} | {r['verdict']} | {r['floor_ratio']:.3f} | "
                         f"{r['baseline_val_rmse']:.4f} -> {r['improved_val_rmse']:.4f} | {fit} | "
                         f"{r['seconds_diagnose']:.0f} |")
        lines.append("")
    (out / "summary.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
