"""Run every reproduced experiment and write figures + REPORT.md + report.json (the ``lugre-jax
reproduce`` command). Li et al., Electronics 2020, 9, 284, sections 4.2.5, 5 and 6."""

from __future__ import annotations

import time
from pathlib import Path

import jax

from ..io import atomic_folder, write_json
from . import _scenarios as sc
from ._plots import PLOTTERS, plot_design, plot_table2, save_traces_npz
from ._report import build_rows, write_report
from ._setup import MODELS, Setup, build_setup

SCENARIOS = {"fig08": sc.fig08, "fig09": sc.fig09, "fig10": sc.fig10, "fig12": sc.fig12, "fig13": sc.fig13,
             "fig14": sc.fig14, "fig15": sc.fig15, "beyond": sc.beyond, "creep": sc.creep_search}


def seed_study(setup: Setup, data_path=None, n_seeds: int = 3) -> dict:
    """Dead zone at 0.005 deg/s of PSO- and GA-identified (whole) compensation for ``n_seeds`` extra
    optimiser seeds: how much of Fig. 10c is the algorithm and how much the seed."""
    from ..dynamic import lugre_from_static, sigma1_eq18
    from ..identify import identify
    from ..io import load_stribeck_csv
    from ._setup import default_data_path

    data = load_stribeck_csv(default_data_path() if data_path is None else data_path)
    s0 = float(setup.presliding["sigma0_nm_per_deg"])
    out = {}
    for label in ("PSO whole", "GA whole"):
        scheme, method = MODELS[label]
        ctrls = {}
        for i in range(n_seeds):
            res = identify(data, scheme, method, key=jax.random.key(1000 + i))
            st = res.friction_model()
            obs = lugre_from_static(st, s0, max(float(sigma1_eq18(setup.J, s0, float(st.sigma2))), 0.0))
            from ..control import LuGreCompensated
            ctrls[f"{label} seed {i}"] = LuGreCompensated(inner=setup.velocity_pid(), observer=obs, k_obs=setup.k_obs, J_ff=setup.J)
        _, met = sc._step(setup, ctrls)
        out[label] = [met[k]["dead_zone_s"] for k in ctrls]
    return out


def run_all(out, *, quick: bool = False, data_path=None, only=None, seeds: int | None = None, progress: bool = True,
            setup_cache=None) -> dict:
    """Run the set-up, every scenario, Table 2 and the excitation design; write PNGs, raw results,
    REPORT.md and report.json under ``out``. Returns ``{"rows": [...], "results": {...}}``.

    The folder is built as a hidden temporary sibling and renamed to ``out`` only when everything is
    written (its MANIFEST.json last); an error or Ctrl-C leaves ``out`` as it was. ``out`` must be new,
    empty, or an earlier result (it holds a MANIFEST.json), which is then replaced: reruns are safe."""
    meta = dict(command="reproduce", quick=quick, only=None if only is None else sorted(only), seeds=seeds)
    with atomic_folder(out, meta=meta) as tmp:
        return _run_into(tmp, quick=quick, data_path=data_path, only=only, seeds=seeds, progress=progress,
                         setup_cache=setup_cache)


def _run_into(out: Path, *, quick, data_path, only, seeds, progress, setup_cache) -> dict:
    from tqdm.auto import tqdm

    from ._table2 import excitation_design, table2

    timings: dict = {}
    names = list(SCENARIOS) if only is None else [n for n in SCENARIOS if n in only]
    n_seeds = (0 if quick else 3) if seeds is None else int(seeds)
    t0 = time.perf_counter()
    with tqdm(total=2 + len(MODELS), desc="set-up: pre-sliding, ki grid, identification", disable=not progress) as pb:
        setup = build_setup(data_path, quick=quick, progress=pb, cache=setup_cache)
    timings["setup"] = time.perf_counter() - t0
    write_json(out / "setup.json", setup.as_dict())
    results: dict = {}
    extra = [("table2", table2)] + ([] if quick else [("design", excitation_design)])
    if only is not None:
        extra = [e for e in extra if e[0] in only]
    todo = [(n, SCENARIOS[n]) for n in names] + extra + ([("seeds", None)] if n_seeds > 0 else [])
    for name, fn in tqdm(todo, desc="experiments", disable=not progress):
        t = time.perf_counter()
        if name == "seeds":
            results[name] = seed_study(setup, data_path, n_seeds)
            write_json(out / "seeds.json", results[name])
        elif name in SCENARIOS:
            r = fn(setup)
            results[name] = r
            write_json(out / f"{name}.json", dict(metrics=r["metrics"], settings=r["settings"]))
            if r["traces"]:
                save_traces_npz(r, out / f"{name}_traces.npz")
            if name in PLOTTERS:
                PLOTTERS[name](r, out / f"{name}.png")
        else:
            r = fn(setup, quick=quick)
            results[name] = r
            write_json(out / f"{name}.json", r)
            if name == "design":
                plot_design(r, out / "excitation_design.png")
            else:
                plot_table2(r, out / "table2.png")
        timings[name] = time.perf_counter() - t
    rows = build_rows(results, setup)
    write_report(out, rows, setup, timings, quick)
    return dict(rows=rows, results=results, setup=setup)
