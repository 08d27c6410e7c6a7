"""What the experiment folders share (an application of lugre_jax, not part of the library): the
argument handling and results folder of every ``experiments/NAME/run.py`` and ``plot.py``, and the
driver of the folders that run one scenario of :mod:`lugre_jax.reproduce` (Li et al., Electronics
2020, 9, 284), and the EMPS data check that ``benchmarks/emps_fit.py`` uses too. Uses the public API only (``tests/test_public_api.py`` checks it).

A script in ``experiments/NAME/`` imports it with::

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # experiments/, for _common
    from _common import run_main
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path


def run_main(name: str, doc: str, default_out: Path, argv=None) -> None:
    """``run.py``: build (or load) the shared set-up, run scenario ``name``, write ``NAME.json`` (+ traces)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(default_out), help="results folder (default: %(default)s)")
    ap.add_argument("--data", default=None, help="Stribeck CSV to identify from (default data/stribeck_paper_like.csv)")
    ap.add_argument("--setup-cache", default=None,
                    help="set-up JSON to load if present, else write (default: OUT/setup.json). Point it at the "
                         "setup.json of a `lugre-jax reproduce` run to share one identification across folders")
    ap.add_argument("--quick", action="store_true", help="reduced optimiser settings")
    a = ap.parse_args(argv)
    import lugre_jax

    lugre_jax.configure()  # float64 and the XLA options, before any computation
    from lugre_jax.io import write_json
    from lugre_jax.reproduce import SCENARIOS, build_setup, excitation_design, save_traces_npz, seed_study, table2

    out = Path(a.out)
    cache = Path(a.setup_cache) if a.setup_cache else out / "setup.json"
    setup = build_setup(a.data, quick=a.quick, cache=cache)
    if name in SCENARIOS:
        r = SCENARIOS[name](setup)
        write_json(out / f"{name}.json", dict(metrics=r["metrics"], settings=r["settings"], setup=setup.as_dict()))
        if r["traces"]:
            save_traces_npz(r, out / f"{name}_traces.npz")
        print(json.dumps(r["metrics"], indent=1, default=float)[:4000])
    elif name in ("table2", "design"):
        r = (table2 if name == "table2" else excitation_design)(setup, quick=a.quick)
        write_json(out / f"{name}.json", r)
        print(json.dumps({k: v for k, v in r.items() if k not in ("grid",)}, indent=1, default=str)[:4000])
    elif name == "seeds":
        r = seed_study(setup, a.data)
        write_json(out / "seeds.json", r)
        print(r)
    else:
        raise ValueError(f"unknown experiment {name!r}")
    print(f"wrote {out}")


def identification_parser(doc: str, script: str, method: str, seeds: int, refine: bool = False,
                          data: bool = True) -> argparse.ArgumentParser:
    """The options of the static-identification ``run.py`` scripts: ``--data`` (a Stribeck CSV, the
    shipped synthetic data by default; only with ``data``), ``--method``, ``--seeds``, ``--refine`` (or
    ``--no-refine`` where ``refine`` is the default; either way ``args.refine``) and ``--out`` (the
    ``results`` folder beside ``script`` by default). A script adds its own options to the parser."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    if data:
        ap.add_argument("--data", default=str(Path(__file__).resolve().parents[1] / "data" / "stribeck_paper_like.csv"))
    ap.add_argument("--method", default=method)
    ap.add_argument("--seeds", type=int, default=seeds)
    if refine:
        ap.add_argument("--no-refine", dest="refine", action="store_false")
    else:
        ap.add_argument("--refine", action="store_true")
    ap.add_argument("--out", default=str(Path(script).with_name("results")))
    return ap


#: The EMPS estimation run, in the shared data folder beside the checkout (not in the repository).
EMPS_DATA = Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "emps" / "DATA_EMPS.mat"


def emps_parser(doc: str) -> argparse.ArgumentParser:
    """The parser of a script on the EMPS data, with ``--data`` (default :data:`EMPS_DATA`)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--data", default=str(EMPS_DATA))
    return ap


def emps_present(args: argparse.Namespace) -> bool:
    """Whether ``args.data`` exists; False after one line saying there is nothing to do (the data are
    not shipped, so a checkout without them runs the script as a no-op), else True with lugre_jax
    configured (float64) for the fits."""
    if not Path(args.data).exists():
        print(f"{args.data}: EMPS data not present; nothing to do (see ../shared/data/README.md)")
        return False
    import lugre_jax

    lugre_jax.configure()
    return True


def results_for_plot(doc: str, default: Path, needs: tuple[str, ...], argv=None) -> Path:
    """The argument handling every experiment's ``plot.py`` shares; returns the results folder.

    ``--results DIR`` (``--out`` is the same option: the run scripts write to ``--out``) defaults
    to ``default``, the ``results`` folder beside the script. When a file in ``needs`` is missing
    it exits with one line naming the ``run.py`` to run first, not a traceback, before anything is
    drawn or written.
    """
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", "--out", dest="results", default=str(default),
                    help="folder with run.py's raw results (default: %(default)s)")
    a = ap.parse_args(argv)
    res = Path(a.results)
    for name in needs:
        if not (res / name).exists():
            raise SystemExit(f"{res / name} not found: run experiments/{Path(default).parent.name}/run.py "
                             "first (with --out DIR when the results are not in the default folder)")
    return res


def read_results(doc: str, default: Path, needs: tuple[str, ...], argv=None) -> tuple[Path, tuple]:
    """:func:`results_for_plot`, then every file of ``needs`` read: a ``.json`` parsed, a ``.csv`` as
    a numpy record array named by its header. Returns the folder and the contents in ``needs``' order."""
    res = results_for_plot(doc, default, needs, argv)
    import numpy as np

    def read(path: Path):
        if path.suffix == ".csv":
            return np.genfromtxt(path, delimiter=",", names=True)
        return json.loads(path.read_text())

    return res, tuple(read(res / name) for name in needs)


def write_figure(fig, path: Path) -> None:
    """Save a plot.py's figure (atomically, closing it) and name the file written."""
    from lugre_jax.io import save_figure

    save_figure(fig, path)
    print(f"wrote {path}")


def plot_main(name: str, default_out: Path, argv=None) -> None:
    """``plot.py``: read the raw results of ``name`` from ``--results`` and write ``NAME.png`` there."""
    out = results_for_plot(f"plot {name} from its raw results", default_out, (f"{name}.json",), argv)
    from lugre_jax.reproduce import PLOTTERS, load_traces_npz, plot_design, plot_table2

    if name == "design":
        plot_design(json.loads((out / "design.json").read_text()), out / "excitation_design.png")
    elif name == "table2":
        plot_table2(json.loads((out / "table2.json").read_text()), out / "table2.png")
    else:
        meta = json.loads((out / f"{name}.json").read_text())
        npz = out / f"{name}_traces.npz"
        res = dict(traces=load_traces_npz(npz) if npz.exists() else {}, metrics=meta["metrics"], settings=meta["settings"])
        png = "beyond" if name == "beyond" else name
        PLOTTERS[name](res, out / f"{png}.png")
    print(f"wrote {out}")
