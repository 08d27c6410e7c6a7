"""Reproduction of the control figures and tables of Li et al., Electronics 2020, 9, 284 (sections
4.2.5, 5 and 6): set-up (plant, identified observers, gains), scenarios, report and plots."""

from ._setup import MODELS as MODELS, Setup as Setup, build_setup as build_setup, load_setup as load_setup
from ._scenarios import (
    beyond as beyond,
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
