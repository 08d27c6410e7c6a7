"""Reproduction of the control figures and tables of Li et al., Electronics 2020, 9, 284 (sections
4.2.5, 5 and 6): set-up (plant, identified observers, gains), scenarios, Table 2, excitation design,
report and plots. Entry point: :func:`run_all` (``lugre-jax reproduce``). The per-figure folders of
``experiments/`` drive one scenario each through this public API (``experiments/_common.py``)."""

from ._run import SCENARIOS as SCENARIOS, run_all as run_all, seed_study as seed_study
from ._scenarios import (
    beyond as beyond,
    creep_search as creep_search,
    drifted_plant as drifted_plant,
    fig08 as fig08,
    fig09 as fig09,
    fig10 as fig10,
    fig12 as fig12,
    fig13 as fig13,
    fig14 as fig14,
    fig15 as fig15,
    run_lanes as run_lanes,
    step_metrics as step_metrics,
)
from ._plots import (
    PLOTTERS as PLOTTERS,
    load_traces_npz as load_traces_npz,
    plot_design as plot_design,
    plot_table2 as plot_table2,
    save_traces_npz as save_traces_npz,
)
from ._report import ROWS as ROWS, build_rows as build_rows, write_report as write_report
from ._setup import MODELS as MODELS, Setup as Setup, build_setup as build_setup, load_setup as load_setup
from ._table2 import excitation_design as excitation_design, table2 as table2
